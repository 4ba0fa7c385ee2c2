"""The process that runs a sweep's cases (lieflow.sweep): one JSON case per
line on stdin, one JSON results row per line on stdout, until stdin ends.

A worker of the sweep keeps one such process and hands it its cases, so that
a case that crashes the interpreter (a fault in native code), hangs or is
killed ends this process, not the worker: the worker reports that case as a
failed row and starts a new process for the next one.

    python3 -m lieflow._sweep_child
"""
import json
import sys


def main():
    from . import sweep  # imported here: the parent only needs this file's name

    out = sys.stdout
    sys.stdout = sys.stderr  # nothing but rows on the channel
    try:
        for line in sys.stdin:
            if not line.strip():
                continue
            row = sweep.run_case(json.loads(line))
            out.write(json.dumps(row) + "\n")
            out.flush()
    except (KeyboardInterrupt, BrokenPipeError):
        return 130  # the sweep stopped: nothing to report
    return 0


if __name__ == "__main__":
    sys.exit(main())

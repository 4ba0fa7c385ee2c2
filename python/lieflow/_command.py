"""The `lieflow` command of a pip-installed lieflow: the C++ command built
with the package (lieflow/bin/lieflow), run in this process's place."""
import os
import sys


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    binary = os.path.join(here, "bin", "lieflow")
    if not os.path.exists(binary):
        sys.stderr.write("lieflow: this installation has no command (%s is missing): reinstall with pip install .\n"
                         % binary)
        return 1
    scripts = os.path.join(here, "scripts")
    if "LIEFLOW_SCRIPTS_DIR" not in os.environ and os.path.isdir(scripts):
        os.environ["LIEFLOW_SCRIPTS_DIR"] = scripts
    os.execv(binary, [binary] + sys.argv[1:])


if __name__ == "__main__":
    sys.exit(main())

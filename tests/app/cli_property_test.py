#!/usr/bin/env python3
"""Command-line property test of `lieflow`: random combinations of
subcommands, options and values (finite, huge, tiny, negative, zero, NaN, inf,
empty, text, long, unicode) must each end in exit 0, 1 or 2 within a time
bound, never by a signal; exit 1 and 2 print a message on stderr; exit 0
never prints a non-finite number on stdout or into an --out file, and
--stats prints one JSON object.

Usage: cli_property_test.py LIEFLOW [--cases N] [--seed S] [--timeout SECONDS]
Deterministic for a seed; prints each failing case as a command line and a
last line "N passed, M failed"; exits 0 only when none failed.
"""
import argparse
import json
import os
import random
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

VALUES = ["1", "0.01", "1e-3", "0.5", "3", "10", "1e308", "1e300", "1e16", "1e-300", "5e-324", "-1", "-0.01",
          "0", "nan", "NaN", "inf", "-inf", "", "abc", "1e", "0x10", " 1", "1,2", "é", "x" * 300, "100000000000000000000000"]
INTEGRATORS = ["rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "rkmk45", "cg3", "cf4", "lgvi", "splitting",
               "genalpha", "exact", "nope"]
SCENES = ["pendulum", "heavy-top", "dzhanibekov", "stiff-spring", "double-pendulum", "cardan-shaft", "gear-train",
          "hinge-pair", "spring-hinge", "chain-3", "chain-0", "chain-abc", "no-such-scene", "/dev/null", "/dev/zero"]
OPTION_KEYS = ["rho_inf", "tolerance", "max_iterations", "rtol", "atol", "cayley", "bogus"]
NON_FINITE = re.compile(r"(?<![A-Za-z_])-?(nan|inf)(?![A-Za-z_])", re.IGNORECASE)


def value(rng):
    return rng.choice(VALUES)


def maybe(rng, p=0.5):
    return rng.random() < p


def simulate_case(rng, tmp):
    args = ["simulate", rng.choice(SCENES + [os.path.join(tmp, "scene.json")])]
    if maybe(rng, 0.6):
        args += ["--integrator", rng.choice(INTEGRATORS)]
    args += ["--t-end", rng.choice(["0.05", "0.2", value(rng)]) if maybe(rng, 0.3) else "0.05"]
    if maybe(rng, 0.5):
        args += ["--dt", rng.choice(["1e-3", "0.01", value(rng)])]
    if maybe(rng, 0.3):
        args += ["--options", "%s=%s" % (rng.choice(OPTION_KEYS), value(rng))]
    for flag in ["--noise-gyro", "--noise-angle", "--noise-quat", "--seed", "--every", "--max-steps",
                 "--max-input-mb", "--max-bodies"]:
        if maybe(rng, 0.12):
            args += [flag, value(rng)]
    if maybe(rng, 0.7):
        args.append("--stats")
    if maybe(rng, 0.3):
        args += ["--out", os.path.join(tmp, "out.csv")]
    if args[1] == "/dev/zero" and "--max-input-mb" not in args:
        # The default 1 GiB read is a test of its own (SceneLimits); here it
        # would cost seconds and gigabytes per case under the sanitizers.
        args += ["--max-input-mb", "16"]
    return args


def calibrate_case(rng, tmp):
    kind = rng.choice(["hinge", "universal", "spring"])
    recording = rng.choice([os.path.join(tmp, "rec.csv"), os.path.join(tmp, "decay.csv"), "/dev/null",
                            os.path.join(tmp, "missing.csv")])
    args = ["calibrate", kind, recording]
    if kind == "spring" and maybe(rng, 0.8):
        args += ["--scene", rng.choice(["spring-hinge", "pendulum", "heavy-top"])]
    for flag in ["--stiffness-start", "--damping-start", "--max-iterations", "--max-substeps", "--max-rows",
                 "--min-samples", "--substeps", "--segments"]:
        if maybe(rng, 0.1):
            args += [flag, value(rng)]
    if maybe(rng, 0.2):
        args += ["--use", rng.choice(["gyroscopes", "orientations", "both", value(rng)])]
    return args


def other_case(rng, tmp):
    choice = rng.randrange(7)
    if choice == 5:
        args = ["view", rng.choice([os.path.join(tmp, "rec.csv"), os.path.join(tmp, "decay.csv"), "/dev/null",
                                    os.path.join(tmp, "missing.csv"), os.path.join(tmp, "scene.json")]),
                "--scene", rng.choice(["hinge-pair", "spring-hinge", "heavy-top", os.path.join(tmp, "scene.json")]),
                "--out", os.path.join(tmp, "view.html")]
        if maybe(rng, 0.3):
            args += ["--frames", value(rng)]
        return args
    if choice == 0:
        return ["study", rng.choice(SCENES[:6]), "--integrators", rng.choice(INTEGRATORS), "--dt",
                rng.choice(["0.01", value(rng)]), "--t-end", rng.choice(["0.05", value(rng)]), "--min-time", "0.001",
                "--no-plots", "--out", os.path.join(tmp, "study")]
    if choice == 1:
        return ["stability", rng.choice(["stiff-spring", "pendulum", "heavy-top"]), "--integrators",
                rng.choice(["rkmk4", "lgvi", "genalpha", "bogus"]), "--no-plots", "--out", os.path.join(tmp, "stab")]
    if choice == 2:
        return [rng.choice(["integrators", "scenes"])] + ([value(rng)] if maybe(rng, 0.3) else [])
    if choice == 3:
        return ["liegroup", "--samples", rng.choice(["100", value(rng)]), "--seconds", "0.01"]
    if choice == 4:
        return [rng.choice(["simulate", "study", "calibrate", "stability", "bogus", "--help"]), "--help"]
    return [rng.choice(["simulate", "study", "calibrate"]), "--" + rng.choice(["bogus", "dt", "out"])]


def prepare(lieflow, tmp):
    """Inputs the cases refer to: recordings and a slightly odd scene."""
    subprocess.run([lieflow, "simulate", "hinge-pair", "--every", "20", "--t-end", "1", "--noise-gyro", "0.01",
                    "--out", os.path.join(tmp, "rec.csv")], check=True, capture_output=True)
    subprocess.run([lieflow, "simulate", "spring-hinge", "--every", "10", "--t-end", "3", "--out",
                    os.path.join(tmp, "decay.csv")], check=True, capture_output=True)
    with open(os.path.join(tmp, "scene.json"), "w") as f:
        json.dump({"name": "odd", "bodies": [{"name": "b", "mass": 1e-300, "inertia": [1e300, 1e300, 1e300],
                                              "angular_velocity": [1e10, 0, 0]}], "t_end": 0.05}, f)


def check(lieflow, args, timeout, tmp):
    """Problems of one case (empty: it passed)."""
    out_file = os.path.join(tmp, "out.csv")
    if os.path.exists(out_file):
        os.remove(out_file)
    try:
        p = subprocess.run([lieflow] + args, capture_output=True, timeout=timeout, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return ["no answer within %g s" % timeout]
    problems = []
    stdout = p.stdout.decode("utf-8", "replace")
    stderr = p.stderr.decode("utf-8", "replace")
    if p.returncode < 0:
        problems.append("killed by signal %d" % -p.returncode)
    elif p.returncode not in (0, 1, 2):
        problems.append("exit status %d" % p.returncode)
    if p.returncode in (1, 2) and "lieflow" not in stderr:
        problems.append("exit %d without a lieflow message on stderr" % p.returncode)
    if p.returncode == 0:
        outputs = [stdout]
        if "--out" in args and os.path.exists(out_file):
            with open(out_file, errors="replace") as f:
                outputs.append(f.read())
        for text in outputs:
            m = NON_FINITE.search(text)
            if m:
                problems.append("non-finite number %r printed on exit 0" % m.group(0))
        if "--stats" in args and args[0] == "simulate":
            try:
                stats = json.loads(stdout.strip().splitlines()[-1])
                if stats.get("steps", 0) < 1:
                    problems.append("exit 0 with %r steps" % stats.get("steps"))
            except (ValueError, IndexError):
                problems.append("--stats did not print a JSON object")
    return problems


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("lieflow")
    parser.add_argument("--cases", type=int, default=300)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=20.0)
    a = parser.parse_args()
    rng = random.Random(a.seed)
    tmp = tempfile.mkdtemp(prefix="lieflow_cli_property_")
    try:
        prepare(a.lieflow, tmp)
        passed = failed = 0
        for _ in range(a.cases):
            kind = rng.random()
            args = (simulate_case if kind < 0.5 else calibrate_case if kind < 0.75 else other_case)(rng, tmp)
            problems = check(a.lieflow, args, a.timeout, tmp)
            if problems:
                failed += 1
                print("FAILED: %s %s\n  %s" % (a.lieflow, " ".join(shlex.quote(x) for x in args),
                                               "; ".join(problems)))
            else:
                passed += 1
        print("%d passed, %d failed" % (passed, failed))
        return 0 if failed == 0 else 1
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())

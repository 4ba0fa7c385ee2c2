#!/usr/bin/env python3
"""Writes a copy of a URDF whose link inertias all satisfy the triangle
inequality A + B >= C of their principal moments, changing only the links
that break it, by MuJoCo's own rule (MJCF compiler attribute `balanceinertia`:
"set all three diagonal elements to their average value whenever the above
condition is violated"; the average of the principal moments is trace/3, and
the balanced tensor is isotropic, so the inertial frame's rotation no longer
matters).

Why: MuJoCo refuses such an inertia unless it balances it, and lieflow uses
the file as written, so on ANYmal (front depth camera) and Talos (gripper
motor links) the two engines integrated different bodies (README.md here,
papers/robots-work-precision). Both engines read the balanced copy in the
work-precision comparison; the copy is written at run time and not kept in
the repository (the Talos files' licence forbids distributing derivatives).

    balance_inertia.py IN.urdf OUT.urdf

Prints each link it changed, its principal moments before and the average
after, to stderr.
"""
import sys
import xml.etree.ElementTree as ET

import numpy as np

# MuJoCo's test, A + B >= C - eps for every ordering (mjEPS = 1e-14 in
# MuJoCo 2.2's user_objects.cc on the principal moments).
EPS = 1e-14


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    tree = ET.parse(argv[1])
    changed = 0
    for link in tree.getroot().iter("link"):
        inertia = link.find("inertial/inertia")
        if inertia is None:
            continue
        get = lambda k: float(inertia.get(k, "0"))
        I = np.array([[get("ixx"), get("ixy"), get("ixz")],
                      [get("ixy"), get("iyy"), get("iyz")],
                      [get("ixz"), get("iyz"), get("izz")]])
        moments = np.linalg.eigvalsh(I)
        a, b, c = sorted(moments)
        if a + b >= c - EPS:
            continue
        mean = float(np.trace(I)) / 3.0
        for k in ("ixx", "iyy", "izz"):
            inertia.set(k, repr(mean))
        for k in ("ixy", "ixz", "iyz"):
            inertia.set(k, "0")
        changed += 1
        print(f"balance_inertia: {argv[1]}: link '{link.get('name')}' principal moments "
              f"{a:.6g} {b:.6g} {c:.6g} break A + B >= C: all three set to {mean:.6g}", file=sys.stderr)
    tree.write(argv[2], xml_declaration=True, encoding="utf-8")
    print(f"balance_inertia: {changed} link(s) balanced", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""The replay page in a real browser (Debian's chromium, headless).

For a built-in scene, a 6-joint URDF arm with shapes (tests/data), a public
URDF arm whose meshes are not here (example-robot-data's UR5: inertia boxes)
and MuJoCo's humanoid (when this lieflow reads MJCF): `lieflow simulate` writes
the run, `lieflow view` (and `simulate --view`) the page; then
  - the page loads without console errors or uncaught exceptions;
  - at three times the poses the page draws (read back from three.js's world
    matrices, #lieflow-state) equal the CSV's row at that time to 1e-9;
  - screenshots at t = 0 and t = end differ where the bodies moved.
Exits 77 (ctest: skipped) with the reason when chromium or three.js is missing.

usage: replay_browser_test.py LIEFLOW SOURCE_DIR WORK_DIR
"""
import csv
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

SKIP = 77
POSE_TOLERANCE = 1e-9
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--hide-scrollbars",
                  "--virtual-time-budget=5000"]
WINDOW = (900, 640)


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def run(cmd, **kw):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    if p.returncode != 0:
        raise AssertionError("%s exited %d:\n%s" % (" ".join(map(str, cmd)), p.returncode, p.stderr))
    return p


def browser(work, page, fragment, *extra):
    profile = os.path.join(work, "profile")
    cmd = [chromium()] + CHROMIUM_FLAGS + ["--user-data-dir=" + profile, "--window-size=%d,%d" % WINDOW]
    cmd += list(extra) + ["file://" + os.path.abspath(page) + fragment]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120)


def pre(dom, name):
    m = re.search(r'<pre id="%s"[^>]*>(.*?)</pre>' % name, dom, re.S)
    if not m:
        raise AssertionError("the page has no #%s" % name)
    return m.group(1).replace("&quot;", '"').replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">")


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header = rows[0]
    return header, [[float(v) for v in r] for r in rows[1:]]


def png_pixels(path):
    """RGB(A) rows of an 8-bit non-interlaced PNG (what chromium writes)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and colour in (2, 6) and interlace == 0, (depth, colour, interlace)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    channels = 4 if colour == 6 else 3
    raw, stride = zlib.decompress(idat), width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = previous[i]
            c = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        previous = line
    return width, height, channels, rows


def changed_pixels(a, b):
    wa, ha, ca, ra = png_pixels(a)
    wb, hb, cb, rb = png_pixels(b)
    assert (wa, ha) == (wb, hb), "screenshots of different sizes"
    n = 0
    for y in range(int(0.08 * ha), int(0.88 * ha)):  # the view, not the header and the controls
        for x in range(wa):
            if sum(abs(ra[y][x * ca + k] - rb[y][x * cb + k]) for k in range(3)) > 30:
                n += 1
    return n


def check_page(work, name, page, run_csv, full=True):
    """full: three times and two screenshots; else the last time alone."""
    header, rows = read_csv(run_csv)
    times = [r[0] for r in rows]
    wanted = [times[0], times[len(times) // 2], times[-1]] if full else [times[-1]]
    for t in wanted:
        p = browser(work, page, "#t=%.17g" % t, "--dump-dom")
        dom = p.stdout
        errors = pre(dom, "lieflow-errors").strip()
        assert not errors, "%s: the page reported errors: %s" % (name, errors)
        assert "Uncaught" not in p.stderr, "%s: %s" % (name, p.stderr)
        state = json.loads(pre(dom, "lieflow-state"))
        assert state["t"] <= t + 1e-12, (name, state["t"], t)
        row = rows[times.index(state["t"])]
        col = {c: i for i, c in enumerate(header)}
        assert state["bodies"], name
        for b in state["bodies"]:
            q = [row[col[b["name"] + "." + k]] for k in ("qw", "qx", "qy", "qz")]
            sign = 1.0 if sum(x * y for x, y in zip(q, b["quaternion"])) >= 0 else -1.0
            dq = max(abs(sign * x - y) for x, y in zip(q, b["quaternion"]))
            assert dq <= POSE_TOLERANCE, "%s: body %s at t = %r: quaternion off by %g" % (name, b["name"], t, dq)
            if b["name"] + ".x" in col:
                x = [row[col[b["name"] + "." + k]] for k in ("x", "y", "z")]
                dx = max(abs(u - v) for u, v in zip(x, b["position"]))
                assert dx <= POSE_TOLERANCE, "%s: body %s at t = %r: position off by %g" % (name, b["name"], t, dx)
        print("%s: t = %.6g: %d bodies drawn at the CSV's poses" % (name, state["t"], len(state["bodies"])))
    if not full:
        return
    shots = []
    for label, t in (("start", times[0]), ("end", times[-1])):
        shot = os.path.join(work, "%s-%s.png" % (name, label))
        browser(work, page, "#t=%.17g" % t, "--screenshot=" + shot)
        assert os.path.exists(shot), "%s: no screenshot" % name
        shots.append(shot)
    n = changed_pixels(*shots)
    assert n > 200, "%s: the screenshots at t = 0 and t = end differ in only %d pixels" % (name, n)
    print("%s: %d pixels differ between t = 0 and t = end" % (name, n))


def main():
    lieflow, source, work = sys.argv[1:4]
    if not chromium():
        print("skipped: no chromium (apt-get install chromium) for the replay's browser test")
        return SKIP
    three = os.environ.get("LIEFLOW_THREE_DIR", "/usr/share/javascript/three")
    if not os.path.exists(os.path.join(three, "build", "three.min.js")):
        print("skipped: no three.js at %s (apt-get install libjs-three)" % three)
        return SKIP
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    models = os.path.join(source, "tests", "data", "models")
    cases = [("double-pendulum", "double-pendulum", ["--t-end", "2", "--every", "5"]),
             ("arm6-shapes", os.path.join(models, "arm6_shapes.urdf"), ["--t-end", "1"]),
             ("ur5", os.path.join(source, "bench", "models", "robots", "ur5.urdf"), ["--ignore", "all", "--t-end", "1"])]
    humanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml"
    reads_mjcf = "libmujoco-dev: present" in run([lieflow, "import", "--help"]).stdout
    if os.path.exists(humanoid) and reads_mjcf:
        cases.append(("humanoid", humanoid, ["--ignore", "all", "--spin", "0,0,3", "--t-end", "0.6"]))
    else:
        print("humanoid: not run (this lieflow reads no MJCF, or MuJoCo's sample models are absent)")
    for name, scene, options in cases:
        run_csv = os.path.join(work, name + ".csv")
        page = os.path.join(work, name + ".html")
        model_options = ["--ignore", "all"] if "--ignore" in options else []
        spin = ["--spin", options[options.index("--spin") + 1]] if "--spin" in options else []
        run([lieflow, "simulate", scene, "--quiet", "--out", run_csv] + options)
        run([lieflow, "view", run_csv, "--scene", scene, "--out", page, "--quiet"] + model_options + spin)
        check_page(work, name, page, run_csv)
    # simulate --view writes the same page as view does from the CSV.
    direct = os.path.join(work, "direct.html")
    run([lieflow, "simulate", "double-pendulum", "--t-end", "2", "--every", "5", "--quiet", "--view", direct,
         "--out", os.path.join(work, "direct.csv")])
    check_page(work, "simulate-view", direct, os.path.join(work, "direct.csv"), full=False)
    print("all replay pages passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The layers of lieflow, read from the code: which folder includes which.

    python3 scripts/layers.py check      # exit 1 naming every include that runs up or sideways
    python3 scripts/layers.py map        # prints docs/layers.md (the map of the house) to stdout
    python3 scripts/layers.py map --check docs/layers.md   # exit 1 if the file is not what the code says
    python3 scripts/layers.py functions  # exit 1 naming every library function over 120 lines

A function over MAX_FUNCTION_LINES lines needs its reason in the comment
right above it, on a line that says "longer than 120 lines because ...".

A folder may include its own files and the folders of lower layers (LAYERS,
top to bottom the order of DESIGN.md's "Layers", lowest first). Folders on
one layer are siblings and include none of each other; so are the
sub-folders SIBLINGS names (the two formulations of dynamics/); the
programs on top (bench/, tests/, ...) may share helpers. The map is
generated, so it cannot drift from the includes: a test compares it.
"""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (layer, folders, what they hold), lowest first.
LAYERS = [
    (1, ["liegroup"], "SO(3), SE(3) and what integrators need; header-only, any scalar"),
    (2, ["integrators"], "steppers: they advance any system on a Lie group, knowing no joint or file"),
    (2, ["liegroup_measure"], "how precise and how fast liegroup/ is (`lieflow liegroup`, bench/)"),
    (3, ["model"], "what a scene is and the files it comes from: scene JSON, MJCF/URDF import"),
    (4, ["dynamics"], "equations of motion; a scene assembled into a system the steppers advance"),
    (5, ["simulation"], "running a scene: the table of steppers, the run driver, observers, invariants"),
    (6, ["peers"], "MuJoCo beside lieflow on the same model file (optional)"),
    (6, ["replay"], "a run as a self-contained HTML page"),
    (6, ["calibration"], "Ceres fits of joint axes, centres and springs to recordings"),
    (7, ["app"], "the `lieflow` command"),
    (8, ["python"], "the Python module"),
    (9, ["bench", "papers", "examples", "fuzz", "tests"], "measurements, papers, examples and tests"),
]

# The layer of the programs on top (they may share helpers among them).
TOP = 9

# Sub-folders that are siblings: neither includes the other.
SIBLINGS = [("dynamics/maximal", "dynamics/joint_space")]

# The library's folders and the command's (functions is their check).
LIBRARY = ["liegroup", "integrators", "liegroup_measure", "model", "dynamics", "simulation", "peers", "replay",
           "calibration", "app", "python"]
MAX_FUNCTION_LINES = 120
REASON = "longer than 120 lines because"

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SOURCES = (".hpp", ".cpp", ".h", ".cc")


def layer_of(path):
    """(layer, folder) of a repository path, or None outside the layers."""
    top = path.split("/", 1)[0]
    for layer, folders, _ in LAYERS:
        if top in folders:
            return layer, top
    return None


def source_files():
    skip = {".git", "build", "build-fuzz", "build-pip"}
    for dirpath, dirnames, filenames in os.walk(ROOT):
        dirnames[:] = sorted(d for d in dirnames if d not in skip and not d.startswith("build"))
        for name in sorted(filenames):
            if name.endswith(SOURCES):
                yield os.path.relpath(os.path.join(dirpath, name), ROOT)


def includes():
    """(file, included path) for every quoted include that names a repository file."""
    for path in source_files():
        with open(os.path.join(ROOT, path), encoding="utf-8", errors="replace") as f:
            text = f.read()
        for inc in INCLUDE.findall(text):
            if os.path.isfile(os.path.join(ROOT, inc)):
                yield path, inc


def sibling_clash(a, b):
    for x, y in SIBLINGS:
        for p, q in ((x, y), (y, x)):
            if a.startswith(p + "/") and b.startswith(q + "/"):
                return True
    return False


def violations():
    out = []
    for path, inc in includes():
        src, dst = layer_of(path), layer_of(inc)
        if src is None or dst is None:
            continue
        if dst[0] > src[0]:
            out.append(f"{path}: includes {inc}, a higher layer ({dst[1]}/ above {src[1]}/)")
        elif dst[0] == src[0] and dst[1] != src[1] and src[0] < TOP:
            out.append(f"{path}: includes {inc}, a sibling layer ({dst[1]}/ beside {src[1]}/)")
        elif sibling_clash(path, inc):
            out.append(f"{path}: includes {inc}, the other formulation")
    return out


def folder_key(path):
    """The folder a file is counted under on the map: top/sub for the library layers."""
    parts = path.split("/")
    if len(parts) > 2 and parts[0] in ("model", "dynamics", "peers"):
        return "/".join(parts[:2])
    return parts[0]


def map_text():
    edges = set()
    for path, inc in includes():
        src, dst = layer_of(path), layer_of(inc)
        if src is None or dst is None or src[0] >= TOP:
            continue
        a, b = folder_key(path), folder_key(inc)
        if a != b and b != "liegroup":
            edges.add((a, b))
    nodes = {n for e in edges for n in e}
    nodes |= {f for _, fs, _ in LAYERS[:-1] for f in fs if not any(n.startswith(f + "/") for n in nodes)}
    nodes = sorted(nodes, key=lambda n: (layer_of(n)[0], n))
    out = ["<!-- Generated by `python3 scripts/layers.py map` from the includes; "
           "a test checks that it is current. -->",
           "# The layers of lieflow", "",
           "Each folder includes only its own files and those of lower layers "
           "(`python3 scripts/layers.py check`; the test `Layers.IncludesRunOnlyDownwards`).", "",
           "| layer | folder | what it holds |", "|---|---|---|"]
    for layer, folders, what in LAYERS[:-1]:
        for folder in folders:
            out.append(f"| {layer} | `{folder}/` | {what} |")
    out += ["", "Who includes whom (an arrow from a folder to one it includes; every layer includes "
            "`liegroup/`, not drawn):", "", "```mermaid",
            "flowchart BT"]
    ident = {n: re.sub(r"[^A-Za-z0-9]", "_", n) for n in nodes}
    for n in nodes:
        out.append(f'  {ident[n]}["{n}/"]')
    for a, b in sorted(edges, key=lambda e: (layer_of(e[0])[0], e)):
        out.append(f"  {ident[a]} --> {ident[b]}")
    out += ["```", "",
            "A scene from file to CSV: `model/` reads it (`loadScene`, model/scene.hpp; "
            "MJCF and URDF through model/import/), `dynamics/` assembles it "
            "(maximal/multibody_scene.hpp or joint_space/articulated_scene.hpp), "
            "`simulation/` picks the stepper from its table (stepper_table_rows.hpp) "
            "and runs it, writing each observed row (simulation_observer.hpp); "
            "`app/` writes the CSV.", ""]
    return "\n".join(out)


def long_functions():
    """(path, line, name, lines) of every function in LIBRARY over MAX_FUNCTION_LINES lines
    without its reason above it; None without Universal Ctags."""
    import shutil
    import subprocess
    ctags = shutil.which("ctags")
    if not ctags:
        return None
    folders = [f for f in LIBRARY if os.path.isdir(os.path.join(ROOT, f))]
    out = subprocess.run([ctags, "-R", "--languages=C++", "--kinds-C++=f", "--fields=+ne", "-f", "-"] + folders,
                         cwd=ROOT, capture_output=True, text=True)
    if out.returncode != 0 or "Universal Ctags" not in subprocess.run(
            [ctags, "--version"], capture_output=True, text=True).stdout:
        return None
    found = []
    for row in out.stdout.splitlines():
        cells = row.split("\t")
        fields = dict(c.split(":", 1) for c in cells[3:] if ":" in c)
        if "line" not in fields or "end" not in fields:
            continue
        begin, end = int(fields["line"]), int(fields["end"])
        if end - begin + 1 <= MAX_FUNCTION_LINES:
            continue
        with open(os.path.join(ROOT, cells[1]), encoding="utf-8", errors="replace") as f:
            lines = f.read().split("\n")
        above, k = [], begin - 2
        while k >= 0 and lines[k].lstrip().startswith("//"):
            above.append(lines[k])
            k -= 1
        if not any(REASON in line for line in above):
            found.append((cells[1], begin, cells[0], end - begin + 1))
    return found


def main(argv):
    if argv[:1] == ["check"]:
        bad = violations()
        for line in bad:
            print(line)
        print(f"{len(bad)} include(s) against the layers" if bad else "every include runs downwards")
        return 1 if bad else 0
    if argv[:1] == ["map"]:
        text = map_text()
        if argv[1:2] == ["--check"]:
            with open(argv[2], encoding="utf-8") as f:
                if f.read() != text:
                    print(f"{argv[2]} is not what the code says: run python3 scripts/layers.py map > {argv[2]}")
                    return 1
            return 0
        sys.stdout.write(text)
        return 0
    if argv[:1] == ["functions"]:
        found = long_functions()
        if found is None:
            print("skipped: needs Universal Ctags (apt-get install universal-ctags)")
            return 77
        for path, line, name, count in found:
            print(f"{path}:{line}: {name} is {count} lines (over {MAX_FUNCTION_LINES}, no reason written above it)")
        print(f"{len(found)} function(s) over {MAX_FUNCTION_LINES} lines" if found
              else f"no function over {MAX_FUNCTION_LINES} lines without its reason")
        return 1 if found else 0
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

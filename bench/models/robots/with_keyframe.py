"""Writes a copy of an MJCF model with one more keyframe: the joints at rest
and their rates given, so that a model that does not move by itself (MuJoCo's
slider_crank and arm26 with their actuators left out: their hinges' axes lie
along gravity) swings from a start both engines read (`--keyframe NAME`).

    /usr/bin/python3 with_keyframe.py MODEL.xml COPY.xml NAME QVEL

QVEL: the joint rates, comma-separated, one per degree of freedom (MuJoCo's
qvel). The copy is written beside nothing else: a model that includes other
files must be copied with them. Its licence is the original's.
"""
import sys
import xml.etree.ElementTree as ET


def main(source, target, name, qvel):
    tree = ET.parse(source)
    root = tree.getroot()
    if root.tag != "mujoco":
        sys.exit(f"with_keyframe: {source}: not an MJCF model (root <{root.tag}>)")
    if root.find(".//include") is not None:
        sys.exit(f"with_keyframe: {source}: includes other files; copy them with it")
    rates = [float(v) for v in qvel.split(",")]
    keyframe = root.find("keyframe")
    if keyframe is None:
        keyframe = ET.SubElement(root, "keyframe")
    if any(k.get("name") == name for k in keyframe.findall("key")):
        sys.exit(f"with_keyframe: {source}: already has a keyframe '{name}'")
    ET.SubElement(keyframe, "key", name=name, qvel=" ".join(repr(v) for v in rates))
    tree.write(target)


if __name__ == "__main__":
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    main(*sys.argv[1:])

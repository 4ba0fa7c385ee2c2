#!/usr/bin/env python3
"""The mass, centre and inertia of a URDF link with every link welded to it
(fixed joints, recursively), from the file alone: an independent reference for
the merged bodies of `lieflow import` and of MuJoCo's `fusestatic` (which
also sees the inertias its compiler balanced).

    /usr/bin/python3 merged_inertia.py MODEL.urdf LINK

Each link's <inertial> (mass, origin xyz/rpy, inertia tensor) is carried into
LINK's frame through the fixed joints' origins (R = Rz(y) Ry(p) Rx(r), URDF's
convention) and summed about the group's centre of mass by the parallel-axis
theorem, I = sum(R_i I_i R_i^T + m_i (|d_i|^2 1 - d_i d_i^T)), d_i = c_i - c.
A link without <inertial> has no mass (URDF). Prints the group, the mass, the
centre and the inertia in LINK's frame and its principal moments.
"""
import sys
import xml.etree.ElementTree as ET

import numpy as np


def rotation(roll, pitch, yaw):
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def origin(element):
    o = element.find("origin") if element is not None else None
    if o is None:
        return np.eye(3), np.zeros(3)
    xyz = np.array([float(v) for v in o.get("xyz", "0 0 0").split()])
    return rotation(*[float(v) for v in o.get("rpy", "0 0 0").split()]), xyz


def merged(path, root):
    robot = ET.parse(path).getroot()
    links = {link.get("name"): link for link in robot.findall("link")}
    children = {}
    for joint in robot.findall("joint"):
        children.setdefault(joint.find("parent").get("link"), []).append(joint)
    group = [(root, np.eye(3), np.zeros(3))]
    for name, r, p in group:  # grows while it is walked: the welded descendants
        for joint in children.get(name, []):
            if joint.get("type") == "fixed":
                rj, pj = origin(joint)
                group.append((joint.find("child").get("link"), r @ rj, p + r @ pj))
    parts = []
    for name, r, p in group:
        inertial = links[name].find("inertial")
        if inertial is None:
            continue
        ri, pi = origin(inertial)
        t = inertial.find("inertia")
        ixy, ixz, iyz = (float(t.get(k, 0.0)) for k in ("ixy", "ixz", "iyz"))
        local = np.array([[float(t.get("ixx")), ixy, ixz], [ixy, float(t.get("iyy")), iyz],
                          [ixz, iyz, float(t.get("izz"))]])
        rw = r @ ri
        parts.append((float(inertial.find("mass").get("value")), p + r @ pi, rw @ local @ rw.T))
    mass = sum(m for m, _, _ in parts)
    centre = sum(m * c for m, c, _ in parts) / mass
    inertia = sum(i + m * ((c - centre) @ (c - centre) * np.eye(3) - np.outer(c - centre, c - centre))
                  for m, c, i in parts)
    return [g[0] for g in group], mass, centre, inertia


if __name__ == "__main__":
    names, mass, centre, inertia = merged(sys.argv[1], sys.argv[2])
    np.set_printoptions(precision=9)
    print("links:", " ".join(names))
    print("mass:", mass)
    print("centre:", centre)
    print("inertia:\n", inertia)
    print("principal moments:", np.linalg.eigvalsh(inertia))

#!/usr/bin/env python3
"""Writes the mesh files of data/meshes/ (docs/meshes.md): python3 scripts/make_meshes.py

funnel.obj  an open conical funnel (a two-sided shell): `sides` facets from a ring of radius 1 m
            at y = 1 m up to a ring of radius 4 m at y = 5 m (the spheres drain through the
            bottom ring)
floor.obj   a closed box 40 x 1 x 40 m whose top face is y = 0 (a solid)
"""
import math
import pathlib

OUT = pathlib.Path(__file__).resolve().parents[1] / "data" / "meshes"


def write_obj(name, comment, vertices, faces):
    lines = [f"# {comment}", "# written by scripts/make_meshes.py"]
    lines += [f"v {x:.6g} {y:.6g} {z:.6g}" for x, y, z in vertices]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    (OUT / name).write_text("\n".join(lines) + "\n")


def funnel(sides=16, r_low=1.0, y_low=1.0, r_high=4.0, y_high=5.0):
    vertices, faces = [], []
    for k in range(sides):
        a = 2 * math.pi * k / sides
        vertices += [(r_low * math.cos(a), y_low, r_low * math.sin(a)), (r_high * math.cos(a), y_high, r_high * math.sin(a))]
    for k in range(sides):
        n = (k + 1) % sides
        faces.append((2 * k, 2 * k + 1, 2 * n + 1, 2 * n))  # a quad, fanned into two triangles on load
    return vertices, faces


def box(lo, hi):
    vertices = [(hi[0] if k & 1 else lo[0], hi[1] if k & 2 else lo[1], hi[2] if k & 4 else lo[2]) for k in range(8)]
    faces = [(0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)]  # outward
    return vertices, faces


if __name__ == "__main__":
    OUT.mkdir(parents=True, exist_ok=True)
    write_obj("funnel.obj", "an open funnel: radius 1 m at y = 1 m to 4 m at y = 5 m, 16 sides", *funnel())
    write_obj("floor.obj", "a closed box, x and z in [-20, 20] m, y in [-1, 0] m", *box((-20, -1, -20), (20, 0, 20)))

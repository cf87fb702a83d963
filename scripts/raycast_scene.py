#!/usr/bin/env python3
"""Writes scenes/raycast/torus.ply, the mesh of the ray caster's benchmark scene
(scenes/raycast/raycast.xml): a torus tessellated into 256 x 128 quads, 65,536 triangles
(the course's bonus: 640x480, 65,000 triangles, 2 point lights). The mesh is generated, not
stored, to keep the repository small (1.2 MB as binary PLY).

    python3 scripts/raycast_scene.py
    foton bench scenes/raycast/raycast.xml --integrator raycast --spp 1 --repeat 30
"""
import math
import pathlib
import struct

MAJOR, MINOR = 256, 128  # segments around the ring and around the tube
R, r = 1.0, 0.35  # ring and tube radii


def main():
    path = pathlib.Path(__file__).resolve().parent.parent / "scenes" / "raycast" / "torus.ply"
    vertices = []
    for i in range(MAJOR):
        u = 2 * math.pi * i / MAJOR
        for j in range(MINOR):
            v = 2 * math.pi * j / MINOR
            ring = R + r * math.cos(v)
            vertices.append((ring * math.cos(u), ring * math.sin(u), r * math.sin(v)))
    index = lambda i, j: (i % MAJOR) * MINOR + (j % MINOR)
    faces = []
    for i in range(MAJOR):
        for j in range(MINOR):
            a, b, c, d = index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)
            faces += [(a, b, c), (a, c, d)]
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    with open(path, "wb") as out:
        out.write(header.encode("ascii"))
        out.write(b"".join(struct.pack("<3f", *p) for p in vertices))
        out.write(b"".join(struct.pack("<B3i", 3, *f) for f in faces))
    print(f"{path}: {len(vertices)} vertices, {len(faces)} triangles")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes the hex mesh of a quarter ring as a Gmsh .msh 4.1 ASCII file (8-node hexahedra, type 5).

The ring: mean radius R, radial thickness h, width b along z, from angle 0 (the end in the plane
y = 0) to 90 deg (the end in the plane x = 0), split into n_theta x n_r x n_z hexes. Node order is
Gmsh's (= VTK_HEXAHEDRON's): the bottom face (z low) counter-clockwise seen from +z, then the top.

    scripts/make_quarter_ring_hex.py OUT.msh [--radius R] [--thickness h] [--width b]
                                     [--n-theta N] [--n-r N] [--n-z N]

data/scenes/meshes/quarter_ring_hex.msh is made by the defaults.
"""
import argparse
import math


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--radius", type=float, default=1.0)
    p.add_argument("--thickness", type=float, default=0.1)
    p.add_argument("--width", type=float, default=0.1)
    p.add_argument("--n-theta", type=int, default=320)
    p.add_argument("--n-r", type=int, default=2)
    p.add_argument("--n-z", type=int, default=1)
    a = p.parse_args()
    nt, nr, nz = a.n_theta, a.n_r, a.n_z

    def tag(i, j, k):  # i along theta, j along r, k along z; tags from 1
        return 1 + i + (nt + 1) * (j + (nr + 1) * k)

    nodes = []
    for k in range(nz + 1):
        for j in range(nr + 1):
            for i in range(nt + 1):
                t = 0.5 * math.pi * i / nt
                r = a.radius - a.thickness / 2 + a.thickness * j / nr
                nodes.append((r * math.cos(t), r * math.sin(t), -a.width / 2 + a.width * k / nz))
    hexes = []
    for k in range(nz):
        for j in range(nr):
            for i in range(nt):
                bottom = [tag(i, j, k), tag(i, j + 1, k), tag(i + 1, j + 1, k), tag(i + 1, j, k)]
                hexes.append(bottom + [t + (nt + 1) * (nr + 1) for t in bottom])
    write_msh(a.out, nodes, hexes)


def write_msh(path, nodes, hexes):
    """Writes nodes (x, y, z) and hexes (node tags from 1, Gmsh order) as .msh 4.1 ASCII."""
    with open(path, "w") as f:
        n, e = len(nodes), len(hexes)
        f.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
        f.write(f"$Nodes\n1 {n} 1 {n}\n3 1 0 {n}\n")
        f.write("".join(f"{i + 1}\n" for i in range(n)))
        f.write("".join(f"{x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in nodes))
        f.write(f"$EndNodes\n$Elements\n1 {e} 1 {e}\n3 1 5 {e}\n")
        f.write("".join(f"{q + 1} " + " ".join(map(str, h)) + "\n" for q, h in enumerate(hexes)))
        f.write("$EndElements\n")


if __name__ == "__main__":
    main()

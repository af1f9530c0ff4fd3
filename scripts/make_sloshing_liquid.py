#!/usr/bin/env python3
"""Writes the liquid of a sloshing tank at t = 0 as a closed OBJ surface: the prism under the
surface y = H + a cos(pi x / L) over [0, L] along x and [0, W] along z, its walls and floor pushed
`margin` outside the tank so that no liquid face lies on a tank wall (the scene's domain cuts it).

    scripts/make_sloshing_liquid.py OUT.obj [--length L] [--width W] [--depth H] [--amplitude a]
                                    [--segments N] [--margin m]

data/scenes/meshes/sloshing_liquid.obj (read by data/scenes/sloshing_tank.json) is made by the
defaults: L = 0.8 m, W = 0.1 m, H = 0.3 m, a = 5 mm, 160 segments along x (the chord of the
cosine is within a (pi / 2N)^2 / 2 = 2.4e-4 a of it).
"""
import argparse
import math


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--length", type=float, default=0.8)
    p.add_argument("--width", type=float, default=0.1)
    p.add_argument("--depth", type=float, default=0.3)
    p.add_argument("--amplitude", type=float, default=0.005)
    p.add_argument("--segments", type=int, default=160)
    p.add_argument("--margin", type=float, default=0.01)
    a = p.parse_args()
    n, m = a.segments, a.margin
    xs = [-m] + [a.length * i / n for i in range(n + 1)] + [a.length + m]
    lo_y, z0, z1 = -m, -m, a.width + m
    verts = []  # per column i: bottom front, bottom back, top front, top back (indices 4i+1 .. 4i+4)
    for x in xs:
        top = a.depth + a.amplitude * math.cos(math.pi * x / a.length)
        verts += [(x, lo_y, z0), (x, lo_y, z1), (x, top, z0), (x, top, z1)]
    faces = []
    for i in range(len(xs) - 1):
        b0, b1, t0, t1 = 4 * i + 1, 4 * i + 2, 4 * i + 3, 4 * i + 4
        c0, c1, u0, u1 = b0 + 4, b1 + 4, t0 + 4, t1 + 4
        faces += [(t0, t1, u1), (t0, u1, u0)]  # top, normal +y
        faces += [(b0, c0, c1), (b0, c1, b1)]  # floor, normal -y
        faces += [(b0, t0, u0), (b0, u0, c0)]  # front z0, normal -z
        faces += [(b1, c1, u1), (b1, u1, t1)]  # back z1, normal +z
    last = 4 * (len(xs) - 1)
    faces += [(1, 2, 4), (1, 4, 3)]  # x low end, normal -x
    faces += [(last + 1, last + 3, last + 4), (last + 1, last + 4, last + 2)]  # x high end, normal +x
    with open(a.out, "w") as f:
        f.write(f"# sloshing tank liquid: L {a.length} W {a.width} H {a.depth} a {a.amplitude} m, "
                f"{n} segments, margin {m} m (scripts/make_sloshing_liquid.py)\n")
        for v in verts:
            f.write("v {:.9g} {:.9g} {:.9g}\n".format(*v))
        for t in faces:
            f.write("f {} {} {}\n".format(*t))


if __name__ == "__main__":
    main()

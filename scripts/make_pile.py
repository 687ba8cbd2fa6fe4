#!/usr/bin/env python3
"""Writes a contact pile scene as YAML: N mixed bodies (boxes, spheres, cylinders, capsules in turn, 0.5 kg,
each a little tilted) on a grid 0.3 m apart, 100 to a layer, above a 3 m square bin of 0.5 m walls on the
ground, to be dropped together: the mixed pile of bench/bullet_side_by_side.cpp as a scene for the node.

  python3 scripts/make_pile.py --bodies 1000 > /tmp/pile_1000.yaml
"""
import argparse
import math


def body(i):
    layer, cell = divmod(i, 100)
    x, y, z = -1.35 + 0.3 * (cell % 10), -1.35 + 0.3 * (cell // 10), 0.6 + 0.3 * layer
    angle = 0.05 * (i % 7)  # about the axis (1, 2, 3)/√14, as the benchmark turns them
    s = math.sin(angle / 2) / math.sqrt(14.0)
    orientation = f"[{s:.9f}, {2 * s:.9f}, {3 * s:.9f}, {math.cos(angle / 2):.9f}]"
    shape = [
        "shape: box, size: [0.2, 0.15, 0.1], collision: true",
        "shape: sphere, size: [0.08], collision: true",
        "shape: cylinder, size: [0.06, 0.16], collision: true",
        "shape: cylinder, size: [0.05, 0.2], collision: {shape: capsule, size: [0.05, 0.1]}",
    ][i % 4]
    return (f"  - {{name: p{i:04d}, mass: 0.5, {shape}, "
            f"initial: {{position: [{x:.3f}, {y:.3f}, {z:.3f}], orientation: {orientation}}}}}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bodies", type=int, default=1000, help="number of bodies")
    parser.add_argument("--integrator", default="rk4")
    parser.add_argument("--rate", type=float, default=50.0, help="publish rate [Hz]")
    parser.add_argument("--dt", type=float, default=0.001, help="physics step [s]")
    args = parser.parse_args()
    print(f"# A pile of {args.bodies} mixed bodies dropped into a bin (written by scripts/make_pile.py).")
    print(f"rate: {args.rate}\ndt: {args.dt}\nintegrator: {args.integrator}\ngravity: [0.0, 0.0, -9.81]")
    print("publish: {per_body_topics: false, state: false, applied_wrench: false}")
    print("environment:")
    print("  - {type: plane, name: floor, normal: [0, 0, 1], offset: 0.0}")
    for name, centre, size in (("east", (1.55, 0, 0.25), (0.1, 3.2, 0.5)), ("west", (-1.55, 0, 0.25), (0.1, 3.2, 0.5)),
                               ("north", (0, 1.55, 0.25), (3.2, 0.1, 0.5)), ("south", (0, -1.55, 0.25), (3.2, 0.1, 0.5))):
        print(f"  - {{type: box, name: wall_{name}, size: {list(size)}, pose: {{position: {list(centre)}}}}}")
    print("bodies:")
    for i in range(args.bodies):
        print(body(i))


if __name__ == "__main__":
    main()

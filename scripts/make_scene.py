#!/usr/bin/env python3
"""Writes a swarm scene (a ~bodies list) as YAML: N bodies on a square grid 1 m apart, zero g.

Bodies cycle through box, sphere and cylinder. The first --with-input of them take wrench commands
(NAME/wrench); the rest drift and spin slowly with no input and no subscriber. --first numbers the bodies
from an offset, so that the scene files of several nodes have disjoint body names and frames:

  python3 scripts/make_scene.py --bodies 64 --with-input 32 > config/swarm.yaml
  python3 scripts/make_scene.py --bodies 500 --first 500 > /tmp/swarm_b.yaml   # the second half of 1000
  python3 scripts/make_scene.py --bodies 10000 --scene-wide > /tmp/big.yaml      # bodies/odom, bodies/wrench
"""
import argparse
import math

SHAPES = ["shape: box, size: [0.4, 0.2, 0.1]", "shape: sphere, size: [0.15]", "shape: cylinder, size: [0.1, 0.4]"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bodies", type=int, default=64, help="number of bodies")
    parser.add_argument("--first", type=int, default=0, help="index of the first body (names swarm_<index>)")
    parser.add_argument("--with-input", type=int, default=None, help="bodies that take wrenches (default: half)")
    parser.add_argument("--integrator", default="rk4")
    parser.add_argument("--rate", type=float, default=100.0, help="publish rate [Hz]")
    parser.add_argument("--dt", type=float, default=0.001, help="physics step [s]")
    parser.add_argument("--publish", default="tf,odom", help="outputs to enable, of tf,odom,state,applied_wrench")
    parser.add_argument("--scene-wide", action="store_true",
                        help="no per-body topics: bodies/odom and bodies/wrench for the whole scene")
    args = parser.parse_args()
    with_input = args.bodies // 2 if args.with_input is None else args.with_input
    enabled = set(args.publish.split(",")) if args.publish else set()
    side = max(1, math.ceil(math.sqrt(args.first + args.bodies)))
    width = max(2, len(str(args.first + args.bodies - 1)))
    publish = ", ".join(f"{o}: {'true' if o in enabled else 'false'}" for o in ("tf", "odom", "state", "applied_wrench"))
    if args.scene_wide:
        publish += ", per_body_topics: false"
    print(f"# A swarm of {args.bodies} bodies (written by scripts/make_scene.py; see docs/scenes.md).")
    print(f"# The first {with_input} take wrench commands (swarm_NN/wrench); the rest drift with no input.")
    print(f"rate: {args.rate}\ndt: {args.dt}\nintegrator: {args.integrator}\nworld_frame: world")
    print("gravity: [0.0, 0.0, 0.0]")
    print(f"publish: {{{publish}}}")
    print("bodies:")
    for k in range(args.bodies):
        i = args.first + k
        x, y = i % side, i // side
        item = f"  - {{name: swarm_{i:0{width}d}, mass: 1.0, {SHAPES[i % 3]}, initial: {{position: [{x}.0, {y}.0, 0.0]"
        if k >= with_input:
            item += f", linear_velocity: [0.0, 0.0, {0.01 * (k % 7):.2f}], angular_velocity: [0.0, 0.0, {0.1 * (k % 5):.1f}]"
        item += "}" + (", wrench_input: false" if k >= with_input else "") + "}"
        print(item)


if __name__ == "__main__":
    main()

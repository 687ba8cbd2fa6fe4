#!/usr/bin/env python3
"""Reads Google Benchmark JSON (integrators_benchmark, scene_benchmark) and prints tables for a reader (docs/performance.md is scripts/performance_report.sh's):
ns per step with every term and with the assembled terms, and their ratio; ns per body-step against N."""
import json
import sys


def medians(path):
    with open(path) as f:
        data = json.load(f)
    rows = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name", "median") != "median":
            continue
        name = b.get("run_name", b["name"]).replace("_median", "")
        rows[name] = b
    return rows


def main():
    steps = medians(sys.argv[1])
    print("| case | integrator | all terms [ns] | assembled [ns] | saving |")
    print("|---|---|---|---|---|")
    for name, b in steps.items():
        if not name.endswith("/all_terms"):
            continue
        base = name[: -len("/all_terms")]
        case, method = base.split("/", 1)
        assembled = steps.get(base + "/assembled")
        if not assembled:
            continue
        ratio = b["real_time"] / assembled["real_time"]
        print(f"| {case} | {method} | {b['real_time']:.0f} | {assembled['real_time']:.0f} | {ratio:.2f}× |")
    if len(sys.argv) > 2:
        scene = medians(sys.argv[2])
        print()
        print("| integrator | bodies | Scene::step: µs per tick (10 steps) | ns per body and step "
              "| World::update: ns per body and step |")
        print("|---|---|---|---|---|")
        for name, b in scene.items():
            parts = name.split("/")
            if len(parts) < 3 or parts[0] != "scene":  # e.g. general_body/<method>: no body count
                continue
            kind, method, bodies = parts[0:3]
            world = scene.get(f"world/{method}/{bodies}")
            through_world = f"{world['per_body_step'] * 1e9:.0f}" if world else "-"
            print(f"| {method} | {bodies} | {b['real_time']:.1f} | {b['per_body_step'] * 1e9:.0f} | {through_world} |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Renders docs/performance.md from one run of the benchmarks (Google Benchmark JSON) and, when given, the
node's load and lockstep measurements (their text output). Every figure on the page comes from that run; the
page says when, from which commit and on which machine. Run by scripts/performance_report.sh."""
import argparse
import os

import benchmark_table  # its medians(); this script's own directory is on sys.path


def medians(path):
    """name -> benchmark entry, the median where repetitions were aggregated; {} for a run not made."""
    if not path or not os.path.exists(path):
        return {}
    return benchmark_table.medians(path)


def ns(entry):
    """The entry's time in ns (Google Benchmark reports each benchmark in its own unit)."""
    scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[entry.get("time_unit", "ns")]
    return entry["real_time"] * scale


def fmt(value, digits=3):
    return f"{value:.{digits}g}" if value < 10 ** digits else f"{value:,.0f}".replace(",", " ")


def one_step(steps):
    lines = ["| case | integrator | all terms [ns] | assembled [ns] | saving | assembled, baseline instructions [ns] |",
             "|---|---|---|---|---|---|"]
    for name, entry in steps.items():
        if not name.endswith("/all_terms"):
            continue
        base = name[: -len("/all_terms")]
        case, method = base.split("/", 1)
        assembled = steps.get(base + "/assembled")
        if not assembled:
            continue
        baseline = steps.get(base + "/assembled/baseline_isa")
        lines.append(f"| {case} | {method} | {fmt(ns(entry))} | {fmt(ns(assembled))} | "
                     f"{ns(entry) / ns(assembled):.2f}× | {fmt(ns(baseline)) if baseline else ''} |")
    return lines


def n_bodies(scene):
    lines = ["| integrator | bodies | Scene::step: µs per tick (10 steps) | ns per body-step | "
             "World::update: ns per body-step |", "|---|---|---|---|---|"]
    for name, entry in scene.items():
        parts = name.split("/")
        if parts[0] != "scene" or len(parts) != 3:
            continue
        method, bodies = parts[1], int(parts[2])
        per_body = ns(entry) / (10 * bodies)
        world = scene.get(f"world/{method}/{bodies}")
        world_text = fmt(ns(world) / (10 * bodies)) if world else ""
        lines.append(f"| {method} | {bodies} | {fmt(ns(entry) / 1e3)} | {fmt(per_body)} | {world_text} |")
    return lines


def batched(scene):
    lines = ["| integrator | bodies | AVX, one core | AVX, 2 threads | SSE2, one core | SSE2, 2 threads |",
             "|---|---|---|---|---|---|"]
    for name, entry in scene.items():
        parts = name.split("/")
        if parts[0] != "scene" or len(parts) != 3 or int(parts[2]) < 1000:
            continue
        method, bodies = parts[1], int(parts[2])

        def cell(key):
            e = scene.get(key)
            return fmt(ns(e) / (10 * bodies)) if e else ""
        lines.append(f"| {method} | {bodies} | {cell(name)} | {cell(f'threaded/{method}/{bodies}/real_time')} | "
                     f"{cell(f'portable/{method}/{bodies}')} | {cell(f'portable_threaded/{method}/{bodies}/real_time')} |")
    general = [(n.split("/")[1], e) for n, e in scene.items() if n.startswith("general_body/")]
    if general:
        lines += ["", "One general body alone in a Scene, 10 steps a tick (what the node's loop runs for one body):",
                  "", "| integrator | ns per step |", "|---|---|"]
        lines += [f"| {method} | {fmt(ns(e) / 10)} |" for method, e in general]
    return lines


def contact(rows):
    lines = ["| scene | integrator | bodies | µs per body-step |", "|---|---|---|---|"]
    for name, entry in rows.items():
        parts = name.split("/")
        if parts[0] == "broadPhaseOnly":
            scene, method, bodies = "broad phase only (no pair touches)", "semi_implicit_euler", int(parts[1])
        else:
            scene = {"resting": "resting on the ground", "stacks": "stacks of 10",
                     "asleep": "stacks of 10, asleep",
                     "stacks2Threads": "stacks of 10, two threads"}.get(parts[0], parts[0])
            method, bodies = parts[1], int(parts[2])
        lines.append(f"| {scene} | {method} | {bodies} | {fmt(ns(entry) / (10 * bodies) / 1e3)} |")
    return lines


def anatomy(rows):
    lines = ["| measurement | ns |", "|---|---|"]
    for name, entry in rows.items():
        # Its counters are inverted rates (kIsRate | kInvert): seconds per operation or per step.
        seconds = next((entry[k] for k in ("ns_per_op", "ns_per_step") if k in entry), None)
        lines.append(f"| {name} | {fmt(seconds * 1e9 if seconds is not None else ns(entry))} |")
    return lines


def text_block(path):
    """A node script's report: its lines from its "machine:" line on (the build's output before it left out)."""
    if not path or not os.path.exists(path):
        return None
    with open(path) as f:
        lines = [line.rstrip("\n") for line in f]
    start = next((i for i, line in enumerate(lines) if line.startswith("machine:")), 0)
    return ["```"] + lines[start:] + ["```"]


def main():
    p = argparse.ArgumentParser()
    for key in ("steps", "scene", "contact", "anatomy", "bullet", "node", "lockstep", "nodelet", "spawn"):
        p.add_argument("--" + key)
    p.add_argument("--date", required=True)
    p.add_argument("--commit", required=True)
    p.add_argument("--machine", required=True)
    p.add_argument("--compiler", required=True)
    p.add_argument("--out", required=True)
    a = p.parse_args()
    page = [
        "# Performance", "",
        f"Generated by `scripts/performance_report.sh` on {a.date} from commit {a.commit}, on {a.machine} "
        f"({a.compiler}; Release, `-O3`, link-time optimisation of the core, the portable build with run-time "
        "AVX/AVX-512 dispatch). Every figure on this page is from that one run: medians of Google Benchmark "
        "repetitions, wall time. Nothing here is asserted by a test; differences under ~10 % are this VM's "
        "noise. Why the code is as it is, with the trials and their figures: [performance_log.md](performance_log.md); "
        "accuracy against cost: [the accuracy report](../report/REPORT.md).", "",
        "## One step", "",
        "`integrators_benchmark`: `Integrator::step` on one body, ns per step of 1 ms. \"all terms\" evaluates "
        "every term whatever the scene, \"assembled\" only the declared ones ([scenes.md](scenes.md)); the last "
        "column is the lane methods' one-body step in the baseline instructions (no AVX-512). Cases: `general` "
        "(full inertia tensor, spin, gravity, damping, world and body input), `isotropic` (the same on a sphere), "
        "`torque_free` (no force, spinning), `gravity_only` (falling, no spin). dopri5 answers most 1 ms "
        "requests from its continuous extension.", ""]
    page += one_step(medians(a.steps))
    scene = medians(a.scene)
    page += ["", "## N bodies", "",
             "`scene_benchmark`: a swarm (box, sphere, cylinder with spin, zero g, half of them pushed), one "
             "iteration one tick of the node's default timing (10 steps of 1 ms), stepped by `Scene::step` on one "
             "thread and through `World::update` as the node's timer runs it.", ""]
    page += n_bodies(scene)
    page += ["", "## Batched and threaded steps", "",
             "The same swarm, ns per body-step: four-body batches in AVX (the default where the CPU has it) or "
             "SSE2 (`Scene::setWideLanes(false)`), on one core or on both (`setThreads(0)`, wall time). The "
             "results are the same bits in every column (tested).", ""]
    page += batched(scene)
    page += ["", "## Contact", "",
             "`contact_benchmark`: one iteration 10 steps of 1 ms after 100 steps of settling; boxes "
             "(0.3 × 0.3 × 0.2 m) resting apart on the ground (four points each), the same boxes in stacks of "
             "10 (also on two threads: the islands' solves spread over the pool, the same bits), and spheres "
             "apart in zero g (the broad phase alone). The accuracy report's piles and "
             "SimBenchmark's scenes, with their accuracy: [REPORT.md](../report/REPORT.md).", ""]
    page += contact(medians(a.contact))
    bullet = text_block(a.bullet)
    if bullet:
        page += ["", "Beside Bullet: `bullet_side_by_side` runs the same scenes in the package and in Bullet's own "
                 "`btDiscreteDynamicsWorld` (sequential impulses, the same h, sweeps, friction and restitution, "
                 "deactivation off in both), back to back on one thread. Sag: how far a body sank or moved while "
                 "the scene settled (0.5 s, untimed); creep: how far one moved over the timed 3 s after it; deepest: "
                 "the deepest penetration seen after a step (the pile's during its drop, timed over its first 2 s).",
                 ""] + [line for line in bullet if line != "```"]
    page += ["", "## Where a lone step's time goes", "",
             "`step_anatomy`: this core's latency of one dependent double operation, and the lane kernel alone "
             "on the general body (no load or store of a `State`, no acceptance test): what `Integrator::step` "
             "costs beyond it is the call around it.", ""]
    page += anatomy(medians(a.anatomy))
    node, lockstep = text_block(a.node), text_block(a.lockstep)
    page += ["", "## The node", ""]
    if node:
        page += ["`scripts/node_load.sh` (a real roscore; swarm scenes at dt 1 ms, tf and odom at 100 Hz, half the "
                 "bodies pushed; the probe reads `/tf` and one body's `odom`):", ""] + node
    else:
        page += ["Not measured in this run (`scripts/performance_report.sh --no-node`)."]
    page += ["", "## Lockstep", ""]
    if lockstep:
        page += ["`scripts/lockstep_speed.sh` (a real roscore; swarm scenes, rk4, dt 1 ms, outputs at 100 Hz of "
                 "simulated time, `real_time_factor: 0`; once with tf and odom read, once with `/clock` only). What "
                 "bounds one body (roscpp's per-message cost): [performance_log.md](performance_log.md#lockstep).",
                 ""] + lockstep
    else:
        page += ["Not measured in this run (`scripts/performance_report.sh --no-node`)."]
    nodelet, spawn = text_block(a.nodelet), text_block(a.spawn)
    if nodelet:
        page += ["", "The simulator as a nodelet ([nodelet.md](nodelet.md)) with an in-process subscriber that reads "
                 "every odometry message of the first body (nothing dropped: the count is checked against the "
                 "stamps), tf and `/clock` published as usual: `scripts/lockstep_nodelet_speed.sh` (same scenes and "
                 "rates). What bounds it: [performance_log.md](performance_log.md#lockstep-as-a-nodelet).", ""] + nodelet
    if spawn:
        page += ["", "## Spawning", "",
                 "`scripts/spawn_speed.sh 2000` (a real roscore; a paused lockstep node; 2 000 free bodies spawned "
                 "one service call at a time over a persistent connection; the mean wall time per call for each "
                 "quarter). With per-body topics each spawn registers ten topics and services, and roscpp searches "
                 "its own registrations linearly for each (perf: `ServiceManager::isServiceAdvertised`, "
                 "`TopicManager::addSubCallback` and `advertise` lead the profile), so the cost grows with the "
                 "bodies already there; without them it stays flat (the paused lockstep driver looks at its "
                 "callbacks every millisecond, which is most of it):", ""] + spawn
    with open(a.out, "w") as f:
        f.write("\n".join(page) + "\n")


if __name__ == "__main__":
    main()

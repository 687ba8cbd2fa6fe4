#!/usr/bin/env bash
# Node load benchmark (not a test): a real roscore and the node on swarm scenes of 1 and 1000 bodies at
# 1 kHz physics (dt 1 ms) with tf + odom at 100 Hz (half the bodies take wrenches). For each: the node's CPU
# share, timer jitter and wrench-to-odometry latency, measured by bench/node_probe.cpp.
# Usage: scripts/node_load.sh [BODIES...=1 1000] (env SECONDS_PER_RUN=10, INTEGRATOR=rk4)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
prepare_node_run 11412
scene=$(mktemp --suffix=.yaml)
echo "machine: $(machine_description); integrator ${INTEGRATOR:-rk4}, dt 1 ms, rate 100 Hz"
(($# > 0)) || set -- 1 1000
for bodies in "$@"; do
  for n in $bodies; do
    write_swarm_scene "$n" "$scene"
    rosparam load "$scene" "/load_$n/rigid_body_node"
    rosrun rigid_body_sim rigid_body_node __ns:="/load_$n" >/dev/null 2>&1 &
    node=$!
    STOP_PIDS="$STOP_PIDS $node"
    sleep 3
    echo "--- $n bodies"
    "$WORKSPACE/devel/lib/rigid_body_sim/node_probe" "/load_$n/$SWARM_FIRST" "/load_$n/reset" "$node" "${SECONDS_PER_RUN:-10}" 30
    kill "$node"; wait "$node" 2>/dev/null || true
  done
done
rm -f "$scene"

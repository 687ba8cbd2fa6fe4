#!/usr/bin/env bash
# Lockstep speed benchmark (not a test): a real roscore and the node in lockstep at real_time_factor 0 (as fast
# as the CPU allows) on swarm scenes at dt 1 ms with tf + odom at 100 Hz of simulated time; a probe subscribes
# to /clock, /tf and the first body's odom and reports simulated seconds per wall second and the node's CPU.
# Each scene runs twice: with the probe reading tf and odom, and with nobody reading them (the probe on /clock only).
# Usage: scripts/lockstep_speed.sh [BODIES...=1 1000] (env SECONDS_PER_RUN=10, INTEGRATOR=rk4)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
prepare_node_run 11413
scene=$(mktemp --suffix=.yaml)
echo "machine: $(machine_description); integrator ${INTEGRATOR:-rk4}, dt 1 ms, outputs at 100 Hz"
(($# > 0)) || set -- 1 1000
for n in "$@"; do
  write_swarm_scene "$n" "$scene"
  rosparam load "$scene" "/lockstep_$n/rigid_body_node"
  rosparam set /use_sim_time true
  for outputs in all clock; do
    rosrun rigid_body_sim rigid_body_node __ns:="/lockstep_$n" _lockstep:=true _real_time_factor:=0 >/dev/null 2>&1 &
    node=$!
    STOP_PIDS="$STOP_PIDS $node"
    sleep 3
    echo -n "$n bodies, $([[ $outputs == all ]] && echo "tf + odom read" || echo "nobody reading tf or odom"): "
    "$WORKSPACE/devel/lib/rigid_body_sim/lockstep_probe" "/lockstep_$n/$SWARM_FIRST" "$node" "${SECONDS_PER_RUN:-10}" "$outputs"
    kill "$node"; wait "$node" 2>/dev/null || true
  done
done
rm -f "$scene"

#!/usr/bin/env bash
# Lockstep speed of the simulator as a nodelet (not a test): a real roscore, a nodelet manager with
# rigid_body_sim/RigidBodyNodelet in lockstep at real_time_factor 0 and rigid_body_sim/LockstepNodeletProbe,
# an in-process subscriber that reads every odometry message of the first body (tf and /clock published as
# usual). The probe reports simulated seconds per wall second from the stamps, the messages it read against
# those sent, and the manager's CPU. Swarm scenes as scripts/lockstep_speed.sh: rk4, dt 1 ms, outputs at
# 100 Hz of simulated time.
# Usage: scripts/lockstep_nodelet_speed.sh [BODIES...=1 1000] (env SECONDS_PER_RUN=10, INTEGRATOR=rk4)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
prepare_node_run 11414
scene=$(mktemp --suffix=.yaml)
result=$(mktemp)
echo "machine: $(machine_description); integrator ${INTEGRATOR:-rk4}, dt 1 ms, outputs at 100 Hz"
(($# > 0)) || set -- 1 1000
for n in "$@"; do
  write_swarm_scene "$n" "$scene"
  ns="/nodelet_$n"
  rosparam load "$scene" "$ns/rigid_body_node"
  rosparam set "$ns/rigid_body_node/lockstep" true
  rosparam set "$ns/rigid_body_node/real_time_factor" 0.0
  rosparam set "$ns/probe/seconds" "${SECONDS_PER_RUN:-10}"
  rosparam set "$ns/probe/output" "$result"
  rosparam set /use_sim_time true
  : >"$result"
  rosrun nodelet nodelet manager __ns:="$ns" __name:=manager >/dev/null 2>&1 &
  manager=$!
  STOP_PIDS="$STOP_PIDS $manager"
  rosrun nodelet nodelet load rigid_body_sim/LockstepNodeletProbe manager __ns:="$ns" __name:=probe \
    odom:="$ns/$SWARM_FIRST/odom" >/dev/null 2>&1 &
  probe=$!
  sleep 1
  rosrun nodelet nodelet load rigid_body_sim/RigidBodyNodelet manager __ns:="$ns" __name:=rigid_body_node \
    >/dev/null 2>&1 &
  sim=$!
  STOP_PIDS="$STOP_PIDS $probe $sim"
  for _ in $(seq $((${SECONDS_PER_RUN:-10} * 10 + 600))); do
    [[ -s $result ]] && break
    sleep 0.1
  done
  echo -n "$n bodies, odom read in process: "
  cat "$result" 2>/dev/null || echo "no result"
  kill "$sim" "$probe" "$manager" 2>/dev/null || true
  wait "$sim" "$probe" "$manager" 2>/dev/null || true
done
rm -f "$scene" "$result"

#!/usr/bin/env bash
# Load benchmark (not a test): a real roscore, the node on the default scene, wrenches at 10 kHz for 10 s.
# Reports the publish rate held, whether the last wrench applied is the last one sent, the node's CPU share
# and its timer overruns. Usage: scripts/load_test.sh [RATE_HZ=10000] [SECONDS=10]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
prepare_node_run 11411
rosrun rigid_body_sim rigid_body_node __ns:=load >/dev/null 2>&1 &
STOP_PIDS="$STOP_PIDS $!"
sleep 2
echo "machine: $(machine_description); node: default scene (rate 100 Hz, dt 1 ms)"
"$WORKSPACE/devel/lib/rigid_body_sim/wrench_load" /load "$(pgrep -f 'rigid_body_node __ns:=load' | head -1)" "${1:-10000}" "${2:-10}"

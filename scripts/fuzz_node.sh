#!/usr/bin/env bash
# Seeded fuzzing of the node (a robustness check, not a test): a private master, the node on the default
# scene, and scripts/fuzz_node.py sending extreme wrenches and service calls for SECONDS.
# Usage: scripts/fuzz_node.sh [SECONDS=30] [SEED=1] [RATE_HZ=500] [CONFIG=default scene]; CONFIG is a
# one-body scene file (e.g. config/falling_box.yaml, with contact). Exit code 1 if a non-finite value was
# published, a stamp went back, a service call hung or the node stopped answering.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
prepare_node_run 11511
if [ -n "${4:-}" ]; then rosparam load "$4" /fuzz/rigid_body_node; fi
rosrun rigid_body_sim rigid_body_node __ns:=fuzz __name:=rigid_body_node _rate:=100 >/tmp/rigid_body_sim_fuzz_node.log 2>&1 &
NODE=$!
STOP_PIDS="$STOP_PIDS $NODE"
sleep 2
echo "machine: $(machine_description); node: ${4:-the default scene}, rate 100 Hz"
status=0
/usr/bin/python3 "$PACKAGE_DIR/scripts/fuzz_node.py" /fuzz "${1:-30}" "${2:-1}" "${3:-500}" || status=$?
if ! kill -0 "$NODE" 2>/dev/null; then
  echo "fuzz: the node exited"; status=1
fi
echo "node log: $(wc -l < /tmp/rigid_body_sim_fuzz_node.log) lines ($(du -h /tmp/rigid_body_sim_fuzz_node.log | cut -f1))"
exit $status

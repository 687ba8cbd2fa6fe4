#!/usr/bin/env bash
# Cost of a spawn (not a test): a paused lockstep node on a private roscore, N free bodies spawned one
# service call at a time (a persistent connection), the mean wall time per call printed for each quarter of
# them, with per-body topics and services and without (publish/per_body_topics: false).
# Usage: scripts/spawn_speed.sh [BODIES=2000]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
prepare_node_run 11416
bodies="${1:-2000}"
echo "machine: $(machine_description); $bodies spawns, one call each"
for per_body in true false; do
  rosrun rigid_body_sim rigid_body_node __name:=spawner _lockstep:=true _start_paused:=true \
    _publish/per_body_topics:=$per_body >/dev/null 2>&1 &
  node=$!
  STOP_PIDS="$STOP_PIDS $node"
  echo "publish/per_body_topics: $per_body"
  /usr/bin/python3 - "$bodies" <<'PYTHON'
import sys, time
import rospy
from rigid_body_sim.srv import Spawn
rospy.init_node("spawn_speed", anonymous=True)
rospy.wait_for_service("/spawn", timeout=30.0)
spawn = rospy.ServiceProxy("/spawn", Spawn, persistent=True)
n = int(sys.argv[1])
quarter = max(1, n // 4)
start = time.monotonic()
for i in range(n):
    reply = spawn("{name: s%05d, mass: 1, initial: {position: [%d, 0, 0]}}" % (i, i))
    if not reply.success:
        sys.exit("spawn %d refused: %s" % (i, reply.message))
    if (i + 1) % quarter == 0:
        now = time.monotonic()
        print("  bodies %5d..%5d: %.2f ms per spawn" % (i + 2 - quarter, i + 1, (now - start) / quarter * 1e3))
        start = now
PYTHON
  kill "$node" 2>/dev/null || true
  wait "$node" 2>/dev/null || true
done

#!/usr/bin/env bash
# The shipped rviz view really renders, and live: starts a private master on a free port, the node on a
# scene (default: config/falling_box.yaml, with contact) and rviz with rviz/rigid_body.rviz on a free virtual
# display (Xvfb, software OpenGL), waits until the body's colour is on the screen (not a blank or black
# window), then moves the first body 0.5 m sideways (or 2 m up) with its set_state service (or resets the
# scene) and checks that its colour moved on a second capture (a frozen or stale view fails). Logs and
# captures go to a private temporary folder (the logs removed after a pass). Usage: scripts/check_view.sh
# [SCENE.yaml] [SCREENSHOT.png]; exit 1 if the view is blank or does not follow the body. Needs rviz, xvfb
# and imagemagick (installed here; not part of scripts/test.sh, being ~80 packages).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_dependencies
if ! command -v rviz >/dev/null || ! command -v Xvfb >/dev/null || ! command -v import >/dev/null; then
  apt-get install -y --no-install-recommends rviz xvfb imagemagick libgl1-mesa-dri >/dev/null
fi
build_workspace >/dev/null
source_workspace
scene="${1:-$PACKAGE_DIR/config/falling_box.yaml}"
work=$(mktemp -d /tmp/rigid_body_sim_view.XXXXXX)
shot="${2:-$work/view.png}"

# A TCP port nobody listens on, and a display number without an X server (no lock file, no socket).
free_port() {
  /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])'
}
free_display() {
  local n
  for n in $(seq 77 199); do
    [[ -e /tmp/.X$n-lock || -e /tmp/.X11-unix/X$n ]] || { echo "$n"; return; }
  done
  echo "check_view: no free X display in :77-:199" >&2
  exit 1
}
start_private_master "$(free_port)"
display=$(free_display)
export DISPLAY=":$display" LIBGL_ALWAYS_SOFTWARE=1
Xvfb "$DISPLAY" -screen 0 1280x800x24 >"$work/xvfb.log" 2>&1 &
STOP_PIDS="$STOP_PIDS $!"
sleep 1
rosparam load "$scene" /rigid_body_node
rosrun rigid_body_sim rigid_body_node >"$work/node.log" 2>&1 &
STOP_PIDS="$STOP_PIDS $!"
rosrun rviz rviz -d "$PACKAGE_DIR/rviz/rigid_body.rviz" >"$work/rviz.log" 2>&1 &
STOP_PIDS="$STOP_PIDS $!"

# The first body's colour (markers.cpp: 0.90, 0.45, 0.10) shaded by rviz's light: orange pixels, red well
# above blue. Prints their count and their mean column and row ("0 0 0" if none).
body_pixels() {
  convert "$1" -fx '(r > 0.35 && r > 1.6*b + 0.1 && g > 0.6*b && r > g) ? 1 : 0' txt:- |
    awk -F'[,: ]+' '/#FFFFFF|white/ { x += $1; y += $2; n++ }
                    END { if (n) printf "%d %.1f %.1f\n", n, x / n, y / n; else print "0 0 0" }'
}
on_screen() { (($(cut -d' ' -f1 <<<"$1") >= 200)); }
for _ in $(seq 60); do
  sleep 1
  import -window root "$shot"
  before=$(body_pixels "$shot")
  on_screen "$before" && break
done
echo "view: $shot, $(cut -d' ' -f1 <<<"$before") pixels of the body's colour"
on_screen "$before" || { echo "view: the body is not on the screen (logs: $work)"; exit 1; }

# Move the first body (its set_state: /set_state for one body, /NAME/set_state in a scene) to a free place
# (set_state refuses an overlap): 0.5 m along x or y, else 2 m up (then captured before it falls back). A
# scene without body services (publish/body_services: false) is reset instead: its bodies back at their
# initial poses, captured at once.
wait_after=$(/usr/bin/python3 - <<'PY'
import copy
import sys
import rosgraph, rospy
from rigid_body_sim.srv import GetState, SetState
from std_srvs.srv import Empty
services = sorted(s for s, _ in rosgraph.Master("/check_view").getSystemState()[2])
names = [s for s in services if s.endswith("/set_state")]
if not names:
    rospy.ServiceProxy("/reset", Empty)()
    print(0.2)
    sys.exit(0)
name = names[0]
start = rospy.ServiceProxy(name[: -len("set_state")] + "get_state", GetState)().pose
set_state = rospy.ServiceProxy(name, SetState)
for dx, dy, dz, wait in ((0.5, 0, 0, 3), (-0.5, 0, 0, 3), (0, 0.5, 0, 3), (0, -0.5, 0, 3), (0, 0, 2.0, 0.2)):
    pose = copy.deepcopy(start)
    pose.position.x += dx
    pose.position.y += dy
    pose.position.z += dz
    reply = set_state(pose=pose, twist_frame="world")
    if reply.success:
        print(wait)
        sys.exit(0)
    print("check_view: set_state refused: " + reply.message, file=sys.stderr)
sys.exit("check_view: the first body has no free place to move to")
PY
)
sleep "$wait_after"
moved="$work/moved.png"
import -window root "$moved"
after=$(body_pixels "$moved")
echo "view: the body's colour centred at ($(cut -d' ' -f2- <<<"$before")) px, after moving it at" \
  "($(cut -d' ' -f2- <<<"$after")) px"
awk -v a="$before" -v b="$after" 'BEGIN { split(a, p, " "); split(b, q, " ");
  exit ((p[2] - q[2])^2 + (p[3] - q[3])^2 >= 25) ? 0 : 1 }' ||
  { echo "view: the body did not move on the screen (logs: $work)"; exit 1; }
rm -f "$work"/*.log

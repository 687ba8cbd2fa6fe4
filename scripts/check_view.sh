#!/usr/bin/env bash
# The shipped rviz view really renders: starts a private master, the node on a scene (default:
# config/falling_box.yaml, with contact) and rviz with rviz/rigid_body.rviz on a virtual display (Xvfb,
# software OpenGL), waits, captures the screen, and checks that the body's colour is on it (not a blank or
# black window). Usage: scripts/check_view.sh [SCENE.yaml] [SCREENSHOT.png]; exit 1 if the view is blank.
# Needs rviz, xvfb and imagemagick (installed here; not part of scripts/test.sh, being ~80 packages).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_dependencies
if ! command -v rviz >/dev/null || ! command -v Xvfb >/dev/null || ! command -v import >/dev/null; then
  apt-get install -y --no-install-recommends rviz xvfb imagemagick libgl1-mesa-dri >/dev/null
fi
build_workspace >/dev/null
source_workspace
scene="${1:-$PACKAGE_DIR/config/falling_box.yaml}"
shot="${2:-/tmp/rigid_body_sim_view.png}"
start_private_master 11611
export DISPLAY=:77 LIBGL_ALWAYS_SOFTWARE=1
Xvfb :77 -screen 0 1280x800x24 >/dev/null 2>&1 &
STOP_PIDS="$STOP_PIDS $!"
sleep 1
rosparam load "$scene" /rigid_body_node
rosrun rigid_body_sim rigid_body_node >/tmp/rigid_body_sim_view_node.log 2>&1 &
STOP_PIDS="$STOP_PIDS $!"
rosrun rviz rviz -d "$PACKAGE_DIR/rviz/rigid_body.rviz" >/tmp/rigid_body_sim_view_rviz.log 2>&1 &
STOP_PIDS="$STOP_PIDS $!"
sleep 15
import -window root "$shot"
# The first body's colour (markers.cpp: 0.90, 0.45, 0.10) shaded by rviz's light: orange pixels, red well above
# blue, anywhere on the screen.
orange=$(convert "$shot" -fx '(r > 0.35 && r > 1.6*b + 0.1 && g > 0.6*b && r > g) ? 1 : 0' -format '%[fx:mean*w*h]' info:)
echo "view: $shot, $orange pixels of the body's colour"
awk -v n="$orange" 'BEGIN { exit (n >= 200) ? 0 : 1 }' || { echo "view: the body is not on the screen"; exit 1; }

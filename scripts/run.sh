#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: installs what is missing, builds the package in ./ws and
# launches the node on the default scene (roslaunch starts a ROS master if none runs).
# Extra arguments go to roslaunch, e.g. scripts/run.sh config:=$PWD/config/default.yaml ns:=robot1
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_dependencies
build_workspace
source_workspace
exec roslaunch rigid_body_sim rigid_body.launch "$@"

#!/usr/bin/env bash
# The install space works on its own: `catkin_make install` into a temporary prefix, then, in a shell that
# sources only that prefix, the node starts from it (rosrun), loads a shipped config through the installed
# launch file and publishes odometry. Writes the outcome as a JUnit file (one test case) into the folder
# given as $1, so that scripts/test.sh counts it with the other tests; exits non-zero when it failed.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
results="${1:?usage: install_check.sh RESULTS_FOLDER}"
prefix=$(mktemp -d /tmp/rigid_body_sim_install.XXXXXX)
log="$prefix.log"
mkdir -p "$results/install_check"

check() {
  (cd "$WORKSPACE" && catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release \
     -DCMAKE_INSTALL_PREFIX="$prefix" install) >"$log" 2>&1 || { echo "catkin_make install failed"; return 1; }
  for file in lib/rigid_body_sim/rigid_body_node lib/rigid_body_sim/accuracy_report share/rigid_body_sim/launch/rigid_body.launch \
              share/rigid_body_sim/launch/rviz.launch share/rigid_body_sim/launch/test_fixture.launch share/rigid_body_sim/config/falling_box.yaml \
              share/rigid_body_sim/rviz/rigid_body.rviz share/rigid_body_sim/meshes/l_bracket.obj \
              share/rigid_body_sim/nodelet_plugins.xml share/rigid_body_sim/launch/nodelet_lockstep.launch \
              lib/librigid_body_nodelets.so; do
    [ -e "$prefix/$file" ] || { echo "not installed: $file"; return 1; }
  done
  # A clean environment: only the system's ROS and the install space, not ./ws/devel.
  env -i HOME="$HOME" PATH=/usr/bin:/bin bash -c "
    set -e
    source '$prefix/setup.bash'
    export ROS_MASTER_URI=http://localhost:11391
    roscore -p 11391 >/dev/null 2>&1 & master=\$!
    trap 'kill \$master \$node 2>/dev/null; wait 2>/dev/null' EXIT
    sleep 3
    [ \"\$(rospack find rigid_body_sim)\" = '$prefix/share/rigid_body_sim' ] || { echo 'rospack finds another copy'; exit 1; }
    # The test kit and the messages from the install space's Python path, not the source tree.
    /usr/bin/python3 -c 'import rigid_body_sim.testing, rigid_body_sim.srv, sys; sys.exit(not rigid_body_sim.testing.__file__.startswith(\"$prefix\"))' \
      || { echo 'rigid_body_sim.testing is not importable from the install space'; exit 1; }
    roslaunch rigid_body_sim rigid_body.launch config:='$prefix/share/rigid_body_sim/config/falling_box.yaml' >/dev/null 2>&1 & node=\$!
    timeout 20 rostopic echo -n 1 /odom/header/frame_id | grep -q world
  " >>"$log" 2>&1 || { echo "the installed node published no odometry (log: $log)"; return 1; }
}

start=$(date +%s)
if message=$(check); then
  outcome='<testcase classname="install" name="InstalledNodeRunsFromTheInstallSpace" time="'$(( $(date +%s) - start ))'"/>'
  status=0
else
  outcome='<testcase classname="install" name="InstalledNodeRunsFromTheInstallSpace"><failure message="'"$message"'"/></testcase>'
  status=1
  echo "install check: $message"
fi
echo "<?xml version=\"1.0\"?><testsuite name=\"install\" tests=\"1\">$outcome</testsuite>" \
  >"$results/install_check/gtest-install_check.xml"
rm -rf "$prefix"
exit $status

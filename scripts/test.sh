#!/usr/bin/env bash
# Every test on a fresh Debian 12 machine: installs what is missing, builds the package and its tests in
# ./ws, runs the core gtests, the ROS-layer gtests and the rostests, checks the install space, and ends with
# "N passed, N failed".
# Exits non-zero when a test failed, a test binary did not report, or no test ran.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_dependencies
build_workspace
build_workspace tests
source_workspace

results="$WORKSPACE/build/test_results"
rm -rf "$results"
# run_tests runs every gtest and rostest; its own exit code does not reflect failures, the XML does.
status=0
(cd "$WORKSPACE" && catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 run_tests -j1) || status=$?
# The install space on its own (counted as one more test).
"$PACKAGE_DIR/scripts/install_check.sh" "$results" || status=$?
/usr/bin/python3 "$PACKAGE_DIR/scripts/summarize_test_results.py" "$results" || status=$?
exit $status

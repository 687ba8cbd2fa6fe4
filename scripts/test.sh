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
# run_tests runs every gtest and rostest; its own exit code does not reflect failures, the XML does. Many
# tests feed the node bad input on purpose, and its refusals (red ERROR and yellow WARN lines) are expected:
# the whole output goes to a log, the terminal gets one line per test file and, on a failure, the failed
# cases with their messages and the log's tail.
status=0
log="$WORKSPACE/build/run_tests.log"
echo "Running the tests (their whole output: $log)"
(cd "$WORKSPACE" && catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 run_tests -j1) 2>&1 | tee "$log" |
  sed -u -n 's|^-- run_tests.py: verify result ".*/test_results/\(.*\)\.xml"$|  ran \1|p' || status=$?
# The install space on its own (counted as one more test).
"$PACKAGE_DIR/scripts/install_check.sh" "$results" || status=$?
summary=0
/usr/bin/python3 "$PACKAGE_DIR/scripts/summarize_test_results.py" "$results" >"$log.summary" || summary=$?
if [ $status -ne 0 ] || [ $summary -ne 0 ]; then
  echo "--- the last 60 lines of $log ---"
  tail -n 60 "$log"
  status=1
fi
cat "$log.summary"  # its last line is "N passed, N failed"
exit $status

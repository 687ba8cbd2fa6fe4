#!/bin/bash
# Seeded fuzzing of what the node reads at start-up: its parameters (test/fuzz/fuzz_parameters.cpp) and mesh
# files (test/fuzz/fuzz_meshes.cpp). Exit 1 on any finding (an unexpected exception, a non-finite accepted
# result, a crash). With --asan, builds in a workspace of its own outside the checkout (RIGID_BODY_SIM_ASAN_WS,
# default /tmp/rigid_body_sim-asan-ws: inside it, the package's links would reach it from the normal workspace)
# with AddressSanitizer and UBSan over the whole package, so that a bad read or write stops the run with a report.
#
# Usage: scripts/fuzz_inputs.sh [--asan] [ITERATIONS] [SEED...]     (defaults: 20000 iterations, seeds 1 2 3)
set -euo pipefail
source "$(dirname "$0")/common.sh"

cmake_args=()
if [ "${1:-}" = "--asan" ]; then
  shift
  WORKSPACE="${RIGID_BODY_SIM_ASAN_WS:-/tmp/rigid_body_sim-asan-ws}"
  cmake_args=(-DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer")
  # Leaks at exit are not what this looks for (ROS's singletons hold memory until the process ends).
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
fi
iterations="${1:-20000}"
shift || true
seeds=("$@")
[ ${#seeds[@]} -eq 0 ] && seeds=(1 2 3)

build_workspace "${cmake_args[@]}" fuzz_parameters fuzz_meshes
source_workspace
bin="$WORKSPACE/devel/lib/rigid_body_sim"
status=0
for seed in "${seeds[@]}"; do
  "$bin/fuzz_parameters" "$iterations" "$seed" || status=1
  "$bin/fuzz_meshes" "$iterations" "$seed" || status=1
done
exit $status

#!/usr/bin/env bash
# Builds (Release) and runs the integrator benchmark: ns per step, median of 5 repetitions.
# Extra arguments go to Google Benchmark, e.g. --benchmark_filter=general
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_dependencies
build_workspace
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); $(g++ --version | head -1)"
echo "mass properties from meshes:"
"$WORKSPACE/devel/lib/rigid_body_sim/mesh_mass_properties_table"
echo
"$WORKSPACE/devel/lib/rigid_body_sim/integrators_benchmark" --benchmark_repetitions=5 \
  --benchmark_report_aggregates_only=true --benchmark_min_time=0.2 "$@"

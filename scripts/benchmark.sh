#!/usr/bin/env bash
# Builds (Release) and runs the benchmarks: ns per step per integrator and case (every term against the
# assembled ones, median of 5), a scene of N = 1 … 10 000 bodies (ns per body and step, median of 3) and
# contact (bodies resting, stacked, in the broad phase only); prints them in tables (scripts/performance_report.sh writes docs/performance.md).
# Extra arguments go to Google Benchmark, e.g. --benchmark_filter=general
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_dependencies
build_workspace
echo "machine: $(machine_description); $(g++ --version | head -1)"
echo "mass properties from meshes:"
"$WORKSPACE/devel/lib/rigid_body_sim/mesh_mass_properties_table"
echo
bench="$WORKSPACE/devel/lib/rigid_body_sim"
results=$(mktemp -d)
"$bench/integrators_benchmark" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2 --benchmark_out="$results/steps.json" --benchmark_out_format=json "$@"
"$bench/scene_benchmark" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2 --benchmark_out="$results/scene.json" --benchmark_out_format=json
echo
echo "contact (us per body and step, median of 3):"
"$bench/contact_benchmark" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2 2>/dev/null | awk '/_median/ {print "  " $1 "  " $NF}'
echo
echo "the core's latencies and the lone kernel without the call around it (bench/step_anatomy.cpp):"
"$bench/step_anatomy" --benchmark_min_time=0.3 2>/dev/null | awk '/^(latency|kernel)\// {print "  " $1 "  " $NF}'
echo
echo "ns per step, every term against the assembled ones (median):"
/usr/bin/python3 "$PACKAGE_DIR/scripts/benchmark_table.py" "$results/steps.json" "$results/scene.json"
rm -rf "$results"

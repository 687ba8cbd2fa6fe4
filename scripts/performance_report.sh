#!/usr/bin/env bash
# Writes docs/performance.md from one run: builds the package (Release), runs the benchmarks and, unless
# --no-node, the node's load and lockstep measurements on a real roscore, and renders their figures with the
# date, the commit and the machine (scripts/performance_report.py). Not a test: it asserts nothing.
# Takes ~20 minutes on the project's 2-core VM (~4 without the node). Extra arguments after --no-node are
# none; SECONDS_PER_RUN is passed to the node scripts.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
with_node=1
[[ "${1:-}" == "--no-node" ]] && with_node=0
install_dependencies
build_workspace
bench="$WORKSPACE/devel/lib/rigid_body_sim"
results=$(mktemp -d)
run() {  # name, binary, repetitions, extra Google Benchmark flags...
  local name=$1 binary=$2 repetitions=$3
  shift 3
  "$bench/$binary" --benchmark_repetitions="$repetitions" --benchmark_report_aggregates_only=true \
    --benchmark_out="$results/$name.json" --benchmark_out_format=json "$@" >/dev/null
}
run steps integrators_benchmark 5 --benchmark_min_time=0.2
run scene scene_benchmark 3 --benchmark_min_time=0.2
run contact contact_benchmark 3 --benchmark_min_time=0.2
run anatomy step_anatomy 1 --benchmark_min_time=0.3
"$bench/bullet_side_by_side" >"$results/bullet.txt"
node_args=()
if [[ $with_node == 1 ]]; then
  "$PACKAGE_DIR/scripts/node_load.sh" 1 1000 >"$results/node.txt"
  "$PACKAGE_DIR/scripts/lockstep_speed.sh" 1 1000 >"$results/lockstep.txt"
  "$PACKAGE_DIR/scripts/lockstep_nodelet_speed.sh" 1 1000 >"$results/nodelet.txt"
  "$PACKAGE_DIR/scripts/spawn_speed.sh" 2000 >"$results/spawn.txt"
  node_args=(--node "$results/node.txt" --lockstep "$results/lockstep.txt" --nodelet "$results/nodelet.txt"
             --spawn "$results/spawn.txt")
fi
commit=$(git -C "$PACKAGE_DIR" rev-parse --short HEAD)
# The page itself does not count: a run rewrites it before it is committed.
git -C "$PACKAGE_DIR" diff --quiet HEAD -- . ':!docs/performance.md' || commit="$commit with uncommitted changes"
/usr/bin/python3 "$PACKAGE_DIR/scripts/performance_report.py" --steps "$results/steps.json" \
  --scene "$results/scene.json" --contact "$results/contact.json" --anatomy "$results/anatomy.json" \
  --bullet "$results/bullet.txt" \
  "${node_args[@]}" --date "$(date -u +%Y-%m-%d)" --commit "$commit" --machine "$(machine_description)" \
  --compiler "$(g++ --version | head -1)" --out "$PACKAGE_DIR/docs/performance.md"
rm -rf "$results"
echo "wrote $PACKAGE_DIR/docs/performance.md"

#!/usr/bin/env bash
# Regenerates the test meshes in test/meshes (committed; run this after changing src/tools/make_test_meshes.cpp).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_dependencies
build_workspace
"$WORKSPACE/devel/lib/rigid_body_sim/make_test_meshes" "$PACKAGE_DIR/test/meshes"
printf 'not an stl' > "$PACKAGE_DIR/test/meshes/broken.stl"  # a file no parser accepts

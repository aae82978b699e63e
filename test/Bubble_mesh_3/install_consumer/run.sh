#!/usr/bin/env bash
# Installs the package from BUILD_DIR into a scratch prefix, then configures,
# builds and runs a consumer project that finds it with find_package.
#   run.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build="$1"; src="$2"; work="$3"
rm -rf "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$src" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/consumer"
test -f "$work/prefix/include/CGAL/Bubble_mesh_3/Metric_3.h"
test -x "$work/prefix/bin/bubble_mesh_3"
echo "1 passed, 0 failed"

#!/usr/bin/env bash
# Configures and builds tetfsi in Release into build/ (or $TETFSI_BUILD_DIR).
# Parallel jobs default to the number of cores, capped so that CGAL translation units
# (about 3.7 GB each) fit in memory.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${TETFSI_BUILD_DIR:-build}
jobs=${TETFSI_JOBS:-$(nproc)}
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" --parallel "$jobs"

#!/usr/bin/env bash
# Configures and builds tetfsi in Release into build/ (or $TETFSI_BUILD_DIR).
# Parallel jobs default to the number of cores, capped so that CGAL translation units
# (about 3.7 GB each) fit in memory.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${TETFSI_BUILD_DIR:-build}
if [ -z "${TETFSI_JOBS:-}" ]; then
  jobs=$(nproc)
  mem_gb=$(awk '/MemAvailable/ {print int($2 / 1048576)}' /proc/meminfo 2>/dev/null || echo 0)
  if [ "$mem_gb" -gt 0 ] && [ $((mem_gb / 4)) -lt "$jobs" ]; then jobs=$((mem_gb / 4)); fi
  [ "$jobs" -ge 1 ] || jobs=1
else
  jobs=$TETFSI_JOBS
fi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" --parallel "$jobs"

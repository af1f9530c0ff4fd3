#!/usr/bin/env bash
# Builds tetfsi and its test suite with AddressSanitizer + UndefinedBehaviorSanitizer at -O1,
# without NDEBUG (CGAL's assertions, preconditions and postconditions and the project's assert()s
# are on), into build-asan/, then runs the whole suite there. Outside CI: on 2 cores it takes
# about 35 min to build and 15 min to test (more on a shared machine: docs/reliability.md).
# CMAKE_CXX_COMPILER_LAUNCHER=ccache in the environment makes rebuilds after a fix cheap.
#
#   scripts/sanitize.sh [ctest arguments, e.g. -R MeshUpdate]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${TETFSI_ASAN_DIR:-build-asan}
jobs=${TETFSI_JOBS:-2}
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_C_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
cmake --build "$build" --parallel "$jobs"
# Open MPI (hypre's) leaks in MPI_Init: suppressed by scripts/lsan_suppressions.txt, which needs
# the full allocation stacks of fast_unwind_on_malloc=0 (Debian's libraries have no frame pointers).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:fast_unwind_on_malloc=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan_suppressions.txt}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$build" --output-on-failure -j"$jobs" "$@"

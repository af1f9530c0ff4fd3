#!/usr/bin/env bash
# Builds tetfsi and its test suite with AddressSanitizer + UndefinedBehaviorSanitizer at -O1,
# without NDEBUG (CGAL's assertions, preconditions and postconditions and the project's assert()s
# are on), into build-asan/, then runs the whole suite there. Outside CI: on 2 cores it takes
# about 35 min to build and well over an hour to test (figures: docs/reliability.md).
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
  -DCMAKE_C_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DTETFSI_TEST_TIMEOUT_SCALE=4
cmake --build "$build" --parallel "$jobs"
# Open MPI (hypre's) leaks in MPI_Init: suppressed by scripts/lsan_suppressions.txt, which needs
# the full allocation stacks of fast_unwind_on_malloc=0 (Debian's libraries have no frame pointers).
# intercept_tls_get_addr=0: GCC 12's sanitizer runtime (GCC <= 13, LLVM <= 16) takes a dynamic-TLS
# block whose address is 16 mod 4096 for a glibc <= 2.24 block with a header and records the two
# words before it as the block's range; glibc 2.25+ has no header, so a block that lands there by
# chance (a dlopened library's TLS, allocated by malloc) gets a garbage range and LeakSanitizer's
# tracer dies scanning it at exit (google/sanitizers#1322). Not recording the blocks can only add
# leak reports, never hide one. (Open MPI 4.1 has no parameter that keeps its plugins loaded.)
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:fast_unwind_on_malloc=0:intercept_tls_get_addr=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan_suppressions.txt}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$build" --output-on-failure -j"$jobs" "$@"

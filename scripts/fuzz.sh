#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (AddressSanitizer + UndefinedBehaviorSanitizer)
# into build-fuzz/ and runs each for a given time or number of executions, one after the other.
# Seed corpora: data/scenes/*.json and docs/examples for the scene loader, generated shapes
# (scripts/fuzz_seeds.py) for the surface readers; the corpora grow in build-fuzz/corpus/.
# Crashes, hangs (> 10 s per input) and inputs over 2 GB of memory are saved in build-fuzz/findings/.
#
#   scripts/fuzz.sh [--time SECONDS | --runs N] [TARGET...]     (default: --time 60, all targets)
#   targets: fuzz_scene fuzz_ply fuzz_surface fuzz_vtu
set -euo pipefail
cd "$(dirname "$0")/.."
limit=(-max_total_time=60)
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --time) limit=(-max_total_time="$2"); shift 2 ;;
    --runs) limit=(-runs="$2"); shift 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_scene fuzz_ply fuzz_surface fuzz_vtu)
command -v clang++-14 >/dev/null || { echo "needs clang-14 and libclang-rt-14-dev (apt-get install -y clang-14 libclang-rt-14-dev)"; exit 2; }
build=build-fuzz
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang-14 \
  -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_CXX_FLAGS="$flags" -DTETFSI_FUZZ=ON -DTETFSI_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" --target "${targets[@]}"
mkdir -p "$build/corpus/scene" "$build/findings"
cp data/scenes/*.json docs/examples/*.json "$build/corpus/scene/" 2>/dev/null || true
python3 scripts/fuzz_seeds.py "$build/corpus"
for t in "${targets[@]}"; do
  case "$t" in
    fuzz_scene) corpus=scene ;;
    fuzz_ply) corpus=ply ;;
    fuzz_surface) corpus=surface ;;
    fuzz_vtu) corpus=vtu ;;
    *) echo "unknown target $t"; exit 2 ;;
  esac
  echo "== $t"
  start=$(date +%s)
  # assimp 5.2 leaks memory on some malformed files (reported in docs/reliability.md): leak
  # detection is off for the target that runs it.
  leaks=1
  [ "$t" = fuzz_surface ] && leaks=0
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ASAN_OPTIONS=detect_leaks=$leaks \
    "$build/fuzz/$t" "$build/corpus/$corpus" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$build/findings/$t-" 2>&1 | tee "$build/$t.log" | grep -E "^#[0-9]+ +(DONE|pulse)|stat::|ERROR|SUMMARY" || true
  echo "$t: $(( $(date +%s) - start )) s; findings: $(ls "$build/findings" | grep -c "^$t-" || true)"
done

#!/usr/bin/env bash
# Builds the libFuzzer targets (FORESTMOD_FUZZ=ON, Clang, ASan + UBSan) in build-fuzz/ and runs
# each for N seconds (default 60), one after the other, from the seed corpus of
# testdata/forestmod/fuzz/<model|mesh> (copied into build-fuzz/corpus/, which keeps growing over
# runs). A crash, leak, undefined behaviour, timeout (> 20 s per input) or allocation beyond 2 GB
# stops a target and leaves its input in build-fuzz/findings/; the script then fails.
# Usage: scripts/fuzz.sh [seconds] [target...]   (targets: fuzz_model_load fuzz_mesh_load)
# Environment: FORESTMOD_FUZZ_BUILD_DIR (default <repo>/build-fuzz), CC / CXX (default clang).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FORESTMOD_FUZZ_BUILD_DIR:-$root/build-fuzz}
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_model_load fuzz_mesh_load)

CC=${CC:-clang} CXX=${CXX:-clang++} cmake -S "$root" -B "$build" -G Ninja \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFORESTMOD_FUZZ=ON \
  -DBUILD_TESTS=OFF -DBUILD_PERF_TESTS=OFF -DBUILD_EXAMPLES=OFF > /dev/null
cmake --build "$build" --target "${targets[@]}"

status=0
for t in "${targets[@]}"; do
  seeds=$root/testdata/forestmod/fuzz/${t#fuzz_}
  seeds=${seeds%_load}
  corpus=$build/corpus/$t
  mkdir -p "$corpus" "$build/findings/$t"
  cp -n "$seeds"/* "$corpus"/
  echo "== $t: $seconds s, corpus $corpus"
  log=$build/findings/$t/last_run.log
  if ! (cd "$build/findings/$t" && \
        LSAN_OPTIONS=suppressions=$root/cmake/lsan.supp \
        "$build/bin/$t" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 \
          -malloc_limit_mb=2048 -print_final_stats=1 "$corpus" > "$log" 2>&1); then
    status=1
    echo "$t: FINDING (see $log and the crash-*/leak-*/timeout-*/oom-* file next to it)"
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$log" | sed "s/^/$t: /" || true
  tail -n 3 "$log"
done
exit $status

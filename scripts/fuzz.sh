#!/usr/bin/env bash
# Fuzzes what clsph reads from users with libFuzzer (Debian's clang and its compiler-rt), under
# AddressSanitizer and UndefinedBehaviorSanitizer: the scene loader with --set overrides
# (fuzz/fuzz_scene.cpp) and the OBJ, STL and PLY readers with the mesh sampler (fuzz/fuzz_obj.cpp,
# fuzz_stl.cpp, fuzz_ply.cpp).
#   scripts/fuzz.sh [SECONDS]     each target for SECONDS (default 60), from the seed corpus in
#                                 fuzz/corpus/ (copied: the repository's seeds are not changed)
# Exits non-zero on the first crash, leak, sanitizer report, timeout (10 s) or an input that
# takes more than 1 GB; the input that did it is left in build-fuzz/ (crash-*, timeout-*, oom-*).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=${CLSPH_FUZZ_BUILD_DIR:-build-fuzz}
command -v clang++ >/dev/null || { echo "clsph: scripts/fuzz.sh needs clang (apt-get install clang)" >&2; exit 1; }
cmake -S fuzz -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j"$(nproc)" >/dev/null
for target in fuzz_scene fuzz_obj fuzz_stl fuzz_ply; do
  seeds=${target#fuzz_}
  work="$build/corpus-$seeds"
  mkdir -p "$work"
  cp -n fuzz/corpus/"$seeds"/* "$work"/ 2>/dev/null || true
  log="$build/$target.log"
  echo "clsph: fuzzing $target for $seconds s (log: $log)"
  set +e
  (cd "$build" && ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "./$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=1024 -malloc_limit_mb=1024 \
      -max_len=65536 -print_final_stats=1 "corpus-$seeds" >"$target.log" 2>&1)
  status=$?
  set -e
  runs=$(grep -Eo 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -Eo '[0-9]+$' || echo "?")
  cov=$(grep -Eo 'cov: [0-9]+' "$log" | tail -1 | grep -Eo '[0-9]+' || echo "?")
  echo "clsph: $target: $runs executions, coverage $cov edges, corpus $(ls "$work" | wc -l) inputs, exit $status"
  if [ $status -ne 0 ]; then
    tail -40 "$log" >&2
    echo "clsph: $target found a failure; the input is in $build/" >&2
    exit 1
  fi
done
echo "clsph: fuzzing found nothing"

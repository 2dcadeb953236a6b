#!/usr/bin/env bash
# What several slabs of one device cost, two builds against each other in one session:
#   bench/slab_cost.sh BASE_BENCH NEW_BENCH OUTDIR [DEVICES]
# Each is clsph-bench-sph (e.g. main's and a branch's); SPHERIC-2 at dp 0.006 to t = 0.05 as 2, 4 and
# 1 slabs, the two alternated, then the new one's 2 slabs traced and joined (scripts/trace_busy.py).
# DEVICES defaults to platform:nvidia. Each run's output is OUTDIR/{base,new}-N.txt. BASE_ARGS
# (environment) are further arguments of the base's runs: one build against itself with the halo
# not overlapped is BASE_ARGS=--whole-force-pass with the same binary twice. DP and UNTIL
# (environment) replace dp 0.006 and t = 0.05 (a smoke test on a CPU: DP=0.05 UNTIL=0.01).
set -u
base=$1 new=$2 out=$3 devices=${4:-platform:nvidia}
dp=${DP:-0.006} until=${UNTIL:-0.05}
read -r -a base_args <<< "${BASE_ARGS:-}"
mkdir -p "$out"
run() {  # name binary slabs [extra...]
    local name=$1 bin=$2 n=$3
    shift 3
    echo "=== $name, $n slab(s) $*"
    timeout 120 "$bin" --devices "$devices" --dp "$dp" --until "$until" --slabs "$n" "$@" > "$out/$name-$n.txt" 2>&1
    echo "rc $?"
    grep -E '\*\*[0-9.]+ ms/step\*\*|^  (balance|exchange|forces)' "$out/$name-$n.txt"
}
# Alternated, the order swapped from one slab count to the next (the first run of a build after
# another can pay for kernel compilation: pocl compiles some kernels at their first launch).
first=new
for n in 2 4 1; do
    if [ "$first" = new ]; then
        run new "$new" "$n"
        run base "$base" "$n" "${base_args[@]}"
        first=base
    else
        run base "$base" "$n" "${base_args[@]}"
        run new "$new" "$n"
        first=new
    fi
done
# The table for BENCHMARKS.md: each build's ms/step as 1, 2 and 4 slabs, and the overhead on 1 slab.
for name in new base; do
    one=$(grep -ohE '\*\*[0-9.]+ ms/step\*\*' "$out/$name-1.txt" | tr -d '*' | cut -d' ' -f1)
    line="$name:"
    for n in 1 2 4; do
        ms=$(grep -ohE '\*\*[0-9.]+ ms/step\*\*' "$out/$name-$n.txt" | tr -d '*' | cut -d' ' -f1)
        [ -n "$ms" ] || { line="$line $n slab(s) failed;"; continue; }
        line="$line $n slab(s) $ms ms/step"
        [ -n "$one" ] && [ "$n" != 1 ] && line="$line ($(awk -v a="$ms" -v b="$one" 'BEGIN { printf "%+.1f %%", 100 * (a / b - 1) }'))"
        line="$line;"
    done
    echo "$line"
done
run newtrace "$new" 2 --trace "$out/T.csv"
python3 "$(dirname "$0")/../scripts/trace_busy.py" "$out/T.csv"

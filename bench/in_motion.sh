#!/usr/bin/env bash
# The interaction pass at t = 0 and in motion, in one call (BENCHMARKS_HISTORY.md, "The interaction
# pass in motion"):
#   bench/in_motion.sh BENCH OUTDIR [DEVICES] [DP] [UNTIL]
# BENCH is clsph-bench-interaction. SPHERIC-2 (default dp 0.006) on DEVICES (default
# platform:nvidia; one device): the fine and clusters forms' pass and warp counts at t = 0, then on
# the state at UNTIL (default 0.05 s) as the run left it, with its velocities zeroed (what the pair
# terms of moving pairs cost), with each cell's particles in id order (what the order within
# cells costs), and in the pipeline's Morton order (--cell-order morton: what it gains). The
# state is kept in OUTDIR/state.ckpt, so only the first run in motion steps.
# Each run's output is OUTDIR/<name>.txt; the table rows are echoed.
set -u
bench=$1 out=$2 devices=${3:-platform:nvidia} dp=${4:-0.006} until=${5:-0.05}
mkdir -p "$out"
run() {  # name [extra...]
    local name=$1
    shift
    echo "=== $name: $*"
    timeout 300 "$bench" --devices "$devices" --dp "$dp" --forms fine clusters --reach 2 --repeats 5 --warmup 1 "$@" \
        > "$out/$name.txt" 2>&1
    echo "rc $?"
    grep -E '^SPHERIC|^per particle|^\| (fine|clusters)|^clusters of' "$out/$name.txt"
}
run at-t0
run moving --until "$until" --state "$out/state.ckpt"
run at-rest --until "$until" --state "$out/state.ckpt" --at-rest
run by-id --until "$until" --state "$out/state.ckpt" --within-cells id
run morton --until "$until" --state "$out/state.ckpt" --cell-order morton

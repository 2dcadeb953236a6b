#!/usr/bin/env bash
# What several slabs cost with the step ahead on several devices (issue 33, item 2):
#   bench/slabs_ahead.sh BENCH OUTDIR [DEVICES]
# BENCH is a Release clsph-bench-sph; SPHERIC-2 at dp 0.006 to t = 0.05 (DP, UNTIL, BUFFER:
# environment) on one GPU as 1, 2 and 4 slabs, the tables kept (run.list_buffer BUFFER, 0.05 by
# default): steps ahead of the host (the default), then --synchronous (the path before), then the
# tables sorted every step as the reference (one slab steps ahead there). Each run's output is
# OUTDIR/slabsN-{ahead,sync,sorted}.txt; the lines for BENCHMARKS.md are echoed. The cuts are
# made once by equal work (BALANCE, static by default): slabs of one GPU run their kernels side by
# side, so the times the dynamic balancer reads overlap (on 2026-12-06 it emptied two of four slabs).
set -u
bench=$1 out=$2 devices=${3:-platform:nvidia}
dp=${DP:-0.006} until=${UNTIL:-0.05} buffer=${BUFFER:-0.05} balance=${BALANCE:-static}
mkdir -p "$out"
t0=$(date +%s)
for n in 1 2 4; do
    for run in "ahead $buffer" "sync $buffer --synchronous" "sorted 0"; do
        read -r name b extra <<< "$run"
        f="$out/slabs$n-$name.txt"
        timeout 150 "$bench" --devices "$devices" --dp "$dp" --until "$until" --interaction fine --slabs "$n" --balance "$balance" \
            --list-buffer "$b" $extra > "$f" 2>&1
        echo "=== $n slab(s), $name (buffer $b): rc $? at $(( $(date +%s) - t0 )) s"
        grep -E '\*\*[0-9.]+ ms/step\*\*|cell tables built|ahead of the host|synchronous|thrown|^share|^  (balance|exchange|forces)' "$f" | head -14
    done
done

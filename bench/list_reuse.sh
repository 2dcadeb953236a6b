#!/usr/bin/env bash
# What keeping the cell tables and cluster lists over steps gives (run.list_buffer, issue 33):
#   bench/list_reuse.sh BENCH OUTDIR [DEVICES]
# BENCH is a Release clsph-bench-sph; SPHERIC-2 at dp 0.006 to t = 0.05 (DP, UNTIL: environment)
# with the fine and the clusters forms, the tables sorted every step (with the step ahead, and
# synchronous: lists kept run synchronous) against buffers of 0.05, 0.1 and 0.2 of the support.
# Then the fine form as 2 and 4 slabs of the device, sorted every step and with a buffer of 0.1
# (kept steps run no exchange: what several slabs cost then). Each run's output is
# OUTDIR/FORM-BUFFER[-sync|-slabsN].txt; the lines for BENCHMARKS.md are echoed.
set -u
bench=$1 out=$2 devices=${3:-platform:nvidia}
dp=${DP:-0.006} until=${UNTIL:-0.05}
mkdir -p "$out"
t0=$(date +%s)
for form in fine clusters; do
    for run in "0" "0 --synchronous" "0.05" "0.1" "0.2"; do
        read -r b extra <<< "$run"
        f="$out/$form-$b${extra:+-sync}.txt"
        timeout 120 "$bench" --devices "$devices" --dp "$dp" --until "$until" --interaction "$form" \
            --list-buffer "$b" $extra > "$f" 2>&1
        echo "=== $form, buffer $b $extra: rc $? at $(( $(date +%s) - t0 )) s"
        grep -E '\*\*[0-9.]+ ms/step\*\*|cell tables built|^\| (sph.forces|sph.clusters[a-z.]*|cells[a-z_.]*) ' "$f"
    done
done
for n in 2 4; do
    for b in 0 0.1; do
        f="$out/fine-$b-slabs$n.txt"
        timeout 120 "$bench" --devices "$devices" --dp "$dp" --until "$until" --interaction fine --slabs "$n" \
            --list-buffer "$b" > "$f" 2>&1
        echo "=== fine, buffer $b, $n slabs: rc $? at $(( $(date +%s) - t0 )) s"
        grep -E '\*\*[0-9.]+ ms/step\*\*|cell tables built|^  (balance|exchange|forces)' "$f"
    done
done

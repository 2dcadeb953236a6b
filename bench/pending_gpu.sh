#!/usr/bin/env bash
# What issue 33 still needs measured on a GPU, in one device call of about 8 minutes:
#   bench/pending_gpu.sh BINDIR OUTDIR [DEVICES]
# BINDIR holds Release builds of clsph-bench-sph and clsph-bench-interaction (copied beside the
# tree, e.g. build-gpu/, and carried); DEVICES defaults to platform:nvidia.
#   1. SPHERIC-2 at dp 0.006 to t = 0.05 s with cells in arrival and in Morton order, alternated
#      (what the ordering costs a GPU and whether `fine` gains from it; its kernels' first build
#      by NVIDIA's compiler);
#   2. bench/slab_cost.sh: 1, 2 and 4 slabs of the one device, the halo overlapped with the
#      interior ("new") against the whole force pass after the merge ("base"), alternated, and the
#      2 slabs' trace joined;
#   3. bench/in_motion.sh: the interaction pass at t = 0 and in motion, fine and clusters.
# Each part's output is under OUTDIR; the lines that go into BENCHMARKS.md are echoed. DP and
# UNTIL (environment) replace dp 0.006 and t = 0.05 everywhere: a smoke test of the whole script on
# a CPU is `DP=0.05 UNTIL=0.01 bench/pending_gpu.sh build/bench OUT platform:pocl`.
set -u
bin=$1 out=$2 devices=${3:-platform:nvidia}
export DP=${DP:-0.006} UNTIL=${UNTIL:-0.05}
here=$(dirname "$0")
mkdir -p "$out"
t0=$(date +%s)
for round in 1 2; do
    for order in arrival morton; do
        f="$out/sph-$order-$round.txt"
        timeout 90 "$bin/clsph-bench-sph" --devices "$devices" --dp "$DP" --until "$UNTIL" --cell-order "$order" > "$f" 2>&1
        echo "=== $order, round $round: rc $? at $(( $(date +%s) - t0 )) s"
        grep -E '\*\*[0-9.]+ ms/step\*\*|cells in|^\| (sph.forces|cells.within[a-z_.0-9]*) ' "$f"
    done
done
BASE_ARGS=--whole-force-pass bash "$here/slab_cost.sh" "$bin/clsph-bench-sph" "$bin/clsph-bench-sph" "$out/slabs" "$devices"
echo "=== slabs done at $(( $(date +%s) - t0 )) s"
bash "$here/in_motion.sh" "$bin/clsph-bench-interaction" "$out/in_motion" "$devices" "$DP" "$UNTIL"
echo "=== in motion done at $(( $(date +%s) - t0 )) s"

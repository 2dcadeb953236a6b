#!/usr/bin/env bash
# What several slabs of one device cost, two builds against each other in one session:
#   bench/slab_cost.sh BASE_BENCH NEW_BENCH OUTDIR [DEVICES]
# Each is clsph-bench-sph (e.g. main's and a branch's); SPHERIC-2 at dp 0.006 to t = 0.05 as 2, 4 and
# 1 slabs, the two alternated, then the new one's 2 slabs traced and joined (scripts/trace_busy.py).
# DEVICES defaults to platform:nvidia. Each run's output is OUTDIR/{base,new}-N.txt.
set -u
base=$1 new=$2 out=$3 devices=${4:-platform:nvidia}
mkdir -p "$out"
run() {  # name binary slabs [extra...]
    local name=$1 bin=$2 n=$3
    shift 3
    echo "=== $name, $n slab(s) $*"
    timeout 120 "$bin" --devices "$devices" --dp 0.006 --until 0.05 --slabs "$n" "$@" > "$out/$name-$n.txt" 2>&1
    echo "rc $?"
    grep -E '\*\*[0-9.]+ ms/step\*\*|^  (balance|exchange|forces)' "$out/$name-$n.txt"
}
for n in 2 4 1; do
    run new "$new" "$n"
    run base "$base" "$n"
done
run newtrace "$new" 2 --trace "$out/T.csv"
python3 "$(dirname "$0")/../scripts/trace_busy.py" "$out/T.csv"

#!/usr/bin/env bash
# SPHERIC-2 validation run: the first 0.6 s of scenes/spheric2.json with a pressure sensor P1 on the
# obstacle's face (0.82, 0.5, 0.021), facing the water (+x), sampled every step, then the event
# times against the experiment (scripts/spheric2_validation.py).
#   scripts/spheric2_validation.sh [DP] [METHOD] [OUTDIR] [clsph run options...]
# DP defaults to 0.012 (0.63 M particles; the benchmark's 0.006 is 5 M), METHOD to mdbc (or dbc).
# CLSPH (the tool) defaults to build/host/app/clsph.
set -euo pipefail
cd "$(dirname "$0")/.."
dp=${1:-0.012}
method=${2:-mdbc}
out=${3:-out/spheric2_${method}_${dp}}
shift $(( $# < 3 ? $# : 3 ))
clsph=${CLSPH:-build/host/app/clsph}
"$clsph" run scenes/spheric2.json --set physics.dp="$dp" --set boundaries.method="$method" --until 0.6 --every 0.6 \
  --set run.probe_every=1 \
  --set 'probes[8]={"name":"P1","kind":"pressure","point":[0.82,0.5,0.021],"normal":[1,0,0],"size":0.009}' \
  --out "$out" --force "$@"
python3 scripts/spheric2_validation.py "$out"

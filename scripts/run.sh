#!/usr/bin/env bash
# The README's main command: installs what is missing (scripts/deps.sh, via scripts/build.sh),
# builds clsph (Release), lists the OpenCL devices, runs scenes/dam_break.json on the default
# devices (every GPU, else every CPU device; $CLSPH_DEVICES overrides) into out/dam_break, and
# plots the surge front against the Koshizuka & Oka (1996) experiment (out/dam_break/surge_front.png).
# Extra arguments go to `clsph run` (e.g. scripts/run.sh --devices 0 --until 0.2).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
bash scripts/build.sh
build=${CLSPH_BUILD_DIR:-build}
clsph="$build/host/app/clsph"

echo
"$clsph" devices
echo

out=out/dam_break
args=(scenes/dam_break.json --out "$out" --force --csv --render --video)
# The scene as written (L/dp = 20, 17,615 particles, ~5,000 steps) takes 5 s on an NVIDIA H200 and
# about 40 s on two CPU cores through pocl (the interaction pass's CPU form; BENCHMARKS.md).
echo "+ clsph run ${args[*]} $*"
"$clsph" run "${args[@]}" "$@"

# Debian's matplotlib lives with the system python, which a pyenv or venv on PATH may hide.
python=/usr/bin/python3
[ -x "$python" ] || python=python3
"$python" scripts/plot_surge.py "$out" tests/data/dam_break_koshizuka_oka_1996.csv

pvd=$(cd "$out" && ls *.pvd | head -1)
cat <<MSG

clsph: done in $((SECONDS - start)) s. Output in $out/:
  $pvd        all frames as one time series: open it in ParaView (File > Open, Apply; colour by
                       velocity or pressure, representation Points or Point Gaussian)
  frame_*.vtu, .csv    one file per frame
  stats.csv            time, dt, particles, kinetic energy, max speed: a row per step
  probe_*.csv          the scene's pressure and water-height probes
  run.json             the resolved scene, clsph version, devices and command line
  surge_front.png      the surge front against Koshizuka & Oka (1996)
  surface.pvd          the free surface per frame (surface_*.vtp): open it in ParaView beside the frames
  render_*.png         an image of each frame, rendered by the devices (render.mp4 too, when ffmpeg is installed)
MSG

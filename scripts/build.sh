#!/usr/bin/env bash
# Configures and builds clsph (Release) into ${CLSPH_BUILD_DIR:-build}. With CLSPH_NO_WARNINGS=1
# (scripts/test.sh, hence CI) a compiler warning in what this build compiled fails it: the project
# builds free of warnings. The log is $build/build.log.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
build=${CLSPH_BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)" 2>&1 | tee "$build/build.log"
if [ "${CLSPH_NO_WARNINGS:-0}" = 1 ] && grep -q "warning:" "$build/build.log"; then
  echo "clsph: the build printed compiler warnings (the project builds free of them; CLSPH_NO_WARNINGS=0 to go on):" >&2
  grep -A3 "warning:" "$build/build.log" | head -40 >&2
  exit 1
fi

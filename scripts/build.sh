#!/usr/bin/env bash
# Configures and builds clsph (Release) into ${CLSPH_BUILD_DIR:-build}.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
build=${CLSPH_BUILD_DIR:-build}
# CLSPH_WERROR=ON (scripts/test.sh sets it): warnings are errors.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCLSPH_WERROR="${CLSPH_WERROR:-OFF}" >/dev/null
cmake --build "$build" -j"$(nproc)"

#!/usr/bin/env bash
# The host-side suites (scene, io and the CLI end to end) under AddressSanitizer and
# UndefinedBehaviorSanitizer, in build-asan/. pocl's JIT allocates memory it never frees, so leak
# detection is off (detect_leaks=0); every other report fails the run.
#   scripts/sanitize.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${CLSPH_ASAN_BUILD_DIR:-build-asan}
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCLSPH_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" -j"$(nproc)" --target clsph-cli clsph-scene-tests clsph-cli-tests >/dev/null
export POCL_DEVICES=${POCL_DEVICES:-"basic pthread"}
export RUSTICL_ENABLE=${RUSTICL_ENABLE:-llvmpipe}
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=0:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
(cd "$build" && ctest --output-on-failure --timeout 900 -R '^(scene|cli)$')
echo "clsph: the scene, io and cli suites are clean under ASan + UBSan"

#!/usr/bin/env bash
# The README's test command: installs what is missing, builds (Release), runs every test suite on
# every OpenCL device present plus two pocl CPU devices and Mesa rusticl (a second vendor), then
# installs the library and builds the example host program against the installed package.
set -euo pipefail
cd "$(dirname "$0")/.."
# --browser: also the live view in headless Chromium (scripts/browser_check.sh; needs `chromium`).
browser=0
if [ "${1:-}" = "--browser" ]; then browser=1; shift; fi
# The project builds free of warnings: a warning in what is compiled fails the test command
# (CLSPH_NO_WARNINGS=0 to go on anyway).
CLSPH_NO_WARNINGS=${CLSPH_NO_WARNINGS:-1} bash scripts/build.sh
build=${CLSPH_BUILD_DIR:-build}
export POCL_DEVICES=${POCL_DEVICES:-"basic pthread"}
export RUSTICL_ENABLE=${RUSTICL_ENABLE:-llvmpipe}
"$build/host/app/clsph" devices --devices all
(cd "$build" && ctest --output-on-failure --timeout 900)

# The library as another program sees it: install, then find_package(clsph) from examples/hello,
# with Eigen3 and nlohmann_json hidden (no public header uses them, so a host program needs neither).
prefix="$PWD/$build/install"
rm -rf "$prefix" "$build/example-hello"
cmake --install "$build" --prefix "$prefix" >/dev/null
cmake -S examples/hello -B "$build/example-hello" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=ON -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON >/dev/null
if grep -Eq "clsph_balance|clsph_warnings|Eigen|nlohmann" "$prefix"/lib*/cmake/clsph/*.cmake; then
  echo "clsph: the installed package names an internal target or a private dependency" >&2
  exit 1
fi
cmake --build "$build/example-hello" -j"$(nproc)"
"$build/example-hello/clsph-hello"

# The Python module as installed: importable with PYTHONPATH alone, and `python3 -m clsph` runs the
# installed tool.
site=$(ls -d "$prefix"/lib/python3*/site-packages 2>/dev/null | head -1)
if [ -n "$site" ]; then
  PYTHONPATH="$site" /usr/bin/python3 -c 'import clsph; print("python: clsph", clsph.__version__, "from", clsph.__file__)'
  PYTHONPATH="$site" /usr/bin/python3 -m clsph --version
fi
if [ "$browser" = 1 ]; then bash scripts/browser_check.sh "$build"; fi
# A fuzzing smoke run of each libFuzzer target (scene, OBJ, STL, PLY readers), 30 s each from the
# seed corpus (CLSPH_FUZZ_SECONDS to change it, 0 to skip); the ASan + UBSan run of the scene, io and
# cli suites with CLSPH_SANITIZE=1 (about 5 minutes more on two cores).
fuzz_seconds=${CLSPH_FUZZ_SECONDS:-30}
if [ "$fuzz_seconds" != 0 ]; then bash scripts/fuzz.sh "$fuzz_seconds"; fi
if [ "${CLSPH_SANITIZE:-0}" = 1 ]; then bash scripts/sanitize.sh; fi
echo "clsph: all tests passed"

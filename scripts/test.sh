#!/usr/bin/env bash
# The README's test command: installs what is missing, builds (Release), runs every test suite on
# every OpenCL device present plus two pocl CPU devices and Mesa rusticl (a second vendor), then
# installs the library and builds the example host program against the installed package.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build=${CLSPH_BUILD_DIR:-build}
export POCL_DEVICES=${POCL_DEVICES:-"basic pthread"}
export RUSTICL_ENABLE=${RUSTICL_ENABLE:-llvmpipe}
"$build/host/app/clsph" devices --devices all
(cd "$build" && ctest --output-on-failure --timeout 900)

# The library as another program sees it: install, then find_package(clsph) from examples/hello.
prefix="$PWD/$build/install"
cmake --install "$build" --prefix "$prefix" >/dev/null
cmake -S examples/hello -B "$build/example-hello" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build/example-hello" -j"$(nproc)"
"$build/example-hello/clsph-hello"

# The Python module as installed: importable with PYTHONPATH alone, and `python3 -m clsph` runs the
# installed tool.
site=$(ls -d "$prefix"/lib/python3*/site-packages 2>/dev/null | head -1)
if [ -n "$site" ]; then
  PYTHONPATH="$site" /usr/bin/python3 -c 'import clsph; print("python: clsph", clsph.__version__, "from", clsph.__file__)'
  PYTHONPATH="$site" /usr/bin/python3 -m clsph --version
fi
echo "clsph: all tests passed"

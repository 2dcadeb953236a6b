#!/usr/bin/env bash
# Installs the Debian packages clsph needs (as root), or prints the exact apt-get line and stops.
# Sourced by scripts/run.sh and scripts/test.sh; safe to run alone.
set -euo pipefail
CLSPH_PACKAGES=(g++ cmake make ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd
  mesa-opencl-icd libeigen3-dev doctest-dev nlohmann-json3-dev libcli11-dev
  python3-matplotlib  # scripts/plot_surge.py: the surge-front plot of scripts/run.sh
  python3-dev pybind11-dev python3-numpy python3-pytest  # the Python module (python/) and its tests
  libstb-dev          # PNG images (stb_image_write, compiled into the library: no link dependency)
  zlib1g-dev          # compressed VTU frames (clsph run --compress)
  libopenmpi-dev openmpi-bin  # MPI (CMake option CLSPH_MPI, on where found): runs across ranks (host/src/mpi/), tests/mpi/ under mpirun
  pkg-config libcpp-httplib-dev libturbojpeg0-dev  # clsph run --serve (host/app/serve/): the live view's HTTP server and JPEG frames (the tool only)
  glmark2-data        # scenes/bunny.json: the Stanford bunny mesh (/usr/share/glmark2/models/bunny.obj)
  clang libclang-rt-14-dev)  # scripts/fuzz.sh: clang, and compiler-rt for libFuzzer and the sanitizers (only recommended by clang)
missing=()
for p in "${CLSPH_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ]; then
    echo "clsph: installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q >/dev/null
    apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
  else
    echo "clsph: missing Debian packages. Install them with:" >&2
    echo "  sudo apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
fi

#!/usr/bin/env bash
# Installs every Debian 12 package camplace needs to build, test (including the clang-format
# check and the viewer's browser test) and benchmark. libtinygltf-dev writes the glTF files of
# `camplace export`, libjs-three is the three.js it copies beside the viewer page, chromium runs
# the page headless in the test labelled `browser`. openmpi-bin and libopenmpi-dev: `mpirun camplace
# study|validate` (docs/cluster.md).
# libassimp-dev reads mesh files (DAE, glTF, 3MF, ...), liburdfdom-dev robot descriptions (URDF).
# The one list of dependencies; README commands and .ci/run call this script.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libcgal-dev libssl-dev libgmp-dev libmpfr-dev libboost-dev libeigen3-dev
  libpagmo-dev libtbb-dev nlohmann-json3-dev libcli11-dev libjemalloc-dev
  libassimp-dev liburdfdom-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 gnuplot-nox clang-format clang libclang-rt-14-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  libtinygltf-dev libjs-three chromium
  openmpi-bin libopenmpi-dev
  # Embree 3, for bench/scale_bench's ray-casting yardstick only (optional: it builds without).
  libembree-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

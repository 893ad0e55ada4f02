#!/usr/bin/env bash
# The one list of camplace's Debian 12 packages, in two sections, and the script that installs
# them (apt-get, as root; packages already installed are skipped):
#   bash scripts/install_deps.sh run   what building and running `camplace` needs
#                                      (scripts/main_job.sh)
#   bash scripts/install_deps.sh       that and everything the tests, benchmarks, the Python
#                                      module and MPI need (scripts/test.sh, scripts/build.sh)
set -euo pipefail
# Section 1, building and running camplace: the compiler and CMake/Ninja; CGAL (exact kernel,
# Nef polyhedra, mesh repair) with GMP/MPFR, Boost and Eigen; pagmo and TBB (optimize);
# nlohmann-json and CLI11; OpenSSL (SHA-256 of scene files); assimp (mesh files) and urdfdom
# (URDF robots); tinygltf (the glTF files of `export`) and libjs-three (the three.js that
# `export` copies beside its viewer page and `serve` sends to its page); cpp-httplib (the HTTP
# server of `serve`); jemalloc (faster allocation in the exact pipeline); gnuplot (the plots of
# the `compare` and `study` reports).
run_packages=(
  build-essential cmake ninja-build pkg-config
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev libeigen3-dev
  libpagmo-dev libtbb-dev nlohmann-json3-dev libcli11-dev libssl-dev libjemalloc-dev
  libassimp-dev liburdfdom-dev
  libtinygltf-dev libjs-three libcpp-httplib-dev gnuplot-nox
)
# Section 2, tests, benchmarks and the optional parts: GoogleTest and Google Benchmark;
# clang-format (the format check); clang and its sanitizer runtime (the libFuzzer targets); the
# Python module (pybind11, numpy) and its tests (pytest, matplotlib); chromium (the browser tests of the viewer and of `serve`); Open MPI (`mpirun camplace
# study|validate`, docs/cluster.md); Embree 3 (bench/scale_bench's ray-casting yardstick only,
# optional: it builds without).
test_packages=(
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-format clang libclang-rt-14-dev
  python3 pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  chromium
  openmpi-bin libopenmpi-dev
  libembree-dev
)
case "${1:-all}" in
  run) packages=("${run_packages[@]}") ;;
  all) packages=("${run_packages[@]}" "${test_packages[@]}") ;;
  *)
    echo "usage: bash scripts/install_deps.sh [run|all]" >&2
    exit 2
    ;;
esac
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

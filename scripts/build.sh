#!/usr/bin/env bash
# Installs the Debian packages (scripts/install_deps.sh) and builds everything with the preset
# `release`: the tool, every test program, the benchmarks, the Python module (at most 2 parallel
# jobs: a CGAL Nef translation unit needs ~1.6 GB and ~35 s).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake --preset release
cmake --build --preset release

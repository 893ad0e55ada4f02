#!/usr/bin/env bash
# Builds everything and runs the whole test suite (ctest, all labels).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --preset release -j2 --timeout 900

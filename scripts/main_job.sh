#!/usr/bin/env bash
# Builds everything and runs the main job: optimise the camera placement of the bundled
# default scene (the paper's basic setup) and print the best configuration and its Err.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
out=out/paper_basic
build/release/app/camplace optimize data/paper_basic.json --seed 1 --time-limit 100 --out "$out"
echo "best configuration: $out/run-1.json"

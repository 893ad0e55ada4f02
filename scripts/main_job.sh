#!/usr/bin/env bash
# The main job: installs what building and running camplace needs (scripts/install_deps.sh run),
# builds the `camplace` tool alone (CMake preset `app`: no tests, benchmarks or Python module),
# optimises the camera placement of the bundled default scene (the paper's basic setup), writes
# the 3D view of the best configuration and prints where it is, with a one-line summary that
# checks the result with the exact pipeline.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh run
cmake --preset app >/dev/null
cmake --build --preset app
C=build/release/app/camplace
scene=data/paper_basic.json
out=out/paper_basic
"$C" optimize "$scene" --seed 1 --time-limit 100 --out "$out"
"$C" export "$scene" --cameras "$out/run-1.json" --out "$out/view"
echo
echo "best configuration: $out/run-1.json"
echo "3D view (cameras, their fields of view, the person, the hull): open $PWD/$out/view/index.html"
"$C" evaluate "$scene" --cameras "$out/run-1.json" --pipeline both | grep '^summary:'

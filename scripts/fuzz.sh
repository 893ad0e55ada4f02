#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz (preset `fuzz`: clang, ASan + UBSan) and runs each
# for a bounded time on its seeds (tests/fuzz/seeds/<target>, plus data/ for scenes and camera
# files, data/studies for study files): the scene loader, the mesh-file reader, the camera-file
# loader, the run-file reader and the study-file reader. A finding (crash, sanitizer report, a loader throwing anything but core::InputError,
# an input taking over 10 s) fails the script and leaves the input in build/fuzz/findings/;
# add it to tests/fuzz/regressions/ once fixed. The five targets run at the same time, each
# for SECONDS of wall-clock time (on 2 cores each gets about two fifths of a core).
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
mkdir -p build/fuzz/findings

# fuzz_TARGET on its seeds for $seconds s; its log is build/fuzz/fuzz_TARGET.log.
run_target() {
  local target=$1
  local corpus=build/fuzz/corpus/$target
  mkdir -p "$corpus"
  local seeds=(tests/fuzz/seeds/$target)
  case $target in
    scene | cameras) seeds+=(data) ;;
    study) seeds+=(data/studies) ;;
  esac
  build/fuzz/tests/fuzz/fuzz_$target "$corpus" "${seeds[@]}" -max_total_time="$seconds" \
    -timeout=10 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix=build/fuzz/findings/$target- 2>build/fuzz/fuzz_$target.log
}

targets=(scene mesh cameras runfile study)
pids=()
for target in "${targets[@]}"; do
  run_target "$target" &
  pids+=($!)
done
status=0
for i in "${!targets[@]}"; do
  target=${targets[$i]}
  echo "--- fuzz_$target: ${seconds} s"
  if ! wait "${pids[$i]}"; then
    tail -n 40 "build/fuzz/fuzz_$target.log"
    echo "fuzz_$target: FINDING (input in build/fuzz/findings/)"
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "build/fuzz/fuzz_$target.log" || true
  fi
done
exit $status

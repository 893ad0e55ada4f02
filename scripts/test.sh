#!/usr/bin/env bash
# Builds everything and runs every check of CI (.ci/run calls this script):
#   1. format       scripts/check_format.sh: every *.cpp/*.hpp as .clang-format says  (seconds)
#   2. release      Release build (scripts/build.sh) and the whole suite: ctest preset
#                   `release`, all labels including `slow`
#   3. asan         ASan + UBSan build (preset `asan`, without the test programs labelled
#                   `slow`) and the tests not labelled `slow`: ctest preset `asan`
#   4. fuzz         libFuzzer targets of tests/fuzz (preset `fuzz`, clang), 30 s each:
#                   scripts/fuzz.sh 30
# Cheapest first. A failed step does not stop the later ones (a format slip must not hide a
# test failure; a release build failure skips only the release tests); the script ends with
# the list of failed steps and exits 1 if there is one. README.md, "Tests", has the timings.
set -uo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh || exit 1

failed=()
# step NAME COMMAND...: runs COMMAND, prints its duration, records NAME if it fails.
step() {
  local name=$1
  shift
  local start=$SECONDS
  echo "=== $name"
  if "$@"; then
    echo "=== $name: passed ($((SECONDS - start)) s)"
  else
    echo "=== $name: FAILED ($((SECONDS - start)) s)"
    failed+=("$name")
    return 1
  fi
}

step "format check" bash scripts/check_format.sh
step "release build" bash scripts/build.sh && step "release tests (all)" ctest --preset release
step "asan build" bash -c 'cmake --preset asan && cmake --build --preset asan' &&
  step "asan tests (not slow)" ctest --preset asan
step "fuzz (30 s per target)" bash scripts/fuzz.sh 30

if [ ${#failed[@]} -gt 0 ]; then
  echo "=== FAILED: ${failed[*]}"
  exit 1
fi
echo "=== all checks passed"

#!/usr/bin/env bash
# Builds everything and runs every check of CI (.ci/run calls this script). Every test runs
# once, and nothing is compiled twice in one configuration:
#   1. format       scripts/check_format.sh: every *.cpp/*.hpp as .clang-format says  (seconds)
#   2. release      Release build of the camplace tool, the benchmarks, the Python module and
#                   the test programs that run the binary or are labelled slow
#                   (CAMPLACE_TESTS=binary-or-slow), and those tests: ctest preset `release`
#                   (with the Python, browser and MPI tests)
#   3. asan         ASan + UBSan build (preset `asan`: the test programs that link only the
#                   modules they test, CAMPLACE_TESTS=library, and those modules; expensive
#                   checks on) and those tests: ctest preset `asan`
#   4. fuzz         libFuzzer targets of tests/fuzz (preset `fuzz`, clang), 30 s each:
#                   scripts/fuzz.sh 30
# Cheapest first. A failed step does not stop the later ones (a format slip must not hide a
# test failure; a release build failure skips only the release tests); the script ends with
# the list of failed steps and exits 1 if there is one. docs/development.md has the timings.
set -uo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
bash scripts/install_deps.sh || exit 1
echo "=== packages installed ($((SECONDS - start)) s)"

failed=()
passed=0
# step NAME COMMAND...: runs COMMAND, prints its duration, records NAME if it fails.
step() {
  local name=$1
  shift
  local start=$SECONDS
  echo "=== $name"
  if "$@"; then
    echo "=== $name: passed ($((SECONDS - start)) s)"
    passed=$((passed + 1))
  else
    echo "=== $name: FAILED ($((SECONDS - start)) s)"
    failed+=("$name")
    return 1
  fi
}

step "format check" bash scripts/check_format.sh
step "release build" bash -c 'cmake --preset release -DCAMPLACE_TESTS=binary-or-slow &&
  cmake --build --preset release' && step "release tests (binary or slow)" ctest --preset release
step "asan build" bash -c 'cmake --preset asan && cmake --build --preset asan' &&
  step "asan tests (library)" ctest --preset asan
step "fuzz (30 s per target)" bash scripts/fuzz.sh 30

echo "=== in all $SECONDS s"
echo "steps: $passed passed, ${#failed[@]} failed"
if [ ${#failed[@]} -gt 0 ]; then
  echo "=== FAILED: ${failed[*]}"
  exit 1
fi
echo "=== all checks passed"

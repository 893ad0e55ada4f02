#!/usr/bin/env bash
# Checks that every C++ source and header (*.cpp, *.hpp) is formatted as .clang-format says
# (Google style, 100 columns). Prints the files that differ and exits 1 if there are any; changes
# nothing. To fix a file: clang-format -i FILE.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang-format >/dev/null; then
  echo "check_format: clang-format not found (scripts/install_deps.sh installs it)" >&2
  exit 2
fi
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp')
else  # a copy of the tree without git: the same files, found on disk
  mapfile -t files < <(find . -path ./build -prune -o -path ./out -prune -o \
    -type f \( -name '*.cpp' -o -name '*.hpp' \) -print | sed 's|^\./||' | sort)
fi
bad=()
for f in "${files[@]}"; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ ${#bad[@]} -gt 0 ]; then
  echo "check_format: ${#bad[@]} of ${#files[@]} files differ from .clang-format ($(clang-format --version)):"
  printf '  %s\n' "${bad[@]}"
  echo "check_format: run clang-format -i on them"
  exit 1
fi
echo "check_format: ${#files[@]} files formatted as .clang-format says"

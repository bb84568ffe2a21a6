#!/usr/bin/env bash
# Applies .clang-format to hail's C++ files (Debian's clang-format 14: apt-get install clang-format).
#
#   scripts/format.sh          rewrites the files in place
#   scripts/format.sh --check  changes nothing; lists the files that differ and fails if any do
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "format: clang-format not found (sudo apt-get install clang-format)" >&2; exit 2; }
# tests/layering/ holds fixtures for the layer check, never compiled.
mapfile -t files < <(git ls-files '*.h' '*.cpp' | grep -v '^tests/layering/')
if [ "${1:-}" = "--check" ]; then
  differ=0
  for f in "${files[@]}"; do
    if ! clang-format --style=file "$f" | cmp -s - "$f"; then echo "format: $f differs"; differ=1; fi
  done
  exit $differ
fi
clang-format --style=file -i "${files[@]}"

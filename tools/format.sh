#!/usr/bin/env bash
# Formats the tracked C++ sources with .clang-format. --check changes nothing and fails, naming the files, when one
# is not formatted (run by .ci/run). shaders/ is GLSL (its push-constant headers too) and keeps its own layout.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-}
mapfile -d '' files < <(git ls-files -z -- '*.cpp' '*.hpp' '*.h' ':!:shaders/*')
if [ "$mode" = "--check" ]; then
  unformatted=()
  for f in "${files[@]}"; do
    clang-format --style=file "$f" | cmp -s - "$f" || unformatted+=("$f")
  done
  if [ ${#unformatted[@]} -gt 0 ]; then
    printf 'format: not formatted (run tools/format.sh): %s\n' "${unformatted[@]}" >&2
    exit 1
  fi
  echo "format: ${#files[@]} files formatted"
else
  clang-format --style=file -i "${files[@]}"
fi

#!/usr/bin/env bash
# The `format` test of `make test`: every C++ file of the tree is as clang-format (.clang-format) writes it.
# Fix with: clang-format -i FILE (or every file: clang-format -i $(git ls-files '*.cpp' '*.hpp' '*.h')).
set -euo pipefail
cd "${1:-$(dirname "$0")/..}"
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
else
  mapfile -t files < <(find src include python/src tests bench fuzz examples -name '*.cpp' -o -name '*.hpp' -o -name '*.h')
fi
# One clang-format process for all: it names each file and line it would change.
if ! out=$(clang-format --dry-run --Werror "${files[@]}" 2>&1); then
  printf '%s\n' "$out" | grep -E '^[^ ]+:[0-9]+:[0-9]+: error' | cut -d: -f1 | sort -u |
    sed 's/^/not formatted (clang-format -i FILE): /'
  exit 1
fi
echo "check-format: ${#files[@]} files formatted"

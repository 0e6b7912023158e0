#!/usr/bin/env bash
# Checks that the lines the last commit changed (or those since REV: check_format.sh REV) follow
# .clang-format, in C++ and CUDA files; prints the reformatting they need and fails when any do.
set -euo pipefail
cd "$(dirname "$0")/.."
base="${1:-HEAD~1}"
if ! git rev-parse --verify --quiet "$base^{commit}" > /dev/null; then
  echo "check_format: no commit $base to compare with; nothing checked"
  exit 0
fi
diff=$(git clang-format --quiet --diff --extensions cpp,hpp,cu,h "$base" -- || true)
if [ -n "$diff" ] && ! grep -q "no modified files to format\|did not modify any files" <<< "$diff"; then
  echo "$diff"
  echo "check_format: the lines above changed since $base do not follow .clang-format;" \
       "apply with: git clang-format $base" >&2
  exit 1
fi
echo "check_format: the C++ lines changed since $base follow .clang-format"

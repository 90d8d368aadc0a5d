#!/bin/sh
# Every C/C++ source of the project matches .clang-format (clang-format 14).
# Fix with: clang-format -i FILE
set -u
files=$(git ls-files '*.c' '*.h' '*.cpp' 2>/dev/null)
if [ -z "$files" ]; then
    files=$(find common pre solver post app tests bench -name '*.[ch]' -o -name '*.cpp' 2>/dev/null)
fi
count=$(echo "$files" | wc -w)
# shellcheck disable=SC2086
if ! clang-format --dry-run --Werror $files; then
    echo "FAIL: the files above differ from .clang-format; run clang-format -i on them"
    exit 1
fi
echo "ok: $count files match .clang-format"

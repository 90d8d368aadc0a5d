#!/bin/sh
# Runs `geoscni COMMAND CASE` on a malformed case file and checks that it
# exits with status 2 and that the first line of its error is exactly the
# file's "# expect: " line, where @CASES@ stands for the absolute path of
# the cases folder (the working directory: messages name resolved geometries).
# usage: check_case_error.sh GEOSCNI COMMAND CASE
set -u
geoscni=$1 command=$2 case_file=$3
expected=$(sed -n 's/^# expect: //p' "$case_file" | sed "s|@CASES@|$(pwd -P)|g")
if [ -z "$expected" ]; then
    echo "FAIL: $case_file has no '# expect: ' line"
    exit 1
fi
output=$(mktemp -d)
trap 'rm -rf "$output"' EXIT
if [ "$command" = check ]; then set -- "$case_file"; else set -- "$case_file" -o "$output/out"; fi
"$geoscni" "$command" "$@" >/dev/null 2>"$output/stderr"
status=$?
actual=$(head -n 1 "$output/stderr" | sed "s/^geoscni $command: error: //")
if [ "$status" -ne 2 ]; then
    echo "FAIL: $case_file: exit status $status, expected 2"
    cat "$output/stderr"
    exit 1
fi
if [ "$actual" != "$expected" ]; then
    echo "FAIL: $case_file"
    echo "  expected: $expected"
    echo "  actual:   $actual"
    exit 1
fi
if [ -e "$output/out/model.h5" ] || [ -e "$output/out/results.h5" ]; then
    echo "FAIL: $case_file: an output file was written for a bad case"
    exit 1
fi
echo "ok: $case_file: $actual"

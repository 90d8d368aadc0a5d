#!/bin/sh
# Runs `geoscni COMMAND CASE` on a case file with a legal but implausible
# soil value and checks that it goes on (exit 0 for check) and warns with
# the file's "# warn: " line, the likely unit mistake; with CASE
# valid.yaml, that nothing is warned of.
# usage: check_case_warning.sh GEOSCNI COMMAND CASE
set -u
geoscni=$1 command=$2 case_file=$3
expected=$(sed -n 's/^# warn: //p' "$case_file")
output=$(mktemp -d)
trap 'rm -rf "$output"' EXIT
"$geoscni" "$command" "$case_file" -q >/dev/null 2>"$output/stderr"
status=$?
if [ "$status" -ne 0 ]; then
    echo "FAIL: $case_file: exit status $status, expected 0"
    cat "$output/stderr"
    exit 1
fi
if [ -z "$expected" ]; then
    if grep -q "warning" "$output/stderr"; then
        echo "FAIL: $case_file: a plausible case was warned of:"
        cat "$output/stderr"
        exit 1
    fi
    echo "ok: $case_file: no warning"
    exit 0
fi
if ! grep -qxF "warning: $expected" "$output/stderr"; then
    echo "FAIL: $case_file"
    echo "  expected: warning: $expected"
    echo "  actual:   $(cat "$output/stderr")"
    exit 1
fi
echo "ok: $case_file: warning: $expected"

#!/bin/sh
# Issue 21, point 2: no two geoscni write one output folder.
# While a solve runs in a folder (held stopped with SIGSTOP, so it cannot
# end first), a second solve, pre, run and post into the folder exit 2 with
# "OUTDIR is in use by another geoscni (pid N)", N the first's pid; the
# first then ends with exit 0 and its results read back. run with two case
# files of the same name (reproducer samename), or one file twice, with -o
# or without, exits 2 before any work, naming both, and writes nothing.
. ./cli_testing.sh
cp -r cases/repro "$out/repro"
r=$out/repro

"$geoscni" pre "$r/concurrent.yaml" -o "$out/c" -q || fail "pre failed"
"$geoscni" solve "$r/concurrent.yaml" -o "$out/c" -q 2>"$out/first.err" &
first=$!
# the lock file holds its owner's pid once the solve has the lock
i=0
while [ "$(cat "$out/c/.geoscni.lock" 2>/dev/null)" != "$first" ] && [ $i -lt 600 ]; do
    sleep 0.05
    i=$((i + 1))
done
kill -STOP $first
for command in "solve $r/concurrent.yaml -o $out/c" "pre $r/concurrent.yaml -o $out/c" \
    "run $r/concurrent.yaml -o $out/c --no-pictures" "post $out/c --no-pictures"; do
    # shellcheck disable=SC2086
    "$geoscni" $command -q 2>"$out/err"
    status=$?
    [ $status -eq 2 ] || fail "$command beside a running solve exited $status, expected 2"
    grep -qF "error: $out/c is in use by another geoscni (pid $first)" "$out/err" ||
        fail "$command: message: $(cat "$out/err")"
done
kill -CONT $first
wait $first
status=$?
[ $status -eq 0 ] || fail "the first solve exited $status: $(cat "$out/first.err")"
h5ls "$out/c/results.h5" >/dev/null 2>&1 || fail "the first solve's results.h5 is unreadable"
"$geoscni" post "$out/c" --no-pictures -q 2>"$out/err" || fail "post after the solve: $(cat "$out/err")"
grep -q "incomplete" "$out/err" && fail "the first solve's results are incomplete"

a=$r/samename_a/case.yaml b=$r/samename_b/case.yaml
"$geoscni" run "$a" "$b" -o "$out/same" --no-pictures -q 2>"$out/err"
[ $? -eq 2 ] || fail "run of two cases of one name should exit 2"
grep -qF "error: $a and $b would both write to $out/same/case (the files have the same name)" "$out/err" ||
    fail "same-name message: $(cat "$out/err")"
[ -e "$out/same" ] && fail "run of two cases of one name wrote $out/same"
"$geoscni" run "$a" "$a" -o "$out/twice" --no-pictures -q 2>"$out/err"
[ $? -eq 2 ] || fail "run of one case twice should exit 2"
(cd "$r" && "$geoscni" run samename_a/case.yaml samename_b/case.yaml --no-pictures -q 2>"$out/err")
[ $? -eq 2 ] || fail "run of two cases of one name without -o should exit 2"
grep -qF "would both write to case" "$out/err" || fail "without -o: $(cat "$out/err")"
[ -e "$r/case" ] && fail "run of two cases of one name without -o wrote $r/case"
finish

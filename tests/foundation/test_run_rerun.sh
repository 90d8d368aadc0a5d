#!/bin/sh
# geoscni run --rerun starts over a run that was interrupted (the solver
# refuses to replace its results otherwise and names run --rerun), and
# run --restart resumes it. Each run is stopped with SIGTERM (a background
# job of a script ignores SIGINT) once it prints its first progress line.
# usage: test_run_rerun.sh GEOSCNI   (run from tests/foundation/cases)
set -u
geoscni=$1
work=$(mktemp -d /tmp/geoscni-run-rerun.XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=0

# run_until_stepping NAME ARGS...: starts geoscni ARGS, waits (at most 60 s)
# for its first progress line or its end, then stops it
run_until_stepping() {
    name=$1
    shift
    "$geoscni" "$@" >"$work/$name.out" 2>"$work/$name.err" &
    pid=$!
    for _ in $(seq 1 600); do
        grep -q "^step " "$work/$name.err" && break
        kill -0 $pid 2>/dev/null || break
        sleep 0.1
    done
    kill -TERM $pid 2>/dev/null
    wait $pid
    status=$?
}

run_until_stepping first run long.yaml -o "$work/out" --no-pictures -j1
[ "$status" -eq 130 ] || {
    echo "FAIL: the first run exited $status, expected 130 (stopped with a checkpoint)"
    cat "$work/first.err"
    failures=$((failures + 1))
}
run_until_stepping rerun run long.yaml -o "$work/out" --no-pictures --rerun -j1
if [ "$status" -ne 130 ] || ! grep -q "^step " "$work/rerun.err"; then
    echo "FAIL: run --rerun over an interrupted run exited $status before stepping:"
    cat "$work/rerun.err"
    failures=$((failures + 1))
else
    echo "ok   run --rerun started over the interrupted run"
fi
run_until_stepping restart run long.yaml -o "$work/out" --no-pictures --restart -j1
if [ "$status" -ne 130 ] ||
    ! grep -q "^restart: from the checkpoint" "$work/restart.out" "$work/restart.err"; then
    echo "FAIL: run --restart did not resume (exit $status):"
    cat "$work/restart.out" "$work/restart.err"
    failures=$((failures + 1))
else
    echo "ok   run --restart resumed: $(grep -h "^restart:" "$work/restart.out" "$work/restart.err")"
fi
echo "run_rerun: $failures failed"
[ "$failures" -eq 0 ]

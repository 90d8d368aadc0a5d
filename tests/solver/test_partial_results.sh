#!/bin/sh
# Issue 21, point 7: results a run did not finish.
# - A solve killed (SIGKILL) leaves results.h5.part beside the results.h5
#   of an earlier run: post refuses it (exit 2) saying the results are
#   incomplete and how to finish them; a --restart refused (another case)
#   leaves results.h5, results.h5.part and history.csv as they were (the
#   .part was once renamed over results.h5); the right --restart finishes
#   the run, and post then works without a warning.
# - A solve stopped by SIGTERM (exit 130) leaves results.h5 marked
#   interrupted: post writes its frames (exit 0) and warns that they are
#   incomplete.
. ./cli_testing.sh
root=$(cd ../.. && pwd)
sed -e "s#^geometry: .*#geometry: $root/geometries/box.geo#" cases/cli_box_long.yaml >"$out/long.yaml"
sed -e 's/end: 1000/end: 0.2/' "$out/long.yaml" >"$out/short.yaml"
sed -e 's/density: 2000/density: 2500/' "$out/long.yaml" >"$out/denser.yaml"

# start_and_stop SIGNAL: solves long.yaml into $out/k and sends SIGNAL once
# history.csv has more rows than the short run writes (4 lines); the solve's exit status in $status
start_and_stop() {
    "$geoscni" solve "$out/long.yaml" -o "$out/k" -q 2>"$out/solve.err" &
    solver=$!
    i=0
    while [ "$(wc -l <"$out/k/history.csv" 2>/dev/null || echo 0)" -lt 6 ] && [ $i -lt 600 ]; do
        sleep 0.05
        i=$((i + 1))
    done
    kill "-$1" $solver
    wait $solver
    status=$?
}

"$geoscni" pre "$out/long.yaml" -o "$out/k" -q || fail "pre failed"
"$geoscni" solve "$out/short.yaml" -o "$out/k" -q 2>/dev/null || fail "the short solve failed"
start_and_stop KILL
[ -e "$out/k/results.h5.part" ] || fail "the killed solve left no results.h5.part"
"$geoscni" post "$out/k" --no-pictures -q 2>"$out/err"
[ $? -eq 2 ] || fail "post on a killed run's results should exit 2"
grep -q "results.h5.part: the results are incomplete: the solve that wrote them stopped before its end without finishing the file (killed) (its last checkpoint: step [0-9]*, t = .* s), and results.h5 beside it is an older run's; continue it with 'geoscni run CASE.yaml -o $out/k --restart'" "$out/err" ||
    fail "post on a .part: $(cat "$out/err")"
for f in results.h5 results.h5.part history.csv; do cp "$out/k/$f" "$out/before_$f"; done
"$geoscni" solve "$out/denser.yaml" -o "$out/k" -q --restart 2>"$out/err"
[ $? -eq 2 ] || fail "a restart with another case should exit 2"
grep -q "started from another case" "$out/err" || fail "refused restart: $(cat "$out/err")"
for f in results.h5 results.h5.part history.csv; do
    cmp -s "$out/k/$f" "$out/before_$f" || fail "a refused restart changed $f"
done
stopped=$(awk -F, 'END { print $1 }' "$out/k/history.csv")
end=$(awk -v t="$stopped" 'BEGIN { printf "%.6g", t + 0.2 }')
sed -e "s/end: 1000/end: $end/" "$out/long.yaml" >"$out/until.yaml"
"$geoscni" solve "$out/until.yaml" -o "$out/k" -q --restart 2>"$out/err" ||
    fail "the restart of the killed run failed: $(cat "$out/err")"
[ -e "$out/k/results.h5.part" ] && fail "results.h5.part left after the restart"
"$geoscni" post "$out/k" --no-pictures -q 2>"$out/err" || fail "post after the restart: $(cat "$out/err")"
grep -q "incomplete" "$out/err" && fail "post after the restart: $(cat "$out/err")"

rm -rf "$out/k/results.h5" "$out/k/history.csv"
start_and_stop TERM
[ $status -eq 130 ] || fail "a solve stopped by SIGTERM exited $status, expected 130"
"$geoscni" post "$out/k" --no-pictures -q 2>"$out/err" ||
    fail "post on an interrupted run's results failed: $(cat "$out/err")"
grep -q "warning: $out/k/results.h5 is incomplete: its run was interrupted before its end of its 1000 s; post writes the [0-9]* frames it has, to t = .* s (continue the run with --restart, then post again)" "$out/err" ||
    fail "post on interrupted results: $(cat "$out/err")"
[ -s "$out/k/long.pvd" ] || fail "post on interrupted results wrote no .pvd"
finish

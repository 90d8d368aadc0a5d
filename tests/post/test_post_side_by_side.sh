#!/bin/sh
# Several posts at once, each with its private Xvfb (post/src/display.c):
# every one ends with status 0 and writes its pictures and plots; then four
# whole runs at once. Before
# Xvfb ran with -noreset, a server reset between two render windows (its
# last client gone) refused the next window now and then: "bad X server
# connection" (abort) or a crash in XSync, 9 of 32 posts when four ran side
# by side on 2 cores (2026-12-02).
geoscni="$1"
out=$(mktemp -d /tmp/geoscni-test-post-side-XXXXXX)
trap 'rm -rf "$out"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
posts=4
rounds=3
"$geoscni" run box.yaml -o "$out/case" -q --no-pictures || {
    echo "FAIL: the run of box.yaml failed"
    exit 1
}
# made LABEL STATUS_FILE LOG FOLDER: exit status 0, the energy plot and
# the damage pictures in FOLDER
made() {
    status=$(cat "$2")
    [ "$status" = 0 ] || fail "$1: status $status: $(head -c 300 "$3")"
    [ -s "$4/plots/energy.png" ] && ls "$4/pictures/"damage_*.png >/dev/null 2>&1 ||
        fail "$1: pictures or plots missing"
}
round=1
while [ $round -le $rounds ]; do
    i=1
    while [ $i -le $posts ]; do
        rm -rf "$out/p$i"
        cp -r "$out/case" "$out/p$i"
        rm -rf "$out/p$i/pictures" "$out/p$i/plots"
        i=$((i + 1))
    done
    i=1
    while [ $i -le $posts ]; do
        ("$geoscni" post "$out/p$i" -q >"$out/log$i" 2>&1
         echo $? >"$out/status$i") &
        i=$((i + 1))
    done
    wait
    i=1
    while [ $i -le $posts ]; do
        made "round $round, post $i" "$out/status$i" "$out/log$i" "$out/p$i"
        i=$((i + 1))
    done
    round=$((round + 1))
done
# Issue 19, point 3: four whole runs at once (pre, solve and post with its
# pictures), each into its own folder
i=1
while [ $i -le $posts ]; do
    ("$geoscni" run box.yaml -o "$out/r$i" -q >"$out/run$i" 2>&1
     echo $? >"$out/run_status$i") &
    i=$((i + 1))
done
wait
i=1
while [ $i -le $posts ]; do
    made "run $i" "$out/run_status$i" "$out/run$i" "$out/r$i"
    i=$((i + 1))
done
echo "$((posts * rounds)) posts and $posts runs side by side, $failures failures"
[ $failures -eq 0 ]

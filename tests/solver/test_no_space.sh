#!/bin/sh
# Issue 21, point 7: a full disk says "no space left on device" and names
# the file, exit status 1 (not 2, bad input), for pre (model.h5), solve
# (results.h5 or history.csv), post (a .vtu or the .pvd) and run. The disk
# is a small tmpfs: mounted directly as root, else in a user and mount
# namespace (unshare -rm); skipped (77) where neither is allowed.
if [ -z "${GEOSCNI_NO_SPACE_INSIDE:-}" ] && [ "$(id -u)" -ne 0 ]; then
    if unshare -rm true 2>/dev/null; then
        GEOSCNI_NO_SPACE_INSIDE=1 exec unshare -rm sh "$0" "$@"
    fi
    echo "skipped: cannot mount a small tmpfs (not root, no user namespaces)"
    exit 77
fi
. ./cli_testing.sh
disk=$out/disk
mkdir -p "$disk"
# mount_disk SIZE: a fresh tmpfs of SIZE on $disk
mount_disk() {
    umount "$disk" 2>/dev/null
    mount -t tmpfs -o "size=$1" tmpfs "$disk" || {
        echo "skipped: mount -t tmpfs failed"
        exit 77
    }
}
trap 'umount "$disk" 2>/dev/null; rm -rf "$out"' EXIT
root=$(cd ../.. && pwd)
# the box under gravity with a frame every 0.05 s: 2.3 MB of results to 4 s
sed -e "s#^geometry: .*#geometry: $root/geometries/box.geo#" -e 's/end: 1000/end: 4/' \
    -e 's/output: .*/output: {every: 0.05}/' cases/cli_box_long.yaml >"$out/case.yaml"

# expect_full WHAT FILE_PATTERN: the last command's exit status and message
expect_full() {
    [ "$status" -eq 1 ] || fail "$1: exit status $status, expected 1: $(cat "$out/err")"
    grep -q "error: $disk/out/$2: .*: no space left on device; free some space on it, or choose an output folder on another disk" "$out/err" ||
        fail "$1: message: $(cat "$out/err")"
    grep -q "bad input" "$out/err" && fail "$1: says bad input"
    echo "$1: $(grep error: "$out/err")"
}

mount_disk 100k
"$geoscni" pre "$out/case.yaml" -o "$disk/out" -q 2>"$out/err"
status=$?
expect_full pre "model.h5.part"
[ -e "$disk/out/model.h5" ] && fail "pre on a full disk left a model.h5"

mount_disk 1m
"$geoscni" pre "$out/case.yaml" -o "$disk/out" -q 2>/dev/null || fail "pre on 1 MB failed"
"$geoscni" solve "$out/case.yaml" -o "$disk/out" -q 2>"$out/err"
status=$?
expect_full solve "\(results.h5.part\|history.csv\)"

"$geoscni" run "$out/case.yaml" -o "$out/done" --no-pictures -q 2>/dev/null || fail "the run to post failed"
mount_disk 4m
mkdir "$disk/out"
cp "$out/done/model.h5" "$out/done/results.h5" "$out/done/history.csv" "$disk/out/"
# leave 50 kB: less than the frames' .vtu files need
free=$(df -k "$disk" | awk 'NR == 2 { print $4 }')
head -c $(((free - 50) * 1024)) /dev/zero >"$disk/filler" 2>/dev/null
"$geoscni" post "$disk/out" --no-pictures -q 2>"$out/err"
status=$?
expect_full post "\(vtu/frame_[0-9]*.vtu\|case.pvd\)\(.part\)*"

mount_disk 1m
"$geoscni" run "$out/case.yaml" -o "$disk/out" --no-pictures -q 2>"$out/err"
status=$?
expect_full run "\(results.h5.part\|history.csv\)"
finish

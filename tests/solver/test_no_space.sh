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

# Issue 19, point 4: a solve whose disk fills stops before the frame that
# would not fit (its frames whole under results.h5, a checkpoint of that
# step), and --restart goes on to the end once there is room: the same
# frames as a run on a roomy disk. (A write that fails anyway, the disk
# filled by another writer, keeps results.h5.part: not renamed.)
"$geoscni" run "$out/case.yaml" -o "$out/done" --no-pictures -q 2>/dev/null || fail "the run to post failed"
mount_disk 1500k
"$geoscni" pre "$out/case.yaml" -o "$disk/out" -q 2>/dev/null || fail "pre on 1.5 MB failed"
"$geoscni" solve "$out/case.yaml" -o "$disk/out" -q 2>"$out/err"
status=$?
[ "$status" -eq 1 ] || fail "solve: exit status $status, expected 1: $(cat "$out/err")"
grep -q "error: $disk/out: [0-9.]* MB free on its disk, the next frame needs about [0-9.]* MB: the run stops at step [0-9]*, .* with its [0-9]* frames whole and a checkpoint of this step; free some space, then continue with 'geoscni solve .* --restart'" "$out/err" ||
    fail "solve: message: $(cat "$out/err")"
echo "solve: $(grep error: "$out/err")"
[ -e "$disk/out/results.h5.part" ] && fail "solve left results.h5.part"
/usr/bin/python3 - "$disk/out/results.h5" <<'PY' || fail "the frames kept are not whole"
import sys, zlib, h5py
with h5py.File(sys.argv[1], "r") as f:
    frames = sorted(f["frames"])
    assert len(frames) == f.attrs["frame_count"] >= 1, (len(frames), f.attrs["frame_count"])
    checked = 0
    def check(name, node):
        global checked
        if isinstance(node, h5py.Dataset):
            assert zlib.crc32(node[()].tobytes()) == node.attrs["crc32"], name
            checked += 1
    f.visititems(check)
    print(f"kept: {len(frames)} frames, {checked} datasets, every CRC right")
PY
mount -o remount,size=8m "$disk" || fail "cannot make room"
"$geoscni" solve "$out/case.yaml" -o "$disk/out" -q --restart 2>"$out/err" ||
    fail "the restart after room was made failed: $(cat "$out/err")"
/usr/bin/python3 - "$disk/out/results.h5" "$out/done/results.h5" <<'PY' || fail "the restarted run is not the roomy one"
import sys, h5py
a, b = (h5py.File(p, "r") for p in sys.argv[1:])
assert a.attrs["complete"] == 1
assert sorted(a["frames"]) == sorted(b["frames"]), (len(a["frames"]), len(b["frames"]))
print(f"restarted: complete, {len(a['frames'])} frames as the roomy run's")
PY

mount_disk 1m
"$geoscni" pre "$out/case.yaml" -o "$disk/out" -q 2>/dev/null || fail "pre on 1 MB failed"
"$geoscni" solve "$out/case.yaml" -o "$disk/out" -q 2>"$out/err"
status=$?
[ "$status" -eq 1 ] || fail "solve on 1 MB: exit status $status: $(cat "$out/err")"
grep -q "no space left on device\|MB free on its disk" "$out/err" || fail "solve on 1 MB: $(cat "$out/err")"
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
[ "$status" -eq 1 ] || fail "run: exit status $status: $(cat "$out/err")"
grep -q "no space left on device\|MB free on its disk" "$out/err" || fail "run: $(cat "$out/err")"
echo "run: $(grep error: "$out/err")"
finish

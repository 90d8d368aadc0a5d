#!/bin/sh
# Issue 20, point 1: the same case, build and machine give the same bits by
# default, for any thread count. cases/punch.yaml (gmsh's default Delaunay
# mesher, damage + Drucker-Prager, MSCNI, failed particles) run from its
# geometry on 1 and on 2 threads, and again with NSNI and
# reference-configuration updates and nonlocal damage: every dataset of model.h5 and results.h5
# (the checkpoint too: a complete run's is its last step's) and every byte
# of history.csv are identical. A changed bit anywhere (a mesher that varies
# from run to run, a reduction whose order follows the threads) fails it.
. ./cli_testing.sh

run() { # NAME THREADS CASE
    OMP_NUM_THREADS=$2 "$geoscni" run "$3" -o "$out/$1" --no-pictures -q \
        >"$out/$1.log" 2>&1 || fail "$1 on $2 threads ended with $?: $(grep error "$out/$1.log")"
}

compare() { # A B
    /usr/bin/python3 - "$out/$1" "$out/$2" <<'PY' || fail "$1 and $2 differ"
import sys, h5py, numpy as np
a, b = sys.argv[1], sys.argv[2]
def datasets(path):
    found = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, node: found.__setitem__(name, node[()])
                     if isinstance(node, h5py.Dataset) else None)
    return found
differ = 0
checked = 0
for name in ("model.h5", "results.h5"):
    x, y = datasets(f"{a}/{name}"), datasets(f"{b}/{name}")
    if sorted(x) != sorted(y):
        print(f"{name}: datasets differ: {sorted(set(x) ^ set(y))[:5]}")
        differ += 1
    for key in sorted(set(x) & set(y)):
        checked += 1
        u, v = np.asarray(x[key]), np.asarray(y[key])
        if u.shape != v.shape or u.tobytes() != v.tobytes():
            print(f"{name}:{key} differs")
            differ += 1
h = [open(f"{p}/history.csv").read() for p in (a, b)]
if h[0] != h[1]:
    print("history.csv differs")
    differ += 1
print(f"{a.split('/')[-1]} / {b.split('/')[-1]}: {checked} datasets and "
      f"{h[0].count(chr(10))} history lines compared, {differ} differ")
sys.exit(1 if differ else 0)
PY
}

cp cases/punch.geo "$out/"
sed 's|^geometry: .*|geometry: punch.geo|' cases/punch.yaml >"$out/punch.yaml"
# (the slope cases' NSNI; to 0.4 m, before particles crush under the edge;
# nonlocal damage over 0.5 m, its averages rebuilt at each update)
{
    sed -e 's|^integration: .*|integration: {method: scni, stabilization: nsni, coefficient: 0.1}|' \
        -e 's|end: 1.4|end: 1.0|' \
        -e 's|damage: {e0: 0.02, ef: 5.0}|damage: {e0: 0.02, ef: 5.0, length: 0.5}|' "$out/punch.yaml"
    echo "kinematics: large"
    echo "reference_update: {strain: 0.1, min_steps: 20}"
} >"$out/updates.yaml"
run one 1 "$out/punch.yaml"
run two 2 "$out/punch.yaml"
compare one two
# the control: one value of the last frame moved by one ulp is found
cp -r "$out/two" "$out/flipped"
/usr/bin/python3 -c '
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r+") as f:
    u = f["frames"][sorted(f["frames"])[-1]]["displacement"]
    u[0, 2] = np.nextafter(u[0, 2], np.inf)' "$out/flipped/results.h5"
failures_before=$failures
compare two flipped >"$out/control.log"
[ $failures -eq $((failures_before + 1)) ] && failures=$failures_before ||
    fail "a value moved by one ulp was not found: $(cat "$out/control.log")"
grep -q "results.h5:frames/.*/displacement differs" "$out/control.log" ||
    fail "the control did not name the dataset: $(cat "$out/control.log")"
run updates_one 1 "$out/updates.yaml"
run updates_two 2 "$out/updates.yaml"
compare updates_one updates_two
updates=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "reference_updates") c = i }
    END { print c ? $c : 0 }' "$out/updates_one/history.csv")
echo "updates: $updates"
[ "${updates:-0}" -ge 1 ] || fail "the run with updates made none"
finish

#!/bin/sh
# Rigid bodies (solver/src/contact.h): soft clay squeezed sideways against a
# rigid footing (cases/rigid_wall.yaml, gmsh's reproducible mesh).
# - rigid: true: no particle but the footing's own lies inside the footing
#   (above its base, 0 <= x < 0.5 m) deeper than 0.01 h at any frame (the
#   penalty keeps it to sigma / M h / 0.5, measured 0.003 h); the wall
#   pushes the soil (footing_fx_N > 10 N at the end: measured 78 N); the
#   energy balance holds within 1e-3 of the work (the contact force is
#   external work); 1 and 2 threads give the same history, bit for bit;
# - negative control, rigid: false: the soil flows over the base, deeper
#   than 0.5 h (measured 1.1 h);
# - case-file checks: rigid without a velocity, and a bad value, name the
#   line;
# - a smooth rigid footing pushed 0.4 B into clay with reference updates
#   (geometries/footing_penetration.yaml at B/5) lets go of the particles
#   of its base that slide out past its edge: some end beyond x = B/2 with
#   u_z short of the footing's settlement by more than 0.1 h (without the
#   release every base particle moves with the footing); the history's u_z
#   is the footing's own; stopped halfway on 1 thread and continued with
#   --restart on 2, it ends on the uninterrupted run's last history row,
#   bit for bit (the contact forces are recomputed from the checkpoint's
#   state, the released particles from its reference positions).
. ./cli_testing.sh
cp cases/rigid_wall.geo cases/rigid_wall.yaml "$out/"
sed 's/, rigid: true//' "$out/rigid_wall.yaml" >"$out/free_wall.yaml"
for run in rigid_wall:2 free_wall:2 rigid_wall_1:1; do
    name=${run%:*}
    threads=${run#*:}
    case_file=$out/${name%_1}.yaml
    OMP_NUM_THREADS=$threads "$geoscni" run "$case_file" \
        -o "$out/$name" -q --no-pictures >"$out/$name.log" 2>&1 ||
        fail "$name ended with status $?: $(grep error "$out/$name.log" | head -1)"
done
cmp -s "$out/rigid_wall/history.csv" "$out/rigid_wall_1/history.csv" ||
    fail "1 and 2 threads give different histories"
/usr/bin/python3 - "$out" <<'PY' || fail "penetration"
import sys, h5py, numpy as np
out, h, B, D = sys.argv[1], 0.1, 0.5, 1.0
def deepest(name):
    model = h5py.File(f"{out}/{name}/model.h5", "r")
    X = model["particles/position"][:]
    own = (np.abs(X[:, 2] - D) < 1e-9) & (X[:, 0] <= B + 1e-9)
    frames = h5py.File(f"{out}/{name}/results.h5", "r")["frames"]
    worst = 0.0
    for key in frames:
        t = frames[key].attrs["time"]
        base = D - 0.01 * max(0.0, t - 0.25)  # the footing's z, ramp 0.5 s
        x = X + frames[key]["displacement"][:]
        inside = ~own & (x[:, 0] < B) & (x[:, 2] > base)
        if inside.any():
            worst = max(worst, np.minimum(B - x[inside, 0], x[inside, 2] - base).max())
    return worst / h
rigid, free = deepest("rigid_wall"), deepest("free_wall")
print(f"deepest particle inside the footing: rigid {rigid:.4f} h, without {free:.3f} h")
sys.exit(0 if rigid < 0.01 and free > 0.5 else 1)
PY
awk -F, '
    NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    { rows[NR] = $0; work = $col["external_work_J"]; fx = $col["footing_fx_N"] }
    END {
        for (r = 2; r <= NR; ++r) {
            split(rows[r], v, ",")
            k = v[col["kinetic_energy_J"]]; w = v[col["internal_energy_J"]]
            d = v[col["damping_work_J"]]; x = v[col["external_work_J"]]
            u = v[col["update_energy_J"]]
            scale = x > 0.01 * work ? x : 0.01 * work
            gap = k + w + d - x - u
            if (gap > 1e-3 * scale || -gap > 1e-3 * scale) {
                printf "energy balance %.3g of the work at t = %s s\n", gap / scale, v[1]; bad++
            }
        }
        printf "wall force on the soil at the end: %.4g N\n", fx
        if (fx < 10) { print "the wall does not push"; bad++ }
        exit bad > 0
    }' "$out/rigid_wall/history.csv" || fail "history of the rigid wall"
# case-file checks
sed 's/pusher: {velocity: \[-0.1, null, null\]}/pusher: {fix: [x], rigid: true}/' \
    "$out/rigid_wall.yaml" >"$out/still.yaml"
"$geoscni" check "$out/still.yaml" >"$out/still.log" 2>&1
status=$?
[ $status -eq 2 ] && grep -q "still.yaml:19:.*rigid body.*nonzero velocity" "$out/still.log" ||
    fail "rigid without a velocity: status $status, $(cat "$out/still.log")"
sed 's/rigid: true/rigid: yes please/' "$out/rigid_wall.yaml" >"$out/word.yaml"
"$geoscni" check "$out/word.yaml" >"$out/word.log" 2>&1
status=$?
[ $status -eq 2 ] && grep -q "word.yaml:20:.*rigid" "$out/word.log" ||
    fail "a bad rigid value: status $status, $(cat "$out/word.log")"
# release of the base's particles that slide out (reference updates)
{
    echo "kinematics: large"
    echo "reference_update: {strain: 0.2, min_steps: 20}"
    sed -e "s|^geometry: *|geometry: $PWD/../../geometries/|" \
        -e "s|^\( *spacing:\).*|\1 0.2|" -e "s|^\( *end:\).*|\1 4.25|" \
        ../../geometries/footing_penetration.yaml
} >"$out/sinking.yaml"
"$geoscni" run "$out/sinking.yaml" -o "$out/sinking" -q \
    --no-pictures >"$out/sinking.log" 2>&1 ||
    fail "the sinking footing ended with status $?: $(grep error "$out/sinking.log" | head -1)"
/usr/bin/python3 - "$out/sinking" <<'PY' || fail "release of the base's particles"
import sys, h5py, numpy as np
out, h, B, D = sys.argv[1], 0.2, 1.0, 5.0
X = h5py.File(f"{out}/model.h5", "r")["particles/position"][:]
frames = h5py.File(f"{out}/results.h5", "r")["frames"]
last = frames[sorted(frames.keys())[-1]]
x = X + last["displacement"][:]
base = (np.abs(X[:, 2] - D) < 1e-9) & (X[:, 0] <= B / 2 + 1e-9)
settlement = 0.1 * (last.attrs["time"] - 0.25)
history = np.genfromtxt(f"{out}/history.csv", delimiter=",", names=True)
reported = -history["footing_uz_m"][-1]
let_go = base & (x[:, 0] > B / 2) & (-last["displacement"][:, 2] < settlement - 0.1 * h)
print(f"settlement {settlement:.4f} m (history {reported:.4f}); {base.sum()} base particles, "
      f"{let_go.sum()} let go past the edge")
sys.exit(0 if let_go.sum() >= 1 and abs(reported - settlement) < 1e-6 else 1)
PY
mkdir -p "$out/resumed" && cp "$out/sinking/model.h5" "$out/resumed/"
sed 's|^\( *end:\).*|\1 2.25|' "$out/sinking.yaml" >"$out/sinking_half.yaml"
OMP_NUM_THREADS=1 "$geoscni" solve "$out/sinking_half.yaml" -o "$out/resumed" -q \
    2>"$out/resumed.log" || fail "the first half: $(cat "$out/resumed.log")"
OMP_NUM_THREADS=2 "$geoscni" solve "$out/sinking.yaml" -o "$out/resumed" -q --restart \
    2>>"$out/resumed.log" || fail "the restart: $(cat "$out/resumed.log")"
[ "$(tail -1 "$out/sinking/history.csv")" = "$(tail -1 "$out/resumed/history.csv")" ] ||
    fail "the restarted sinking footing ends elsewhere than the uninterrupted one"
# every row of before the restart kept (a restart after reference updates
# once dropped them all, and the frames with them: the loop it read the
# checkpoint's step from had been replaced)
# (the resumed one has one row more: the first half's last, at its end)
# rows_kept DIR: every history row of the uninterrupted run is in DIR's,
# which has at most one more
rows_kept() {
    /usr/bin/python3 - "$out/sinking/history.csv" "$out/$1/history.csv" <<'PY'
import sys
a, b = (open(p).read().splitlines() for p in sys.argv[1:])
missing = [row for row in a if row not in set(b)]
print(f"history rows: uninterrupted {len(a)}, {sys.argv[2]}: {len(b)}, missing {len(missing)}")
sys.exit(0 if not missing and len(b) - len(a) <= 1 else 1)
PY
}
# frames_kept DIR same|all: DIR has the uninterrupted run's frames, the
# same ones or at least as many
frames_kept() {
    /usr/bin/python3 - "$out/sinking/results.h5" "$out/$1/results.h5" "$2" <<'PY'
import sys, h5py
a, b = (sorted(h5py.File(p, "r")["frames"].keys()) for p in sys.argv[1:3])
print(f"frames: uninterrupted {len(a)}, {sys.argv[2]}: {len(b)}")
sys.exit(0 if (a == b if sys.argv[3] == "same" else len(b) >= len(a)) else 1)
PY
}
rows_kept resumed ||
    fail "the restarted run lost or changed history rows of the uninterrupted one"
# and stopped by a signal after its first updates (the case that lost
# every row and frame before the checkpoint), continued with --restart
mkdir -p "$out/signalled" && cp "$out/sinking/model.h5" "$out/signalled/"
OMP_NUM_THREADS=1 "$geoscni" solve "$out/sinking.yaml" -o "$out/signalled" -q \
    2>"$out/signalled.log" &
solver=$!
i=0
until awk -F, 'NR == 1 { for (k = 1; k <= NF; ++k) if ($k == "reference_updates") c = k; next }
               c && $c >= 2 { found = 1 } END { exit !found }' \
    "$out/signalled/history.csv" 2>/dev/null || [ $i -ge 600 ]; do
    sleep 0.1
    i=$((i + 1))
done
kill -TERM $solver
wait $solver
[ $? -eq 130 ] || fail "the signalled run did not stop on the signal: $(cat "$out/signalled.log")"
OMP_NUM_THREADS=2 "$geoscni" solve "$out/sinking.yaml" -o "$out/signalled" -q --restart \
    2>>"$out/signalled.log" || fail "the restart after the signal: $(cat "$out/signalled.log")"
rows_kept signalled ||
    fail "the run stopped by a signal after updates lost history rows on --restart"
frames_kept signalled all ||
    fail "the run stopped by a signal after updates lost frames on --restart"
frames_kept resumed same ||
    fail "the restarted run's frames differ from the uninterrupted one's"
finish

#!/bin/sh
# Issue 15: where reference updates add damage to the paper's soil. Runs the
# coarse Slope I (geometries/slope_I_coarse.yaml: NSNI 0.1, damage +
# Drucker-Prager, 4,886 particles) as it is (its first reference kept, the
# default with damage) and with `reference_update: {strain: 0.2,
# min_steps: 20}`, one after the other on THREADS threads (default 1), and
# compares them: the particles with damage above 0.1 (e_t above 0.0222 for
# e0 = 0.02, ef = 5) at every frame, the kinetic energy's median over
# windows of the run, the time step at the end, and where the particles
# damaged only with updates lie (reference x-z, 2 m bins) and how far they
# moved, and the median speed of the soil far from the footing and the
# face (reference x < 4 m, z < 3 m) at every frame: how much an update sets
# the whole body ringing. About a minute a run on one core.
# UPDATE replaces the updated run's reference_update (e.g. "{strain: 100,
# volume: [0.001, 1000], every: 8, min_steps: 20}": one update every 8 s,
# to see what a single update does); EXTRA adds a line to both cases (e.g.
# "damping: {local: 0.5}").
# Usage: [UPDATE=...] [EXTRA=...] bench/damage_updates.sh [BUILD_DIR] [OUT]
#        (default build, out/damage_updates)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
out=${2:-$root/out/damage_updates}
geoscni=$root/$build/bin/geoscni
[ -x "$geoscni" ] || { echo "no $geoscni: build first" >&2; exit 2; }
mkdir -p "$out"
sed -e "s|^geometry: *|geometry: $root/geometries/|" \
    "$root/geometries/slope_I_coarse.yaml" >"$out/kept.yaml"
[ -n "${EXTRA:-}" ] && echo "$EXTRA" >>"$out/kept.yaml"
cp "$out/kept.yaml" "$out/updated.yaml"
echo "reference_update: ${UPDATE:-"{strain: 0.2, min_steps: 20}"}" >>"$out/updated.yaml"
for name in kept updated; do
    "$geoscni" run "$out/$name.yaml" -o "$out/$name" -j "${THREADS:-1}" -q \
        --no-pictures 2>"$out/$name.log" || {
        echo "$name: the run failed: see $out/$name.log" >&2
        exit 1
    }
done
/usr/bin/python3 - "$out/kept" "$out/updated" <<'PY'
import csv, sys
import h5py
import numpy as np

kept, updated = sys.argv[1], sys.argv[2]


def frames(run):
    f = h5py.File(run + "/results.h5", "r")
    names = sorted(f["frames"].keys())
    return [(f["frames"][n].attrs.get("time", np.nan),
             f["frames"][n]["damage"][:],
             f["frames"][n]["displacement"][:],
             f["frames"][n]["velocity"][:]) for n in names]



def history(run):
    rows = list(csv.DictReader(open(run + "/history.csv")))
    return {k: np.array([float(r[k]) for r in rows])
            for k in ("time_s", "step", "kinetic_energy_J",
                      "reference_updates")}


a, b = frames(kept), frames(updated)
print("particles with damage above 0.1 (e_t above 0.0222), first reference kept"
      " / updated:")
for i in range(0, min(len(a), len(b)), 4):
    print(f"  frame {i:2d}: {np.sum(a[i][1] > 0.1):5d} / {np.sum(b[i][1] > 0.1):5d}")
print(f"  the end:  {np.sum(a[-1][1] > 0.1):5d} / {np.sum(b[-1][1] > 0.1):5d}"
      f" of {a[-1][1].size}")
ha, hb = history(kept), history(updated)
line = []
for lo, hi in ((4, 6), (6, 8), (8, 12), (12, 16), (16, 20)):
    sa = (ha["time_s"] >= lo) & (ha["time_s"] < hi)
    sb = (hb["time_s"] >= lo) & (hb["time_s"] < hi)
    line.append(f"{lo}-{hi} s {np.median(ha['kinetic_energy_J'][sa]):.0f}"
                f" / {np.median(hb['kinetic_energy_J'][sb]):.0f}")
print("kinetic energy, median J (kept / updated): " + "; ".join(line))
print(f"steps: {int(ha['step'][-1])} / {int(hb['step'][-1])}")
X = h5py.File(kept + "/model.h5", "r")["particles/position"][:]
Xb = h5py.File(updated + "/model.h5", "r")["particles/position"][:]
if X.shape != Xb.shape or not np.allclose(X, Xb):
    print("the two runs' particles differ: no comparison by particle")
    sys.exit(0)
far = (X[:, 0] < 4) & (X[:, 2] < 3)
print(f"median speed of the soil far from the footing (x < 4 m, z < 3 m,"
      f" {far.sum()} particles), mm/s, kept / updated (* an update within"
      f" the half second before):")
updated_at = hb["time_s"][1:][np.diff(hb["reference_updates"]) > 0]
row = []
for i in range(min(len(a), len(b))):
    t = b[i][0]
    since = (updated_at >= t - 0.5) & (updated_at < t)
    row.append(f"{t:5.1f} s {1e3 * np.median(np.linalg.norm(a[i][3][far], axis=1)):5.2f}"
               f" / {1e3 * np.median(np.linalg.norm(b[i][3][far], axis=1)):5.2f}"
               f"{'*' if since.any() else ' '}")
for k in range(0, len(row), 4):
    print("  " + "   ".join(row[k:k + 4]))
extra = (b[-1][1] > 0.1) & (a[-1][1] <= 0.1)
moved = np.linalg.norm(b[-1][2], axis=1)
print(f"damaged only with updates: {extra.sum()} particles; how far they moved"
      f" (quartiles, m): {np.percentile(moved[extra], [25, 50, 75]).round(4)}"
      f"; all particles: {np.percentile(moved, [25, 50, 75]).round(4)}")
H, _, _ = np.histogram2d(X[extra, 0], X[extra, 2], bins=[10, 5],
                         range=[[0, 20], [0, 10]])
print("where (reference x in 2 m bins from 0 to 20 m, rows z from the top):")
for j in range(4, -1, -1):
    print(f"  z {2 * j:2d}-{2 * j + 2:2d} m: " +
          " ".join(f"{int(H[i, j]):4d}" for i in range(10)))
PY

"""The geostatic stage of cases/geostatic_column.yaml against the closed
form of a level elastic column (test_geostatic.sh): the frame at t = 0
carries sigma_v = -rho g (H - z) and sigma_h = K0 sigma_v with zero
displacements, and the loading stage that follows keeps the column at rest.
With K0 given (geostatic.k0: the stresses of level ground set first) the
layers hold that K0 instead of the elastic one.
usage: check_geostatic.py OUTDIR [K0]"""
import sys

import h5py
import numpy as np

RHO, G, H = 1880.0, 9.81, 4.0
K, MU = 27.4e6, 9.15e6
NU = (3 * K - 2 * MU) / (2 * (3 * K + MU))
K0 = float(sys.argv[2]) if len(sys.argv) > 2 else NU / (1 - NU)
SETTLEMENT = RHO * G * H * H / (2 * (K + 4 * MU / 3))  # of the top, m

failures = 0


def check(ok, text):
    global failures
    print(("ok: " if ok else "FAIL: ") + text)
    failures += not ok


out = sys.argv[1]
with h5py.File(out + "/model.h5", "r") as m, h5py.File(out + "/results.h5", "r") as r:
    x = m["particles/position"][:]
    volume = m["particles/volume"][:]
    names = sorted(r["frames"].keys())
    first, last = r["frames"][names[0]], r["frames"][names[-1]]
    stress = first["stress"][:]
    z = x[:, 2]
    vertical = -RHO * G * (H - z)
    scale = RHO * G * H
    # Equilibrium of the whole column: the integral of sigma_zz is the
    # weight times H/2, to the stage's residual (1e-4) with a margin.
    total = -(stress[:, 2] * volume).sum() / (RHO * G * volume.sum() * H / 2)
    check(abs(total - 1) <= 1e-3, f"integral of sigma_zz / (W H / 2) = {total:.6f} (1 within 1e-3)")
    # Layer means below the top half metre (where sigma -> 0 and the ratio
    # means nothing): sigma_zz within 0.5% of rho g H of the closed form,
    # sigma_xx / sigma_zz within 1% of K0 (nodal stresses of irregular
    # particles scatter pointwise; their means do not).
    worst_v = worst_h = 0.0
    for low in np.arange(0.0, H - 0.5, 0.5):
        layer = (z >= low) & (z < low + 0.5)
        worst_v = max(worst_v, abs((stress[layer, 2] - vertical[layer]).mean()) / scale)
        ratio = (stress[layer, 0] / stress[layer, 2]).mean()
        worst_h = max(worst_h, abs(ratio / K0 - 1))
    check(worst_v <= 5e-3, f"layer means of sigma_zz within {worst_v:.2e} of rho g H (5e-3)")
    check(worst_h <= 1e-2, f"layer means of sigma_xx / sigma_zz within {worst_h:.2e} of K0 = {K0:.5f} (1e-2)")
    rms = np.sqrt((((stress[:, 2] - vertical) / scale) ** 2).mean())
    check(rms <= 0.03, f"pointwise rms of sigma_zz {rms:.4f} of rho g H (0.03)")
    check(np.abs(first["displacement"][:]).max() == 0.0, "the displacements start at zero")
    drift = np.abs(last["displacement"][:]).max()
    check(drift <= 1e-3 * SETTLEMENT,
          f"the loading stage stays at rest: |u| {drift:.2e} m at the end, "
          f"1e-3 of the geostatic settlement {SETTLEMENT:.2e} m")
    residual = r.attrs["geostatic_residual"]
    check(0 < residual <= 1e-4 and r.attrs["geostatic_steps"] > 0,
          f"geostatic_residual {residual:.3g}, {r.attrs['geostatic_steps']} steps")
sys.exit(1 if failures else 0)

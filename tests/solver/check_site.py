"""The layered column of cases/layered_column.yaml against closed forms
(test_site.sh; issue 22, point 4). Three soils (sand 0-2 m, clay 2-3.5 m,
fill 3.5-6 m):
  compression OUTDIR TOLERANCE: 100 kPa on the top, rollers on the sides:
    the top settles q sum(h_i / M_i), M = K + 4 mu / 3; prints the error.
  geostatic OUTDIR LEVEL [K0]: the column under its weight with the water
    table at LEVEL (m, or "a,bx,by": the plane a + bx x + by y): the frame at
    t = 0 holds the effective
    sigma'_v = -sum(rho g h) + u, u = gamma_w (LEVEL - z), and
    sigma'_h / sigma'_v the layer's K0 (elastic nu / (1 - nu), or K0 given).
usage: check_site.py compression OUTDIR TOLERANCE | geostatic OUTDIR LEVEL [K0]"""
import sys

import h5py
import numpy as np

G, GAMMA_W = 9.81, 1000.0 * 9.81
# name: bottom, top (m), density, saturated density (kg/m^3), K, mu (Pa)
SOILS = {"sand": (0.0, 2.0, 1900.0, 2050.0, 40.0e6, 20.0e6),
         "clay": (2.0, 3.5, 1700.0, 1800.0, 10.0e6, 3.0e6),
         "fill": (3.5, 6.0, 1800.0, 2000.0, 20.0e6, 8.0e6)}
H, Q = 6.0, 100.0e3
failures = 0


def check(ok, text):
    global failures
    print(("ok: " if ok else "FAIL: ") + text)
    failures += not ok


def effective_vertical(z, level):
    """sigma'_v at height z: the column's weight above, less u."""
    total = 0.0
    for bottom, top, rho, rho_sat, _, _ in SOILS.values():
        low = max(bottom, z)
        if top <= low:
            continue
        wet = max(0.0, min(top, level) - low)
        total += G * (rho_sat * wet + rho * (top - low - wet))
    return -total + GAMMA_W * max(0.0, level - z)


def soil_at(z):
    for name, (bottom, top, *_) in SOILS.items():
        if bottom <= z < top:
            return name
    return "fill"


mode, out = sys.argv[1], sys.argv[2]
with h5py.File(out + "/model.h5", "r") as m, h5py.File(out + "/results.h5", "r") as r:
    x = m["particles/position"][:]
    names = [n.decode() if isinstance(n, bytes) else n for n in m["volumes/name"][:]]
    check(sorted(names) == sorted(SOILS), f"model.h5 names the volumes {names}")
    owner = m["particles/physical_volume"][:]
    inside = [soil_at(z) for z in x[:, 2]]
    away = np.array([min(abs(z - 2.0), abs(z - 3.5)) > 1e-9 for z in x[:, 2]])
    agree = np.mean([names[o] == s for o, s, a in zip(owner, inside, away) if a])
    check(agree == 1.0, f"every particle off an interface carries its layer's volume ({agree:.3f})")
    frames = sorted(r["frames"].keys())
    z = x[:, 2]
    if mode == "compression":
        tolerance = float(sys.argv[3])
        u = r["frames"][frames[-1]]["displacement"][:]
        top = z > H - 1e-9
        exact = -Q * sum((t - b) / (K + 4 * mu / 3) for b, t, _, _, K, mu in SOILS.values())
        error = u[top, 2].mean() / exact - 1
        print(f"settlement {-u[top, 2].mean():.6f} m, closed form {-exact:.6f} m, error {error:+.4f}")
        check(abs(error) <= tolerance, f"the top's settlement within {tolerance} of q sum(h / M)")
        stress = r["frames"][frames[-1]]["stress"][:]
        mean = stress[:, 2].mean()
        check(abs(mean / -Q - 1) <= 5e-3, f"mean sigma_zz {mean:.0f} Pa within 0.5% of -q")
    else:
        plane = [float(v) for v in sys.argv[3].split(",")] + [0.0, 0.0]
        levels = plane[0] + plane[1] * x[:, 0] + plane[2] * x[:, 1]
        k0 = float(sys.argv[4]) if len(sys.argv) > 4 else None
        stress = r["frames"][frames[0]]["stress"][:]
        scale = -effective_vertical(0.0, plane[0])
        worst_v = worst_h = 0.0
        for low in np.arange(0.0, H, 0.5):
            band = (z >= low) & (z < low + 0.5)
            expected = np.array([effective_vertical(t, h) for t, h in zip(z[band], levels[band])])
            worst_v = max(worst_v, abs((stress[band, 2] - expected).mean()) / scale)
            # K0 off the interfaces by more than a kernel support and a
            # cell (0.6 m at 0.25 m): nearer, the shape functions, smooth
            # across the interface, blend the layers' strains (the sand
            # 0.3-0.5 m below the soft clay 2.7-2.9% off)
            clear = band & np.array([min(abs(t - 2.0), abs(t - 3.5)) > 0.6 for t in z])
            if clear.sum() == 0 or low + 0.5 > H - 0.5:
                continue  # the top half metre: sigma -> 0, the ratio means nothing
            name = soil_at(low + 0.25)
            K, mu = SOILS[name][4], SOILS[name][5]
            nu = (3 * K - 2 * mu) / (2 * (3 * K + mu))
            expected_k0 = k0 if k0 else nu / (1 - nu)
            ratio = (stress[clear, 0] / stress[clear, 2]).mean()
            worst_h = max(worst_h, abs(ratio / expected_k0 - 1))
        # 2%: the interface cells carry one soil's density and stiffness over
        # both sides (measured 1.5% at 0.25 m spacing beside the sand-clay
        # interface, 0.4% elsewhere)
        check(worst_v <= 0.02,
              f"layer means of sigma'_zz within {worst_v:.2e} of sigma'_v at the base ({scale:.0f} Pa; 0.02)")
        check(worst_h <= 0.02, f"layer means of sigma'_xx / sigma'_zz within {worst_h:.2e} of K0 (0.02)")
sys.exit(1 if failures else 0)

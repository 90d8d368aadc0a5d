# Taylor's stability number for phi = 0 by the circle method (the method of
# his chart): N_s = c / (F gamma H) = the largest M / (R L) over circular
# slip surfaces (M: the moment of the sliding mass's weight about the
# centre, per unit gamma; R L: the arc's radius times its length), for a
# slope of angle beta and height H = 1 on a firm base at its toe (no soil
# in front of the toe or below it): the reference of test_fos.sh's
# undrained 60-degree slope (docs/fos.md). Brute force over circles through
# a point of the face and one of the crest; a minute for three angles.
# Usage: /usr/bin/python3 scripts/taylor_circle.py 90 60
# (prints N_s 0.2605 at 90 degrees, Taylor's 0.261, H_c = 3.838 c / gamma;
# 0.1906 at 60 degrees, Taylor's 0.191)
import numpy as np, sys
def ground(x, H, run):
    return np.where(x <= 0, 0.0, np.where(x >= run, H, H * x / max(run, 1e-12)))
def stability_number(beta_deg, H=1.0, back=4.0, n=400):
    run = H / np.tan(np.radians(beta_deg)) if beta_deg < 90 else 0.0
    best = 0.0
    x1s = np.linspace(0.0, run, 21) if run > 0 else np.array([0.0])
    for x1 in x1s:                       # exit on the face (or the toe)
        z1 = float(ground(np.array([x1]), H, run)[0])
        for x2 in np.linspace(run + 0.02 * H, run + back * H, 80):  # entry on the crest
            # circles through (x1, z1) and (x2, H): centre on the bisector
            mx, mz = 0.5 * (x1 + x2), 0.5 * (z1 + H)
            dx, dz = x2 - x1, H - z1
            nx, nz = -dz, dx                 # bisector direction (up-left)
            norm = np.hypot(nx, nz); nx, nz = nx / norm, nz / norm
            for t in np.linspace(-0.2 * H, 4 * H, 120):
                xc, zc = mx + t * nx, mz + t * nz
                R = np.hypot(x1 - xc, z1 - zc)
                x = np.linspace(x1, x2, n)
                inside = R * R - (x - xc) ** 2
                if np.any(inside < -1e-12):
                    continue
                arc = zc - np.sqrt(np.maximum(inside, 0.0))
                g = ground(x, H, run)
                h = g - arc
                if np.any(h < -1e-9 * H) or np.any(arc < -1e-9 * H):
                    continue                 # above the ground, or below the base
                W = np.trapz(h, x)
                M = np.trapz(h * (x - xc), x)
                if W <= 0 or M <= 0:
                    continue
                a1 = np.arctan2(x1 - xc, zc - z1); a2 = np.arctan2(x2 - xc, zc - H)
                L = R * abs(a2 - a1)
                Ns = M / (R * L)             # c / (F gamma H) with H = 1
                best = max(best, Ns)
    return best
for beta in map(float, sys.argv[1:]):
    Ns = stability_number(beta)
    print(f"beta {beta:5.1f}: N_s = {Ns:.4f}, 1/N_s = {1/Ns:.3f}")

#!/usr/bin/env python3
# Limit-equilibrium slope stability for 2D sections (circular slip surfaces):
# Bishop simplified (iterated) and Spencer, any number of soil layers, an
# optional phreatic line with hydrostatic pore pressure and ponded water on
# the face. An independent reference for geoscni's strength-reduction FS.
# Python 3 + numpy only.
#
# Usage:
#   /usr/bin/python3 scripts/slope_limit_equilibrium.py CASE.json [--spencer]
#   /usr/bin/python3 scripts/slope_limit_equilibrium.py --selftest [--spencer] [NAME_PART]
# --selftest runs every scripts/slope_cases/*.json (optionally only those whose
# file name contains NAME_PART) and compares with the references they carry.
# --spencer also runs a Spencer search (slower; Spencer on the Bishop circle is
# always printed).
#
# Case file (JSON; any consistent units, y up):
#   ground     [[x, y], ...] surface polyline, x increasing (either facing)
#   layers     top to bottom: {"name", "top": polyline or null (= ground),
#              "c", "phi" (deg), "gamma" (above water), "gamma_sat"}; a point
#              belongs to the lowest layer whose top is above it
#   base       elevation of a firm base no circle may cross (default min ground)
#   phreatic   optional polyline; u = gamma_w (z_w - y) below it; where it is
#              above the ground the water stands on the face (ponded water)
#   gamma_w    (default 9.81); slices (default 60)
#   search     optional {"exit_range": [x0, x1], "entry_range": [x0, x1],
#              "n": 24, "n_angle": 12, "restarts": 4}; or "circle":
#              {"xc", "yc", "R"} to evaluate one circle only
#   references [{"value", "what"}], check {"value", "tol"} (relative, Bishop)
#   variants   [{"name", ...overrides..., "references", "check"}]
# Sign convention: internally the slope rises to the right (mass moves to -x);
# a section descending to the right is mirrored and reported back unmirrored.
import glob, json, math, os, sys, time
import numpy as np

def at(poly, x):                       # polyline elevation, flat beyond ends
    return np.interp(x, poly[:, 0], poly[:, 1])

class Section:
    def __init__(self, d):
        g = np.array(d["ground"], float)
        self.mirror = g[0, 1] > g[-1, 1]
        def P(a):
            a = np.array(a, float)
            if self.mirror:
                a = a[::-1].copy(); a[:, 0] *= -1.0
            return a
        self.ground = P(d["ground"])
        self.layers = []
        for L in d["layers"]:
            top = P(L["top"]) if L.get("top") is not None else self.ground
            self.layers.append((top, float(L["c"]), math.tan(math.radians(L["phi"])),
                                float(L["gamma"]), float(L.get("gamma_sat", L["gamma"]))))
        self.pw = P(d["phreatic"]) if d.get("phreatic") else None
        self.gw = float(d.get("gamma_w", 9.81))
        self.base = float(d.get("base", self.ground[:, 1].min()))
        self.n = int(d.get("slices", 60))
        self.x0, self.x1 = self.ground[0, 0], self.ground[-1, 0]
        self.scale = self.ground[:, 1].max() - self.base + 1e-12

    def zw(self, x):
        return at(self.pw, x) if self.pw is not None else np.full_like(x, -np.inf)

    def slices(self, xc, yc, R, xa, xb):
        """Slice data for the arc between exit xa and entry xb, or None if the
        arc leaves the ground or crosses the base."""
        xs = np.linspace(xa, xb, self.n + 1)
        xm = 0.5 * (xs[:-1] + xs[1:]); b = xs[1] - xs[0]
        yb = yc - np.sqrt(np.maximum(R * R - (xm - xc) ** 2, 0.0))
        g = at(self.ground, xm)
        tol = 1e-6 * self.scale
        ys = yc - np.sqrt(np.maximum(R * R - (xs[1:-1] - xc) ** 2, 0.0))
        if np.any(yb > g + tol) or np.any(ys > at(self.ground, xs[1:-1]) + tol):
            return None
        low = yc - R if xa <= xc <= xb else min(yb[0], yb[-1])
        if low < self.base - tol:
            return None
        # layer tops clipped to the ground and made non-increasing downwards
        T = [g]
        for top, *_ in self.layers[1:]:
            T.append(np.minimum(at(top, xm), T[-1]))
        zw = self.zw(xm)
        W = np.zeros_like(xm); c = np.zeros_like(xm); tphi = np.zeros_like(xm)
        for k, (_, ck, tk, gk, gsk) in enumerate(self.layers):
            hi = T[k]
            lo = np.maximum(yb, T[k + 1]) if k + 1 < len(T) else yb
            h = np.maximum(hi - lo, 0.0)
            wet = np.clip(np.minimum(hi, zw) - lo, 0.0, h)   # below the water
            W += b * (gk * (h - wet) + gsk * wet)
            on = yb <= hi + tol                              # base in layer k
            c = np.where(on, ck, c); tphi = np.where(on, tk, tphi)
        W += b * self.gw * np.maximum(zw - g, 0.0)            # ponded water column
        u = self.gw * np.maximum(zw - yb, 0.0)
        # hydrostatic thrust of the pond on the vertical end faces of the
        # water column (exact equivalent of the water pressure on the face)
        Fh = np.zeros_like(xm); py = np.zeros_like(xm)
        for i, xe, sgn in ((0, xa, 1.0), (-1, xb, -1.0)):
            ge = at(self.ground, xe); d = max(at(self.pw, xe) - ge, 0.0) if self.pw is not None else 0.0
            Fh[i] += sgn * 0.5 * self.gw * d * d; py[i] = ge + d / 3.0
        return dict(xm=xm, yb=yb, b=b, W=W, c=c, tphi=tphi, u=u, Fh=Fh, py=py,
                    sina=(xm - xc) / R, cosa=(yc - yb) / R, xc=xc, yc=yc, R=R)

def bishop(s, F=1.0):
    """Bishop simplified (moment about the centre, vertical slice equilibrium):
    F = sum[(c b + (W - u b) tan phi) / m_a] / [sum W sin a + sum Fh (y_F - y_c) / R],
    m_a = cos a + sin a tan phi / F, iterated to convergence."""
    drive = np.sum(s["W"] * s["sina"]) + np.sum(s["Fh"] * (s["py"] - s["yc"])) / s["R"]
    if drive <= 0:
        return math.inf
    res = s["c"] * s["b"] + (s["W"] - s["u"] * s["b"]) * s["tphi"]
    for _ in range(200):
        m = s["cosa"] + s["sina"] * s["tphi"] / F
        if m.min() < 0.05:                  # unrealistic steep exit (m_alpha)
            return math.inf
        Fn = np.sum(res / m) / drive
        if abs(Fn - F) < 1e-9 * F:
            return Fn
        F = Fn
    return F

def spencer(s, F0):
    """Spencer: parallel interslice resultants at angle theta. Per slice (force
    along the base, Mohr-Coulomb on the base):
      Q = [W sin a - Fh cos a - (c l + (W cos a + Fh sin a - u l) tan phi)/F]
          / [cos(theta - a) - sin(theta - a) tan phi / F]
    with sum Q = 0 (forces) and sum Q cos(theta - a) + sum Fh (y_F - y_b)/R = 0
    (moments about the centre). Solved by damped Newton on (F, theta)."""
    W, sa, ca, tp, Fh = s["W"], s["sina"], s["cosa"], s["tphi"], s["Fh"]
    l = s["b"] / ca; ext = np.sum(Fh * (s["py"] - s["yb"])) / s["R"]; sc = np.sum(W)
    def r(v):
        F, th = v
        den = np.cos(th - np.arcsin(sa)) - np.sin(th - np.arcsin(sa)) * tp / F
        if F <= 0 or den.min() < 0.05:
            return None
        Q = (W * sa - Fh * ca - (s["c"] * l + (W * ca + Fh * sa - s["u"] * l) * tp) / F) / den
        return np.array([Q.sum(), np.sum(Q * np.cos(th - np.arcsin(sa))) + ext]) / sc
    v = np.array([F0, 0.0]); f = r(v)
    if f is None:
        return math.nan
    for _ in range(60):
        if np.abs(f).max() < 1e-10:
            return v[0]
        J = np.empty((2, 2)); h = (1e-7 * v[0], 1e-7)
        for j in range(2):
            w = v.copy(); w[j] += h[j]; fj = r(w)
            if fj is None:
                return math.nan
            J[:, j] = (fj - f) / h[j]
        try:
            step = np.linalg.solve(J, -f)
        except np.linalg.LinAlgError:
            return math.nan
        lam = 1.0
        while lam > 1e-4:
            w = v + lam * step; fw = r(w)
            if fw is not None and np.abs(fw).max() < np.abs(f).max():
                v, f = w, fw; break
            lam *= 0.5
        else:
            return math.nan
    return v[0] if np.abs(f).max() < 1e-7 else math.nan

def circle(sec, xa, xb, psi):
    """Circle through the ground points at xa (exit) and xb (entry) whose arc
    subtends 2 psi: centre on the chord's perpendicular bisector."""
    ya, yb = at(sec.ground, xa), at(sec.ground, xb)
    dx, dy = xb - xa, yb - ya; ch = math.hypot(dx, dy)
    t, R = 0.5 * ch / math.tan(psi), 0.5 * ch / math.sin(psi)
    xc, yc = 0.5 * (xa + xb) - t * dy / ch, 0.5 * (ya + yb) + t * dx / ch
    return xc, yc, R

def fs_of(sec, p, method="bishop"):
    xa, xb, psi = p
    if not (sec.x0 <= xa < xb <= sec.x1) or not (0.01 < psi < 1.55):
        return math.inf, None
    xc, yc, R = circle(sec, xa, xb, psi)
    if at(sec.ground, xa) > yc or at(sec.ground, xb) > yc:   # lower arc only
        return math.inf, None
    s = sec.slices(xc, yc, R, xa, xb)
    if s is None:
        return math.inf, None
    F = bishop(s)
    if method == "spencer" and math.isfinite(F):
        F = spencer(s, F); F = F if math.isfinite(F) else math.inf
    return F, s

def nelder_mead(f, x0, steps, iters=300, tol=1e-7):
    """Plain Nelder-Mead (reflection 1, expansion 2, contraction 1/2, shrink 1/2)."""
    X = [np.array(x0, float)] + [np.array(x0, float) + np.eye(len(x0))[i] * steps[i]
                                  for i in range(len(x0))]
    Y = [f(x) for x in X]
    for _ in range(iters):
        o = np.argsort(Y); X = [X[i] for i in o]; Y = [Y[i] for i in o]
        if math.isfinite(Y[-1]) and Y[-1] - Y[0] < tol:
            break
        m = np.mean(X[:-1], axis=0); xr = m + (m - X[-1]); yr = f(xr)
        if yr < Y[0]:
            xe = m + 2 * (m - X[-1]); ye = f(xe)
            X[-1], Y[-1] = (xe, ye) if ye < yr else (xr, yr)
        elif yr < Y[-2]:
            X[-1], Y[-1] = xr, yr
        else:
            xk = m + 0.5 * (X[-1] - m); yk = f(xk)
            if yk < Y[-1]:
                X[-1], Y[-1] = xk, yk
            else:
                X = [X[0] + 0.5 * (x - X[0]) for x in X]; Y = [Y[0]] + [f(x) for x in X[1:]]
    i = int(np.argmin(Y))
    return X[i], Y[i]

def search(sec, opt, method="bishop", start=None):
    """Grid over exit point, entry point and half-angle, then Nelder-Mead
    from the best few distinct starts; returns (F, params, slices)."""
    n, na = int(opt.get("n", 24)), int(opt.get("n_angle", 12))
    def rng(key):
        r = opt.get(key, [sec.x0, sec.x1])
        return sorted(-v for v in r) if sec.mirror and key in opt else r
    ea, eb = rng("exit_range"), rng("entry_range")
    f = lambda p: fs_of(sec, p, method)[0]
    def pts(r):                         # grid plus the ground vertices in range
        v = sec.ground[:, 0]
        return np.unique(np.r_[np.linspace(r[0], r[1], n), v[(v >= r[0]) & (v <= r[1])]])
    if start is None:
        cand = []
        for xa in pts(ea):
            for xb in pts(eb):
                if xb - xa > 1e-3 * sec.scale:
                    for psi in np.radians(np.linspace(8, 85, na)):
                        F = f((xa, xb, psi))
                        if math.isfinite(F):
                            cand.append((F, (xa, xb, psi)))
        cand.sort(key=lambda t: t[0]); starts = []
        for F, p in cand:
            if all(abs(p[0] - q[0]) + abs(p[1] - q[1]) > 0.1 * sec.scale for q in starts):
                starts.append(p)
            if len(starts) >= int(opt.get("restarts", 4)):
                break
    else:
        starts = [start]
    steps = [(ea[1] - ea[0]) / n + 1e-3, (eb[1] - eb[0]) / n + 1e-3, math.radians(4)]
    best = (math.inf, None)
    for p in starts:
        for _ in range(3):                     # restart NM at its own optimum
            p, F = nelder_mead(f, p, steps)
        if F < best[0]:
            best = (F, tuple(p))
    if best[1] is None:
        return math.inf, None, None
    return best[0], best[1], fs_of(sec, best[1], method)[1]

def run(d, spencer_search=False):
    sec = Section(d); t0 = time.time(); out = {}
    if "circle" in d:                           # one given circle
        c = d["circle"]; xc = -c["xc"] if sec.mirror else c["xc"]
        xs = np.linspace(sec.x0, sec.x1, 20001)  # its ground crossings, by a fine scan
        arc = c["yc"] - np.sqrt(np.maximum(c["R"] ** 2 - (xs - xc) ** 2, 0))
        inside = xs[(c["R"] ** 2 > (xs - xc) ** 2) & (arc < at(sec.ground, xs))]
        s = sec.slices(xc, c["yc"], c["R"], inside[0], inside[-1]) if len(inside) > 1 else None
        out["bishop"] = bishop(s) if s else math.inf
    else:
        out["bishop"], p, s = search(sec, d.get("search", {}))
        if spencer_search and s is not None:
            out["spencer_min"], _, _ = search(sec, d.get("search", {}), "spencer", start=p)
    if s is not None and math.isfinite(out["bishop"]):
        out["spencer"] = spencer(s, out["bishop"])
        m = -1.0 if sec.mirror else 1.0
        xa, xb = s["xm"][0] - s["b"] / 2, s["xm"][-1] + s["b"] / 2
        low = s["yc"] - s["R"] if xa <= s["xc"] <= xb else min(at(sec.ground, xa), at(sec.ground, xb))
        out["circle"] = dict(xc=m * s["xc"], yc=s["yc"], R=s["R"], exit=sorted([m * xa, m * xb]), lowest=low)
    out["time"] = time.time() - t0
    return out

def report(name, d, out):
    c = out.get("circle")
    line = f"{name}: Bishop FS = {out['bishop']:.3f}"
    if "spencer" in out:
        sp = out["spencer"]
        line += ", Spencer (same circle) = " + (f"{sp:.3f}" if math.isfinite(sp) else "no solution")
    if "spencer_min" in out:
        line += f", Spencer min = {out['spencer_min']:.3f}"
    print(line + f"   [{out['time']:.1f} s]")
    if c:
        print(f"    circle xc={c['xc']:.3f} yc={c['yc']:.3f} R={c['R']:.3f}; ground "
              f"x={c['exit'][0]:.3f}..{c['exit'][1]:.3f}; lowest y={c['lowest']:.3f}")
    for r in d.get("references", []):
        print(f"    ref {r['value']:.3f}  ({r['what']}): Bishop {100 * (out['bishop'] / r['value'] - 1):+.1f}%")
    chk = d.get("check")
    if chk:
        ok = abs(out["bishop"] / chk["value"] - 1) <= chk["tol"]
        print(f"    check {chk['value']:.3f} +-{100 * chk['tol']:.0f}%: {'PASS' if ok else 'FAIL'}")
        return ok
    return True

def cases_of(d):
    base = {k: v for k, v in d.items() if k != "variants"}
    if not d.get("variants"):
        return [(d.get("name", "case"), base)]
    return [(f"{d.get('name', 'case')} | {v['name']}", {**base, **v}) for v in d["variants"]]

def main(argv):
    sp = "--spencer" in argv; args = [a for a in argv if not a.startswith("--")]
    if "--selftest" in argv:
        here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "slope_cases")
        files = sorted(f for f in glob.glob(os.path.join(here, "*.json"))
                       if not args or args[0] in os.path.basename(f))
    else:
        files = args
    if not files:
        print(__doc__ or "usage: see the header of this file"); return 2
    ok, t0 = True, time.time()
    for fn in files:
        with open(fn) as fh:
            d = json.load(fh)
        print(f"== {os.path.basename(fn)}: {d.get('description', '')}")
        for name, c in cases_of(d):
            ok &= report(name, c, run(c, sp))
    print(f"total {time.time() - t0:.1f} s; {'all checks passed' if ok else 'SOME CHECKS FAILED'}")
    return 0 if ok else 1

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

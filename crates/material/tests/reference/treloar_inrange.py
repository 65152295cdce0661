"""Reference objective of the in-range Ogden fit on Treloar's (1944) data.

Throwaway script (not run by the tests) for the provenance of the numbers
in crates/material/src/drucker_windows.rs' Treloar test. It minimises the
same objective as `material-fit`: residuals
(T_fit - T) / max(|T|, 1 % of the mode's largest |T|), all mode weights 1,
cost = 1/2 sum r^2, Ogden in the Abaqus convention, under Drucker's condition
(log-strain Hessian positive definite: det >= 0 and trace >= 0 in the
expanded form 4 (s1 s2 + s1 s3 + s2 s3), 2 (s1 + s2 + 2 s3)) on the default
windows: each mode's data range extended to lambda = 1, BT down to 0.6,
on a geometric grid of GRID stretches per window. Each random start is
polished by SLSQP twice: from the draw, and from scipy's bounded
trust-region least squares (trf) optimum of the draw.

Usage: python treloar_inrange.py TERMS STARTS [MU_BOUND]
(MU_BOUND: |mu_i| bound in units of the largest measured stress, default 1e3)
"""

import sys

import numpy as np
import scipy
from scipy.optimize import least_squares, minimize, nnls

GRID = 120
LATERAL = {"UT": 0.5, "PT": 1.0, "BT": 2.0}


def load(path):
    rows = [
        line.strip().split(",")
        for line in open(path)
        if line.strip() and not line.startswith("#") and not line.startswith("mode")
    ]
    data = {}
    for mode, stretch, stress in rows:
        data.setdefault(mode, []).append((float(stretch), float(stress)))
    return {m: np.array(v) for m, v in data.items()}


def principal(mode, lam):
    if mode == "UT":
        return lam, lam**-0.5, lam**-0.5
    if mode == "PT":
        return lam, np.ones_like(lam), 1.0 / lam
    return lam, lam, lam**-2.0


def main():
    terms, starts = int(sys.argv[1]), int(sys.argv[2])
    mu_bound = float(sys.argv[3]) if len(sys.argv) > 3 else 1e3
    data = load("../../../../data/reference/treloar_1944.csv")
    scale = max(np.abs(v[:, 1]).max() for v in data.values())
    pts = []
    for mode in ("UT", "PT", "BT"):
        lam, t = data[mode][:, 0], data[mode][:, 1]
        denom = np.maximum(np.abs(t), 0.01 * np.abs(t).max())
        pts.append((LATERAL[mode], lam, t / scale, scale / denom / scale))
    windows = {
        m: (min(1.0, data[m][:, 0].min()), max(1.0, data[m][:, 0].max())) for m in data
    }
    windows["BT"] = (min(0.6, windows["BT"][0]), windows["BT"][1])
    grid = []
    for mode, (lo, hi) in windows.items():
        lam = np.exp(np.linspace(np.log(lo), np.log(hi), GRID))
        grid.append(np.stack(principal(mode, lam)))
    grid = np.concatenate(grid, axis=1)  # 3 x G

    def stresses_basis(alpha):
        cols = []
        for c, lam, t, g in pts:
            cols.append(
                np.stack(
                    [2.0 / a * (lam ** (a - 1.0) - lam ** (-c * a - 1.0)) for a in alpha],
                    axis=1,
                )
            )
        return np.concatenate(cols)

    target = np.concatenate([p[2] for p in pts])
    gain = np.concatenate([p[3] for p in pts]) * scale

    def residuals(x):
        mu, alpha = x[:terms], x[terms:]
        return gain * (stresses_basis(alpha) @ mu - target)

    def cost(x):
        r = residuals(x)
        return 0.5 * r @ r

    def drucker(x):
        mu, alpha = x[:terms], x[terms:]
        s = [np.sum(mu[:, None] * grid[j][None, :] ** alpha[:, None], axis=0) for j in range(3)]
        det = 4.0 * (s[0] * s[1] + s[0] * s[2] + s[1] * s[2])
        trace = 2.0 * (s[0] + s[1] + 2.0 * s[2])
        return np.concatenate([det, trace])

    rng = np.random.default_rng(12345)
    best = (np.inf, None)
    found = []
    for k in range(starts):
        alpha = rng.uniform(-6.0, 8.0, terms)
        alpha[np.abs(alpha) < 0.3] = 0.3
        b = stresses_basis(alpha) * gain[:, None]
        mu, _ = nnls(b, gain * target)
        x0 = np.concatenate([mu, alpha])
        # Each start twice: SLSQP from the draw, and SLSQP from the
        # unconstrained trust-region optimum of the draw (SLSQP alone
        # stalls in Ogden's narrow valleys).
        bounds = [(-mu_bound, mu_bound)] * terms + [(-30.0, 30.0)] * terms
        lo, hi = np.array(bounds).T
        x1 = least_squares(
            residuals, np.clip(x0, lo, hi), bounds=(lo, hi), method="trf",
            xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=20000,
        ).x
        for start in (x0, x1):
            res = minimize(
                cost,
                start,
                method="SLSQP",
                constraints=[{"type": "ineq", "fun": drucker}],
                bounds=bounds,
                options={"maxiter": 2000, "ftol": 1e-14},
            )
            feasible = drucker(res.x).min() >= -1e-12
            if feasible and np.isfinite(res.fun):
                found.append(res.fun)
                if res.fun < best[0]:
                    best = (res.fun, res.x)
    print(f"scipy {scipy.__version__} numpy {np.__version__}")
    print(f"mu bound {mu_bound} x largest stress ({mu_bound * scale:.3e} Pa)")
    print(f"ogden-{terms}: {starts} starts, {len(found)} feasible, grid {GRID}/window {windows}")
    print(f"best cost {best[0]:.9f}")
    print("mu_pa", list(best[1][:terms] * scale))
    print("alpha", list(best[1][terms:]))
    print("sorted costs", sorted(found)[:10])


if __name__ == "__main__":
    main()

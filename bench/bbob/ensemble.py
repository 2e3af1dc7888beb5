"""A gradient-free ensemble Langevin minimiser (a numpy prototype for the
bbob harness of run.py; not part of the hrla package).

    minimize(fun, bounds, maxfun, rng, **options) -> (x_best, f_best, calls)

N particles x_i in the box. Each iteration evaluates U at all N points
(N calls of the point-wise ``fun``), then moves every particle by one step
of Langevin dynamics in the ensemble's whitened frame, with a gradient
that no call provides: the gradient of a quadratic model of U fitted to
the ensemble's own values.

Frame: m = mean_i x_i, C = cov_i x_i + 1e-12 tr(C)/d I = L L^T (Cholesky;
``precondition=False``: L = sqrt(tr C / d) I, scale only), z = L^-1 (x - m).

Values: U_i replaced by the normal scores s_i = Phi^-1((r_i + 1/2)/n) of
their ranks r_i among the points of the fit (``values="raw"``: U_i - mean),
so that every decision is invariant to monotone transforms of U.

Temperature, scale-free: V = a s with a = kappa / sd(s over the current
generation), kappa = r sqrt(d/2) (default r = 6). At a quadratic V = c |z|^2
/ 2 centred on the ensemble, sd(V) = c sqrt(d/2), so c = r; off centre
sd(V) grows, c falls and the ensemble spreads as it travels.

Gradient (derivative-free; the second-order Stein / statistical
linearisation of ensemble Kalman methods): V ~ c0 + g^T z + z^T H z / 2,
least squares over the last ``memory`` = 2 generations (re-whitened in the
current frame; older points with some |z_k| > 1e3 left out), the
isotropic part of H free, the rest shrunk by a ridge (``ridge`` = 0.05 n
on standardised features); grad V(z_i) = g + H z_i. ALDI's finite-N
correction adds -(d + 1)/N z_i to it (``aldi=False``: not). ``psd=True``
clips H's negative eigenvalues to 0 (measured worse; off).

Step, in z, V at unit temperature (spec section 4 with a = b = alpha =
beta = 1): HRLA's exact Ornstein-Uhlenbeck step with the frozen gradient,
step h_k = min(1, eta / lambda_max(H)) (eta = 1; a Newton-sized step on the
model; h = 1 where H has no positive eigenvalue), velocities y kept per
particle in whitened units; the drift capped at 3 sqrt(d) whitened units.
For the isotropic model the per-step variance ratio is (1 - h c)^2 + 2 h =
2 / r: r = 6 contracts the ensemble 3x in variance per step on a quadratic.
``order=1``: overdamped (ALDI / EKS), z' = z - h_k grad + sqrt(2 h_k) xi.
Positions are clipped to the box (``boundary="reflect"``: reflected).

Population: N0 = max(8, ceil(pop_factor P / memory) + 1), P = 1 + d + d(d+1)/2
the model's parameters (d = 5: 12; d = 10: 34).

Cooling when stalled (``cool``, default 1: off): after every
``cool_every`` = 10 iterations of a restart without a new best, kappa is
multiplied by ``cool``, so an ensemble held wide by a rugged landscape's
rank noise contracts (``cool=1.5``: the variant ``ensemble-n2cool15``).

Restarts (IPOP): when sd(U) over a generation falls below 1e-12 (|mean U| +
1e-300), the ensemble's largest standard deviation below 1e-12 of the box,
or the restart's best has not improved (relatively, by 1e-12) for 20 + 3 d
iterations, the ensemble is drawn again uniformly in the box with N
doubled (``restarts=False``: never). The best point ever evaluated is
returned. Nothing depends on ``maxfun`` but the stop, so a run's first
B calls are those of any longer run with the same seed.
"""

import math

import numpy as np
from scipy.special import ndtri


class _Done(Exception):
    pass


def hrla_coefficients(h, alpha=1.0, beta=1.0, b=1.0, a=1.0):
    """The folded constants of spec section 4 (float64, cancellations
    avoided as in bench/peers/peers.py)."""
    gamma, sx2, sy2 = a / b, beta / a, alpha / b
    u = alpha * h
    om = -math.expm1(-u)
    e = 1.0 - om
    if u < 0.5:
        br, q, term = 0.0, 0.0, 1.0
        for n in range(1, 40):
            term *= u / n
            if n >= 3:
                br += (-1) ** n * (4.0 - 2.0 ** n) * term
            if n >= 2:
                q -= (-1) ** n * term
    else:
        br = 2.0 * u - e * e + 4.0 * e - 3.0
        q = u + math.expm1(-u)
    q /= alpha
    cgx = beta * h + (gamma / alpha) * q
    cgy = (gamma / alpha) * om
    syy = sy2 * (-math.expm1(-2.0 * u)) / alpha
    sxy = sy2 * om * om / alpha ** 2
    schur = (sy2 / alpha ** 3) * (br - om ** 3 / (1.0 + e)) + 2.0 * sx2 * h
    lyy = math.sqrt(syy)
    return dict(e=e, c1=om / alpha, cgx=cgx, cgy=cgy, lyy=lyy, lxy=sxy / lyy, lxx=math.sqrt(schur))


def _quad_features(z):
    n, d = z.shape
    iu = np.triu_indices(d)
    outer = z[:, :, None] * z[:, None, :]
    q = outer[:, iu[0], iu[1]] * np.where(iu[0] == iu[1], 0.5, 1.0)
    iso = 0.5 * np.sum(z * z, axis=1, keepdims=True)
    return np.hstack([np.ones((n, 1)), z, iso, q]), iu


def fit_quadratic(z, v, ridge):
    """g, H of V ~ c0 + g^T z + z^T H z / 2; the isotropic part of H free,
    the rest shrunk by ridge (relative to the features' scale)."""
    n, d = z.shape
    A, iu = _quad_features(z)
    p = A.shape[1]
    free = 2 + d
    scale = np.sqrt(np.mean(A * A, axis=0)) + 1e-300
    As = A / scale
    lam = ridge * n
    pen = np.zeros(p)
    pen[free:] = math.sqrt(lam)
    As = np.vstack([As, np.diag(pen)[free:]])
    vs = np.concatenate([v, np.zeros(p - free)])
    theta, *_ = np.linalg.lstsq(As, vs, rcond=None)
    theta /= scale
    g = theta[1:1 + d]
    c_iso = theta[1 + d]
    Hq = np.zeros((d, d))
    Hq[iu] = theta[free:]
    H = Hq + Hq.T  # off-diagonal: coefficient of z_k z_l; diagonal: 2 * (1/2 coeff)
    H[np.diag_indices(d)] *= 0.5
    H += c_iso * np.eye(d)
    return g, H


def minimize(fun, bounds, maxfun, rng=None, *, n0=None, r=6.0, h=1.0, eta=1.0, order=2,
             precondition=True, restarts=True, values="rank", memory=2, ridge=0.05,
             aldi=True, pop_factor=1.0, boundary="clip", psd=False, cool=1.0, cool_every=10):
    rng = np.random.default_rng(rng)
    bounds = np.asarray(bounds, dtype=float)
    lo, hi = bounds[:, 0], bounds[:, 1]
    d = lo.size
    width = hi - lo
    p = 1 + d + d * (d + 1) // 2
    if n0 is None:
        n0 = max(8, int(math.ceil(pop_factor * p / memory)) + 1)
    kappa = r * math.sqrt(d / 2.0)
    best = [math.inf, None]
    calls = [0]

    def evaluate(X):
        out = np.empty(len(X))
        for k, x in enumerate(X):
            if calls[0] >= maxfun:
                raise _Done
            calls[0] += 1
            f = float(fun(x))
            out[k] = f
            if f < best[0]:
                best[0], best[1] = f, x.copy()
        return out

    def reflect(X):
        if boundary == "clip":
            return np.clip(X, lo, hi)
        Y = (X - lo) % (2 * width)
        Y = np.where(Y > width, 2 * width - Y, Y)
        return np.clip(lo + Y, lo, hi)

    n = n0
    stall_limit = 20 + 3 * d
    try:
        while calls[0] < maxfun:
            X = lo + width * rng.random((n, d))
            Yv = np.zeros((n, d))
            hist = []
            run_best, since = math.inf, 0
            kappa_run = kappa
            while True:
                F = evaluate(X)
                hist.append((X.copy(), F))
                hist = hist[-memory:]
                # stopping tests of this restart
                fb = F.min()
                if not math.isfinite(run_best) or fb < run_best - 1e-12 * abs(run_best):
                    run_best, since = fb, 0
                else:
                    since += 1
                    if since % cool_every == 0:
                        kappa_run *= cool
                sdF = F.std()
                m = X.mean(axis=0)
                C = np.cov(X.T).reshape(d, d)
                tr = np.trace(C)
                if restarts and (sdF <= 1e-12 * (abs(F.mean()) + 1e-300)
                                 or math.sqrt(max(np.max(np.diag(C)), 0.0)) < 1e-12 * width.max()
                                 or since > stall_limit):
                    break
                if not np.isfinite(tr) or tr <= 0:
                    if restarts:
                        break
                    tr = 1e-300
                C = C + 1e-12 * tr / d * np.eye(d)
                if precondition:
                    try:
                        L = np.linalg.cholesky(C)
                    except np.linalg.LinAlgError:
                        w, Q = np.linalg.eigh(C)
                        L = Q * np.sqrt(np.maximum(w, 1e-300))
                else:
                    L = math.sqrt(tr / d) * np.eye(d)
                Xa = np.vstack([hx for hx, _ in hist])
                Fa = np.concatenate([hf for _, hf in hist])
                Za = np.linalg.solve(L, (Xa - m).T).T
                if values == "rank":
                    ranks = np.argsort(np.argsort(Fa, kind="stable"), kind="stable")
                    s = ndtri((ranks + 0.5) / len(Fa))
                else:
                    s = Fa - Fa.mean()
                cur = s[-n:]
                sd = cur.std()
                if not sd > 0:
                    sd = 1.0
                Va = (kappa_run / sd) * s
                # older points far outside the current frame say nothing local
                near = np.all(np.isfinite(Za), axis=1) & (np.max(np.abs(Za), axis=1) < 1e3)
                near[-n:] = True
                if not np.all(np.isfinite(Za[-n:])):
                    break  # a degenerate frame: restart
                g, H = fit_quadratic(Za[near], Va[near], ridge)
                if not (np.all(np.isfinite(g)) and np.all(np.isfinite(H))):
                    break
                if psd:  # the model's negative curvature (noise, mostly) clipped to 0
                    w, Q = np.linalg.eigh(H)
                    H = (Q * np.maximum(w, 0.0)) @ Q.T
                Z = Za[-n:]
                G = g + Z @ H.T
                if aldi:
                    G = G - (d + 1) / n * Z
                lmax = float(np.linalg.eigvalsh(H)[-1])
                hk = min(h, eta / lmax) if eta and lmax > 0 else h
                co = hrla_coefficients(hk)
                # cap the drift at 3 sqrt(d) whitened units a step
                gn = np.linalg.norm(G, axis=1, keepdims=True)
                cap = 3.0 * math.sqrt(d) / max(co["cgx"], 1e-300)
                G = np.where(gn > cap, G * (cap / np.maximum(gn, 1e-300)), G)
                xi1 = rng.standard_normal((n, d))
                if order == 2:
                    xi2 = rng.standard_normal((n, d))
                    Zn = Z + co["c1"] * Yv - co["cgx"] * G + co["lxy"] * xi1 + co["lxx"] * xi2
                    Yv = co["e"] * Yv - co["cgy"] * G + co["lyy"] * xi1
                else:
                    Zn = Z - hk * G + math.sqrt(2.0 * hk) * xi1
                X = reflect(m + Zn @ L.T)
            n *= 2
    except _Done:
        pass
    return best[1], best[0], calls[0]

#!/usr/bin/env python3
"""Benchmark problems of the quality benchmark: value, analytic gradient,
known global minimum U*, a box [lo, hi] per coordinate and a start
distribution (uniform in the box).

    python functions.py --check     # gradients against central differences,
                                    # U(x*) = U*, and a summary of the problems

Every problem is a `Problem`; `make(name, d)` builds one, `PROBLEMS` lists the
names in the benchmark's order and `DIMS[name]` the dimensions each is run in
(the Lennard-Jones cluster only in its own dimension 21). Only numpy is
needed. Written like the crate's potentials (`core/src/potential/`): where a
textbook form cancels near the minimum (1 - cos, 1 - exp) it is computed as
2 sin^2 and expm1, so gaps of 1e-6 and below are meaningful.
"""

import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Optional, Tuple

import numpy as np

PI = math.pi
TWO_PI = 2.0 * math.pi

# The Styblinski–Tang minimum per coordinate (the root of 4x^3 - 32x + 5 = 0
# in (-3, -2.5)) and its value, as in core/src/potential/styblinski_tang.rs.
ST_XSTAR = -2.903534027771178
ST_USTAR_PER_COORD = -39.16616570377142

# LJ7: Wales & Doye (1997) give -16.505384 (six decimals). The value used for
# the gap is the same minimum to full double precision, found by
# `--check` (Newton's method from the pentagonal bipyramid below) and
# agreeing with Wales & Doye to all their digits.
LJ7_USTAR_WALES_DOYE = -16.505384
LJ7_USTAR = -16.505384168012217


@dataclass(frozen=True)
class Problem:
    """A box-constrained minimisation problem with a known minimum."""

    name: str
    d: int
    lo: float  # every coordinate lies in [lo, hi]
    hi: float
    fstar: float  # U* (the global minimum)
    # vg(x, need_grad) -> (U(x), grad U(x) or None); x a float64 1-D array.
    vg: Callable[[np.ndarray, bool], Tuple[float, Optional[np.ndarray]]]
    xstar: Optional[np.ndarray] = None  # a global minimiser, where one is known in closed form

    def value(self, x):
        return self.vg(np.asarray(x, dtype=float), False)[0]

    def grad(self, x):
        return self.vg(np.asarray(x, dtype=float), True)[1]

    def value_and_grad(self, x):
        return self.vg(np.asarray(x, dtype=float), True)

    @property
    def lower(self):
        return np.full(self.d, self.lo)

    @property
    def upper(self):
        return np.full(self.d, self.hi)

    @property
    def bounds(self):
        """[(lo, hi)] * d, as scipy takes them."""
        return [(self.lo, self.hi)] * self.d

    @property
    def width(self):
        return self.hi - self.lo

    def start(self, rng):
        """One start point, uniform in the box, from a numpy Generator."""
        return rng.uniform(self.lo, self.hi, size=self.d)


# ---------------------------------------------------------------------------
# The potentials. Each takes (x, need_grad) and returns (U, grad or None).
# ---------------------------------------------------------------------------

def _rastrigin_paper(x, need_grad):
    # D + |x|^2 - sum cos(2 pi x_i) = |x|^2 + 2 sum sin^2(pi x_i)
    s = np.sin(PI * x)
    u = float(x @ x + 2.0 * (s @ s))
    if not need_grad:
        return u, None
    return u, 2.0 * x + TWO_PI * np.sin(TWO_PI * x)


def _rastrigin(x, need_grad):
    # 10 D + sum (x_i^2 - 10 cos(2 pi x_i)) = |x|^2 + 20 sum sin^2(pi x_i)
    s = np.sin(PI * x)
    u = float(x @ x + 20.0 * (s @ s))
    if not need_grad:
        return u, None
    return u, 2.0 * x + 20.0 * PI * np.sin(TWO_PI * x)


def _ackley(x, need_grad):
    # 20 (1 - exp(-0.2 r)) + e (1 - exp(-q)), r = |x|/sqrt(D),
    # q = (1/D) sum (1 - cos 2 pi x_i) = (2/D) sum sin^2(pi x_i)
    d = x.size
    s = np.sin(PI * x)
    r = math.sqrt(float(x @ x) / d)
    q = 2.0 * float(s @ s) / d
    u = -20.0 * math.expm1(-0.2 * r) - math.e * math.expm1(-q)
    if not need_grad:
        return u, None
    radial = 4.0 * math.exp(-0.2 * r) / (d * r) if r > 0.0 else 0.0
    wave = TWO_PI * math.e * math.exp(-q) / d
    # sin(2 pi x) = 2 sin(pi x) cos(pi x); the gradient at 0 is 0.
    return u, radial * x + wave * (2.0 * s * np.cos(PI * x))


def _levy(x, need_grad):
    # w_i = 1 + (x_i - 1)/4;
    # sin^2(pi w_1) + sum_{i<D} (w_i - 1)^2 (1 + 10 sin^2(pi w_i + 1))
    #               + (w_D - 1)^2 (1 + sin^2(2 pi w_D))
    w = 1.0 + 0.25 * (x - 1.0)
    dw = w - 1.0
    s1 = math.sin(PI * w[0])
    wi, di = w[:-1], dw[:-1]
    si = np.sin(PI * wi + 1.0)
    bi = 1.0 + 10.0 * si * si
    sd = math.sin(TWO_PI * w[-1])
    bd = 1.0 + sd * sd
    u = s1 * s1 + float(di @ (di * bi)) + dw[-1] * dw[-1] * bd
    if not need_grad:
        return u, None
    g = np.empty_like(x)  # dU/dw, then / 4
    g[:-1] = 2.0 * di * bi + di * di * 20.0 * PI * si * np.cos(PI * wi + 1.0)
    g[-1] = 2.0 * dw[-1] * bd + dw[-1] * dw[-1] * 2.0 * sd * math.cos(TWO_PI * w[-1]) * TWO_PI
    g[0] += TWO_PI * s1 * math.cos(PI * w[0])
    return u, 0.25 * g


def _rosenbrock(x, need_grad):
    # sum_{i<D} 100 (x_{i+1} - x_i^2)^2 + (1 - x_i)^2
    a, b = x[:-1], x[1:]
    t = b - a * a
    o = 1.0 - a
    u = float(100.0 * (t @ t) + o @ o)
    if not need_grad:
        return u, None
    g = np.zeros_like(x)
    g[:-1] = -400.0 * a * t - 2.0 * o
    g[1:] += 200.0 * t
    return u, g


def _styblinski_tang(x, need_grad):
    # (1/2) sum x^4 - 16 x^2 + 5 x
    x2 = x * x
    u = 0.5 * float(np.sum(x2 * x2 - 16.0 * x2 + 5.0 * x))
    if not need_grad:
        return u, None
    return u, 2.0 * x2 * x - 16.0 * x + 2.5


_GRIEWANK_CACHE = {}


def _griewank_scale(d):
    s = _GRIEWANK_CACHE.get(d)
    if s is None:
        s = 1.0 / np.sqrt(np.arange(1, d + 1, dtype=float))
        _GRIEWANK_CACHE[d] = s
    return s


def _griewank(x, need_grad):
    # 1 + sum x^2/4000 - prod cos(x_i / sqrt(i))
    sc = _griewank_scale(x.size)
    z = x * sc
    c = np.cos(z)
    p = float(np.prod(c))
    u = float(x @ x) / 4000.0 + (1.0 - p)
    if not need_grad:
        return u, None
    # prod_{j != i} cos z_j from prefix and suffix products (no division by a
    # cosine that may be 0).
    pre = np.concatenate(([1.0], np.cumprod(c[:-1])))
    suf = np.concatenate((np.cumprod(c[::-1][:-1])[::-1], [1.0]))
    return u, x / 2000.0 + np.sin(z) * sc * pre * suf


_ZAKHAROV_CACHE = {}


def _zakharov(x, need_grad):
    # sum x^2 + s^2 + s^4, s = sum 0.5 i x_i (i from 1)
    c = _ZAKHAROV_CACHE.get(x.size)
    if c is None:
        c = 0.5 * np.arange(1, x.size + 1, dtype=float)
        _ZAKHAROV_CACHE[x.size] = c
    s = float(c @ x)
    s2 = s * s
    u = float(x @ x) + s2 + s2 * s2
    if not need_grad:
        return u, None
    return u, 2.0 * x + (2.0 * s + 4.0 * s2 * s) * c


_LJ_N = 7
_LJ_I, _LJ_J = np.triu_indices(_LJ_N, k=1)


def _lj7(x, need_grad):
    # sum_{i<j} 4 (r^-12 - r^-6) over the 7 atoms x.reshape(7, 3)
    p = x.reshape(_LJ_N, 3)
    diff = p[_LJ_I] - p[_LJ_J]  # (21, 3)
    r2 = np.einsum("ij,ij->i", diff, diff)
    inv6 = 1.0 / (r2 * r2 * r2)
    u = float(4.0 * np.sum(inv6 * (inv6 - 1.0)))
    if not need_grad:
        return u, None
    # dU/d(diff) = diff * (24 r^-6 - 48 r^-12) / r^2
    coef = (24.0 * inv6 - 48.0 * inv6 * inv6) / r2
    f = diff * coef[:, None]
    g = np.zeros((_LJ_N, 3))
    np.add.at(g, _LJ_I, f)
    np.add.at(g, _LJ_J, -f)
    return u, g.ravel()


def _lj7_bipyramid():
    """The pentagonal bipyramid (the LJ7 global minimum's shape), before
    polishing: a ring of 5 atoms at radius 1.12/(2 sin 36 deg), two on the axis."""
    a = 1.12
    rr = a / (2.0 * math.sin(PI / 5.0))
    h = math.sqrt(max(a * a - rr * rr, 0.0))
    pts = [[rr * math.cos(2 * PI * k / 5), rr * math.sin(2 * PI * k / 5), 0.0] for k in range(5)]
    pts += [[0.0, 0.0, h], [0.0, 0.0, -h]]
    return np.array(pts).ravel()


# ---------------------------------------------------------------------------
# Problems of other classes than the textbook ones: a plateau-and-valley
# landscape, a deceptive one, a larger cluster and a least-squares fit.
# ---------------------------------------------------------------------------

# Plateau and valley: per coordinate, 1 on flat plateaus with narrow
# Gaussian valleys at the integers -4..4 of depth 1 (down to 0) and one of
# depth 2 at 3 (down to -1): U* = -d at x = (3, ..., 3); the valleys' tails
# meet at exp(-50), so the gradient is 0 to double precision between them.
PLATEAU_CENTRES = np.arange(-4.0, 5.0)
PLATEAU_DEPTHS = np.where(PLATEAU_CENTRES == 3.0, 2.0, 1.0)
PLATEAU_WIDTH = 0.1


def _plateau(x, need_grad):
    z = (x[:, None] - PLATEAU_CENTRES[None, :]) / PLATEAU_WIDTH
    e = PLATEAU_DEPTHS[None, :] * np.exp(-0.5 * z * z)
    u = float(x.size - np.sum(e))
    if not need_grad:
        return u, None
    return u, np.sum(e * z, axis=1) / PLATEAU_WIDTH


# Schwefel's function, the deceptive classic: the best basin per coordinate
# (x = 420.97, at the box's edge) is far from the second best (x = -302.5).
# The constant is -min_t t sin(sqrt|t|) per coordinate, so U* = 0 to
# rounding; d/dx [x sin sqrt|x|] = sin s + (s / 2) cos s, s = sqrt|x|.
SCHWEFEL_PER_COORD = 418.98288727243374
SCHWEFEL_XSTAR = 420.9687463599821


def _schwefel(x, need_grad):
    s = np.sqrt(np.abs(x))
    sn = np.sin(s)
    u = float(SCHWEFEL_PER_COORD * x.size - np.sum(x * sn))
    if not need_grad:
        return u, None
    return u, -(sn + 0.5 * s * np.cos(s))


def _lj(n):
    ii, jj = np.triu_indices(n, k=1)

    def vg(x, need_grad):
        p = x.reshape(n, 3)
        diff = p[ii] - p[jj]
        r2 = np.einsum("ij,ij->i", diff, diff)
        inv6 = 1.0 / (r2 * r2 * r2)
        u = float(4.0 * np.sum(inv6 * (inv6 - 1.0)))
        if not need_grad:
            return u, None
        coef = (24.0 * inv6 - 48.0 * inv6 * inv6) / r2
        f = diff * coef[:, None]
        g = np.zeros((n, 3))
        np.add.at(g, ii, f)
        np.add.at(g, jj, -f)
        return u, g.ravel()

    return vg


# LJ13: the Mackay icosahedron, -44.326801 (Wales & Doye 1997).
LJ13_USTAR = -44.326801

# A least-squares fit of two Gaussian peaks A exp(-(t - c)^2 / (2 w^2)) to
# noiseless data at t = 0, 1, ..., 100 from (A, c, w) = (5, 30, 3) and
# (2, 70, 10): parameters on different scales (amplitudes ~1, centres ~10^2,
# widths ~10) in one box [0.5, 100]; U* = 0 (also at the peaks swapped).
FIT_T = np.arange(0.0, 101.0)
FIT_TRUE = np.array([5.0, 30.0, 3.0, 2.0, 70.0, 10.0])


def _fit_model(p):
    out = np.zeros_like(FIT_T)
    parts = []
    for k in range(2):
        a, c, w = p[3 * k: 3 * k + 3]
        z = (FIT_T - c) / w
        e = np.exp(-0.5 * z * z)
        out += a * e
        parts.append((a, w, z, e))
    return out, parts


FIT_DATA = _fit_model(FIT_TRUE)[0]


def _gauss_fit(x, need_grad):
    m, parts = _fit_model(x)
    r = m - FIT_DATA
    u = float(r @ r)
    if not need_grad:
        return u, None
    g = np.empty(6)
    for k, (a, w, z, e) in enumerate(parts):
        g[3 * k] = 2.0 * (r @ e)
        g[3 * k + 1] = 2.0 * (r @ (a * e * z / w))
        g[3 * k + 2] = 2.0 * (r @ (a * e * z * z / w))
    return u, g


# The rotated problems: U(c + Q (x - c)) with Q the committed orthogonal
# matrix rotation10.txt (numpy default_rng(12345), QR of a standard normal
# 10 x 10 matrix, signs fixed by R's diagonal) and c the minimiser, so that
# the minimum stays where it was, inside the box.
ROTATION10 = np.loadtxt(Path(__file__).resolve().parent / "rotation10.txt")


def _rotated(vg, c):
    def rvg(x, need_grad):
        z = c + ROTATION10 @ (x - c)
        u, g = vg(z, need_grad)
        return u, (None if g is None else ROTATION10.T @ g)

    return rvg


# ---------------------------------------------------------------------------
# The registry.
# ---------------------------------------------------------------------------

PROBLEMS = [
    "rastrigin_paper",
    "rastrigin",
    "ackley",
    "levy",
    "rosenbrock",
    "styblinski_tang",
    "griewank",
    "zakharov",
    "lj7",
]
ROTATED = ["rot_" + n for n in PROBLEMS if n != "lj7"]
NEW = ["plateau", "schwefel", "lj13", "gauss_fit"]
PROBLEMS = PROBLEMS + ROTATED + NEW

DIMS = {name: (2, 10) for name in PROBLEMS}
DIMS["lj7"] = (21,)
DIMS.update({name: (10,) for name in ROTATED})
DIMS.update({"plateau": (10,), "schwefel": (10,), "lj13": (39,), "gauss_fit": (6,)})


def make(name, d):
    """The problem `name` in dimension `d` (lj7: d must be 21)."""
    if name not in DIMS:
        raise KeyError(f"unknown problem {name!r}; known: {', '.join(PROBLEMS)}")
    if name == "lj7":
        if d != 21:
            raise ValueError("lj7 exists only in dimension 21 (7 atoms in 3-D)")
        return Problem("lj7", 21, -1.5, 1.5, LJ7_USTAR, _lj7, None)
    if DIMS[name] != (2, 10) and d not in DIMS[name]:
        raise ValueError(f"{name} exists only in dimension(s) {DIMS[name]}")
    if name.startswith("rot_"):
        base = make(name[4:], d)
        return Problem(name, d, base.lo, base.hi, base.fstar, _rotated(base.vg, base.xstar), base.xstar)
    if name == "plateau":
        return Problem(name, d, -5.0, 5.0, -float(d), _plateau, np.full(d, 3.0))
    if name == "schwefel":
        return Problem(name, d, -500.0, 500.0, 0.0, _schwefel, np.full(d, SCHWEFEL_XSTAR))
    if name == "lj13":
        return Problem(name, 39, -2.0, 2.0, LJ13_USTAR, _lj(13), None)
    if name == "gauss_fit":
        return Problem(name, 6, 0.5, 100.0, 0.0, _gauss_fit, FIT_TRUE.copy())
    if d < 2:
        raise ValueError("d must be at least 2")
    zero, one = np.zeros(d), np.ones(d)
    table = {
        "rastrigin_paper": (-5.12, 5.12, 0.0, _rastrigin_paper, zero),
        "rastrigin": (-5.12, 5.12, 0.0, _rastrigin, zero),
        "ackley": (-32.768, 32.768, 0.0, _ackley, zero),
        "levy": (-10.0, 10.0, 0.0, _levy, one),
        "rosenbrock": (-5.0, 10.0, 0.0, _rosenbrock, one),
        "styblinski_tang": (-5.0, 5.0, ST_USTAR_PER_COORD * d, _styblinski_tang, np.full(d, ST_XSTAR)),
        "griewank": (-600.0, 600.0, 0.0, _griewank, zero),
        "zakharov": (-5.0, 10.0, 0.0, _zakharov, zero),
    }
    lo, hi, fstar, vg, xstar = table[name]
    return Problem(name, d, lo, hi, fstar, vg, xstar)


def all_problems(dims=(2, 10), names=None):
    """Every (name, d) of the benchmark: each textbook problem in each of
    `dims`, lj7 in its own dimension 21 whatever `dims` says."""
    out = []
    for name in names or PROBLEMS:
        if name == "lj7":
            out.append(make("lj7", 21))
        elif DIMS[name] != (2, 10):
            out.extend(make(name, d) for d in DIMS[name])
        else:
            out.extend(make(name, d) for d in dims)
    return out


# ---------------------------------------------------------------------------
# Self-test.
# ---------------------------------------------------------------------------

def _textbook_value(name, x):
    """The textbook formula of each value, written plainly (with the
    cancellations), to check the rewritten forms above."""
    d = x.size
    i = np.arange(1, d + 1)
    if name == "rastrigin_paper":
        return d + x @ x - np.sum(np.cos(TWO_PI * x))
    if name == "rastrigin":
        return 10 * d + np.sum(x * x - 10 * np.cos(TWO_PI * x))
    if name == "ackley":
        return (-20 * np.exp(-0.2 * np.sqrt(x @ x / d))
                - np.exp(np.sum(np.cos(TWO_PI * x)) / d) + 20 + math.e)
    if name == "levy":
        w = 1 + (x - 1) / 4
        return (np.sin(PI * w[0]) ** 2
                + np.sum((w[:-1] - 1) ** 2 * (1 + 10 * np.sin(PI * w[:-1] + 1) ** 2))
                + (w[-1] - 1) ** 2 * (1 + np.sin(TWO_PI * w[-1]) ** 2))
    if name == "rosenbrock":
        return np.sum(100 * (x[1:] - x[:-1] ** 2) ** 2 + (1 - x[:-1]) ** 2)
    if name == "styblinski_tang":
        return 0.5 * np.sum(x ** 4 - 16 * x ** 2 + 5 * x)
    if name == "griewank":
        return 1 + np.sum(x * x) / 4000 - np.prod(np.cos(x / np.sqrt(i)))
    if name == "zakharov":
        s = np.sum(0.5 * i * x)
        return np.sum(x * x) + s ** 2 + s ** 4
    if name == "lj7":
        p = x.reshape(7, 3)
        u = 0.0
        for a in range(7):
            for b in range(a + 1, 7):
                r = np.linalg.norm(p[a] - p[b])
                u += 4 * (r ** -12 - r ** -6)
        return u
    raise KeyError(name)


def _central_difference(p, x):
    g = np.empty_like(x)
    for i in range(x.size):
        h = 1e-6 * max(1.0, abs(x[i]))
        xp, xm = x.copy(), x.copy()
        xp[i] += h
        xm[i] -= h
        xp2, xm2 = x.copy(), x.copy()
        xp2[i] += 2.0 * h
        xm2[i] -= 2.0 * h
        # Fourth-order central difference (Ackley's kink at 0 makes the
        # second-order one too coarse 1e-4 away from it).
        g[i] = (8.0 * (p.value(xp) - p.value(xm)) - (p.value(xp2) - p.value(xm2))) / (12.0 * h)
    return g


def _lj7_polished_minimum():
    """Newton's method (finite-difference Hessian of the analytic gradient,
    with the 6 zero modes handled by a least-squares solve) from the
    pentagonal bipyramid: the LJ7 minimum to full precision."""
    p = make("lj7", 21)
    x = _lj7_bipyramid()
    for _ in range(50):
        g = p.grad(x)
        if np.max(np.abs(g)) < 1e-13:
            break
        hcols = []
        for i in range(21):
            e = np.zeros(21)
            e[i] = 1e-6
            hcols.append((p.grad(x + e) - p.grad(x - e)) / 2e-6)
        hess = np.array(hcols).T
        step = np.linalg.lstsq(0.5 * (hess + hess.T), -g, rcond=1e-10)[0]
        x = x + step
    return p.value(x), float(np.max(np.abs(p.grad(x)))), x


def check(verbose=True):
    """Values against the plain textbook formulas and gradients against
    (fourth-order) central differences at random points of each box (and
    near the minimiser), U(x*) = U*, grad U(x*) = 0, and the LJ7 minimum
    polished from the bipyramid equal to U*; returns the number of
    failures."""
    rng = np.random.default_rng(12345)
    failures = 0
    rows = []
    for p in all_problems(dims=(2, 10)) + [make(n, 3) for n in PROBLEMS if DIMS[n] == (2, 10)]:
        worst = 0.0
        pts = [p.start(rng) for _ in range(8)]
        if p.xstar is not None:
            pts += [p.xstar + 0.01 * rng.standard_normal(p.d), p.xstar + 1e-4 * rng.standard_normal(p.d)]
        if p.name == "lj7":
            pts += [_lj7_bipyramid() + 0.05 * rng.standard_normal(21)]
        for x in pts:
            u, g = p.value_and_grad(x)
            if not math.isclose(u, p.value(x), rel_tol=0, abs_tol=0):
                failures += 1
                print(f"FAIL {p.name} d={p.d}: value and value_and_grad disagree", file=sys.stderr)
            if p.name.startswith("rot_"):
                base = make(p.name[4:], p.d)
                ref = float(_textbook_value(base.name, base.xstar + ROTATION10 @ (x - base.xstar)))
            elif p.name in NEW:
                ref = u  # one formula only: the gradient check below is the test
            else:
                ref = float(_textbook_value(p.name, x))
            if abs(u - ref) > 1e-12 * max(1.0, abs(ref)):
                failures += 1
                print(f"FAIL {p.name} d={p.d}: U = {u!r} but the textbook formula gives {ref!r}", file=sys.stderr)
            fd = _central_difference(p, x)
            err = float(np.max(np.abs(fd - g)) / (1.0 + np.max(np.abs(g))))
            worst = max(worst, err)
        ok = worst < 1e-6
        extra = ""
        if p.xstar is not None:
            u0, g0 = p.value_and_grad(p.xstar)
            gap = u0 - p.fstar
            gnorm = float(np.max(np.abs(g0)))
            ok = ok and abs(gap) < 1e-12 * max(1.0, abs(p.fstar)) and gnorm < 1e-9
            extra = f"U(x*) - U* = {gap:.1e}, |grad U(x*)|_inf = {gnorm:.1e}"
        if p.name == "lj7":
            u0, gnorm, _ = _lj7_polished_minimum()
            gap = u0 - p.fstar
            ok = ok and abs(gap) < 1e-12 and gnorm < 1e-9 and round(u0, 6) == LJ7_USTAR_WALES_DOYE
            extra = f"polished bipyramid U = {u0:.15f} (U* = {p.fstar}, Wales & Doye {LJ7_USTAR_WALES_DOYE}), |grad|_inf = {gnorm:.1e}"
        failures += 0 if ok else 1
        rows.append((p.name, p.d, p.lo, p.hi, p.fstar, worst, "ok" if ok else "FAIL", extra))
    if verbose:
        print("| problem | d | box | U* | worst gradient error (rel.) | check | at the minimiser |")
        print("| --- | ---: | --- | ---: | ---: | --- | --- |")
        for name, d, lo, hi, fstar, worst, ok, extra in rows:
            print(f"| {name} | {d} | [{lo}, {hi}] | {fstar:.12g} | {worst:.1e} | {ok} | {extra} |")
        print(f"{failures} failed" if failures else "all gradients and minima check")
    return failures


if __name__ == "__main__":
    if "--check" in sys.argv[1:]:
        sys.exit(1 if check() else 0)
    print(__doc__)

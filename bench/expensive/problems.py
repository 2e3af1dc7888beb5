#!/usr/bin/env python3
"""Three expensive problems as a scipy user writes them: a plain
``fun(x) -> float``, a box per coordinate, and a target value (the value at
which the user would say "found it").

- ``ode``: a Lotka-Volterra parameter fit with ``scipy.integrate.solve_ivp``
  (6 parameters: the four rates and the two initial populations), least
  squares on the logarithms of 21 noisy observations of both species;
- ``peaks``: a least-squares fit of three Gaussian peaks on a constant
  baseline to 201 noisy points (10 parameters on different scales:
  amplitudes in [0, 10], centres in [0, 100], widths in [0.1, 20], the
  baseline in [0, 2]);
- ``lj8``: the energy of a Lennard-Jones cluster of 8 atoms (24
  coordinates in [-1.5, 1.5]; the known minimum -19.821489, Wales and
  Doye 1997).

The data are generated from fixed seeds (numpy ``default_rng``), so every
method sees the same function. ``fstar`` is the best value known, found for
the fits by polishing from the parameters that made the data (``--polish``,
below), and no run of any method in the benchmark went lower; a run reaches
the target when ``fun(x) <= target = fstar + 1e-6 |fstar|``.

    python problems.py            # one call's cost, the value at the truth
    python problems.py --polish peaks,ode   # the fits' fstar (minutes)
"""

import os

for _k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_k, "1")

import argparse
import math
import time
from dataclasses import dataclass
from typing import Callable, Sequence, Tuple

import numpy as np

# The target's relative distance to the best known value.
REL = 1e-6


@dataclass(frozen=True)
class Problem:
    """A problem: ``fun(x) -> float`` on the box ``bounds`` (a pair
    ``(lo_i, hi_i)`` per coordinate), the best known value ``fstar`` and
    the target ``fstar + REL |fstar|``."""

    name: str
    fun: Callable[[np.ndarray], float]
    bounds: Sequence[Tuple[float, float]]
    fstar: float
    truth: np.ndarray  # where the data came from (the fits) or the known minimiser's neighbourhood

    @property
    def d(self) -> int:
        return len(self.bounds)

    @property
    def target(self) -> float:
        return self.fstar + REL * abs(self.fstar)

    @property
    def lo(self) -> np.ndarray:
        return np.array([b[0] for b in self.bounds], dtype=float)

    @property
    def hi(self) -> np.ndarray:
        return np.array([b[1] for b in self.bounds], dtype=float)


# ---------------------------------------------------------------- ODE fit
# Lotka-Volterra, in the logarithms u = log x, v = log y of the populations
# (the populations stay positive whatever the parameters, and the
# integrator works on the scale the data are fitted on):
#   du/dt = alpha - beta e^v,   dv/dt = delta e^u - gamma.
# Parameters p = (alpha, beta, delta, gamma, x0, y0); observations of both
# species at t = 0, 1, ..., 20 with multiplicative noise exp(0.1 N(0, 1)).
ODE_TRUE = np.array([1.0, 0.1, 0.075, 1.5, 10.0, 5.0])
ODE_BOUNDS = [(0.1, 3.0), (0.01, 1.0), (0.01, 1.0), (0.1, 3.0), (1.0, 30.0), (1.0, 30.0)]
ODE_T = np.arange(0.0, 21.0)
# Tight tolerances: a gradient by finite differences (steps ~1e-8 relative)
# needs the solution smooth in the parameters well below the step, and the
# target needs the value to 1e-6 relative.
ODE_RTOL = 1e-10
ODE_ATOL = 1e-10
# A solve that the integrator gives up on (parameters that blow a population
# up to e^700 within the window) is worth this much: far above any fit.
ODE_FAIL = 1e6


def _lv_rhs(t, s, alpha, beta, delta, gamma):
    u, v = s
    return [alpha - beta * math.exp(min(v, 700.0)), delta * math.exp(min(u, 700.0)) - gamma]


def _lv_solve(p):
    from scipy.integrate import solve_ivp

    alpha, beta, delta, gamma, x0, y0 = (float(c) for c in p)
    sol = solve_ivp(_lv_rhs, (ODE_T[0], ODE_T[-1]), [math.log(x0), math.log(y0)], method="DOP853",
                    t_eval=ODE_T, args=(alpha, beta, delta, gamma), rtol=ODE_RTOL, atol=ODE_ATOL)
    if sol.status != 0 or sol.y.shape[1] != len(ODE_T):
        return None
    return sol.y


def _ode_data():
    rng = np.random.default_rng(20240611)
    y = _lv_solve(ODE_TRUE)
    return y + 0.1 * rng.standard_normal(y.shape)


ODE_DATA = _ode_data()


def ode_fun(x):
    """Sum of squared residuals of the log populations."""
    y = _lv_solve(x)
    if y is None or not np.all(np.isfinite(y)):
        return ODE_FAIL
    return float(np.sum((y - ODE_DATA) ** 2))


# ---------------------------------------------------------------- three peaks
PEAKS_T = np.linspace(0.0, 100.0, 201)
# (A, c, w) per peak, then the baseline: two peaks overlapping at 40 and 52
# and a narrow one at 75.
PEAKS_TRUE = np.array([4.0, 40.0, 6.0, 3.0, 52.0, 10.0, 6.0, 75.0, 1.5, 0.5])
PEAKS_BOUNDS = [(0.0, 10.0), (0.0, 100.0), (0.1, 20.0)] * 3 + [(0.0, 2.0)]


def _peaks_model(p):
    out = np.full_like(PEAKS_T, p[9])
    for k in range(3):
        a, c, w = p[3 * k: 3 * k + 3]
        out += a * np.exp(-0.5 * ((PEAKS_T - c) / w) ** 2)
    return out


PEAKS_DATA = _peaks_model(PEAKS_TRUE) + 0.1 * np.random.default_rng(20240612).standard_normal(PEAKS_T.shape)


def peaks_fun(x):
    """Sum of squared residuals."""
    r = _peaks_model(np.asarray(x, dtype=float)) - PEAKS_DATA
    return float(r @ r)


# ---------------------------------------------------------------- LJ8
LJ_N = 8
_II, _JJ = np.triu_indices(LJ_N, k=1)


def lj8_fun(x):
    """4 sum (r^-12 - r^-6) over the pairs."""
    p = np.asarray(x, dtype=float).reshape(LJ_N, 3)
    diff = p[_II] - p[_JJ]
    r2 = np.einsum("ij,ij->i", diff, diff)
    inv6 = 1.0 / (r2 * r2 * r2)
    return float(4.0 * np.sum(inv6 * (inv6 - 1.0)))


# The best values known. The fits': L-BFGS-B then Nelder-Mead, four times
# over, from the parameters that made the data (`--polish`), the lowest
# value any run of any method has found (docs/QUALITY.md, "Expensive
# functions", says how many runs; summarize.py flags a run below it).
ODE_FSTAR = 0.2909183053759802
PEAKS_FSTAR = 1.8968657598679426
LJ8_FSTAR = -19.821489  # Wales & Doye 1997


def make(name):
    if name == "ode":
        return Problem("ode", ode_fun, ODE_BOUNDS, ODE_FSTAR, ODE_TRUE)
    if name == "peaks":
        return Problem("peaks", peaks_fun, PEAKS_BOUNDS, PEAKS_FSTAR, PEAKS_TRUE)
    if name == "lj8":
        return Problem("lj8", lj8_fun, [(-1.5, 1.5)] * (3 * LJ_N), LJ8_FSTAR, np.zeros(3 * LJ_N))
    raise ValueError(f"unknown problem {name!r}; known: {', '.join(PROBLEMS)}")


PROBLEMS = ["ode", "peaks", "lj8"]


def _cost():
    for name in PROBLEMS:
        p = make(name)
        rng = np.random.default_rng(0)
        xs = [p.lo + (p.hi - p.lo) * rng.random(p.d) for _ in range(50)]
        t0 = time.perf_counter()
        vals = [p.fun(x) for x in xs]
        dt = (time.perf_counter() - t0) / len(xs)
        at_truth = p.fun(p.truth) if name != "lj8" else float("nan")
        print(f"{name}: d = {p.d}, {dt * 1e3:.3f} ms per call (random points), f(truth) = {at_truth!r}, "
              f"median f(random) = {np.median(vals):.4g}, fstar = {p.fstar!r}, target = {p.target!r}")


def _polish(name):
    """The fits' best known value: L-BFGS-B then Nelder-Mead, four times
    over, from the parameters that made the data (about 6 minutes for the
    ODE)."""
    from scipy.optimize import minimize

    p = make(name)
    x = p.truth.copy()
    for _ in range(4):
        r = minimize(p.fun, x, method="L-BFGS-B", bounds=p.bounds,
                     options={"ftol": 1e-16, "gtol": 1e-12, "maxiter": 10_000, "maxfun": 100_000})
        r2 = minimize(p.fun, r.x, method="Nelder-Mead", bounds=p.bounds,
                      options={"xatol": 1e-12, "fatol": 1e-16, "maxfev": 20_000})
        x = r2.x if r2.fun < r.fun else r.x
    print(f"{name}: {p.fun(x)!r} at {np.array2string(x, precision=12, separator=', ')}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--polish", default=None, help="comma list of fits (ode, peaks) whose best value to find")
    a = ap.parse_args()
    if a.polish:
        for n in a.polish.split(","):
            _polish(n)
    else:
        _cost()

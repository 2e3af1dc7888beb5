#!/usr/bin/env python3
"""Evaluations to a target on expensive functions: hrla against the peers a
scipy user would pick, every call to ``fun`` counted.

    # from the repository root, with numpy, scipy, cma and hrla installed
    # (run.sh sets that up and runs these), one core per job:
    nice -n 10 python bench/expensive/run.py --out target/expensive/runs.csv \\
        --problems peaks,lj8 --seeds 0-19 --jobs 2
    nice -n 10 python bench/expensive/run.py --out target/expensive/runs.csv --append \\
        --problems ode --seeds 0-9 --jobs 2
    python bench/expensive/summarize.py target/expensive/runs.csv

Problems: problems.py (an ODE fit with solve_ivp, a 10-parameter fit of
three peaks, an 8-atom Lennard-Jones cluster), each a plain
``fun(x) -> float`` with a box and a target.

Methods, each given ``fun`` alone (no gradient; where a method wants one it
takes finite differences, and those calls count too):

  dual-annealing  scipy.optimize.dual_annealing(fun, bounds, maxfun=cap,
                  rng=seed): its defaults (L-BFGS-B local searches with
                  scipy's 2-point differences).
  differential-evolution  scipy.optimize.differential_evolution(fun, bounds,
                  maxiter=10**9, rng=seed): its defaults (best1bin, popsize
                  15, tol 0.01, then an L-BFGS-B polish); it may stop by
                  itself before the cap, as a user would run it.
  ipop-cma-es     cma.fmin2(fun, x0 uniform in the box at each (re)start,
                  sigma0 = 0.3, options {bounds, CMA_stds: hi - lo, seed:
                  seed + 1}, restarts=9, incpopsize=2): IPOP-CMA-ES with
                  each coordinate's initial spread a third of its side.
  hrla            hrla.minimize with its defaults (method "auto"): see
                  hrla_minimize below, the one function that knows which
                  version of the API is installed.

Counting and stopping (the same wrapper for every method): each call of
``fun`` is one evaluation; the call whose value is <= the target records
its index and raises TargetReached, the attempt of call cap + 1 raises
BudgetExhausted; either ends the method and is caught here.

Columns: problem,d,method,seed,cap,reached,evals_to_target,evaluations,best,wall_seconds,note
(evals_to_target empty when the target was not reached; evaluations = calls
made; best = the lowest value seen; note = how hrla was called, or an error
other than the two stops).
"""

import os

for _k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_k, "1")

import argparse
import csv
import inspect
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import counting  # noqa: E402
import problems  # noqa: E402
from counting import BudgetExhausted, int_list  # noqa: E402

COLUMNS = ["problem", "d", "method", "seed", "cap", "reached", "evals_to_target", "evaluations", "best",
           "wall_seconds", "note"]
METHODS = ["hrla", "dual-annealing", "differential-evolution", "ipop-cma-es"]
CAP = 20_000


class TargetReached(Exception):
    """Raised by the call whose value reaches the target."""


class Counted(counting.Counted):
    """``fun`` under the counting and stopping rule of the module's docstring."""

    def __init__(self, fun, target, cap):
        super().__init__(fun, cap)
        self.target = float(target)
        self.best = math.inf
        self.hit = None

    def __call__(self, x, *args):
        if self.hit is not None:
            # A method that swallowed the exception and went on: stop again.
            raise TargetReached
        v = self.evaluate(x)
        if v < self.best:
            self.best = v
        if v <= self.target:
            self.hit = self.calls
            raise TargetReached
        return v


# ------------------------------------------------------------------ hrla

def _has_scipy_api(hrla):
    """Whether ``hrla.minimize`` takes scipy's arguments (``fun(x) -> float``,
    ``jac``, ``maxfun``, ``rng``)."""
    params = inspect.signature(hrla.minimize).parameters
    return all(k in params for k in ("jac", "maxfun", "rng"))


def _forward_differences(fun, x, fx, lo, hi):
    """∇fun(x) by forward differences with scipy's '2-point' step
    ``sqrt(eps) max(1, |x_i|)``, taken inward where the step would leave the
    box: ``D`` calls of ``fun``."""
    g = np.empty_like(x)
    for i in range(x.size):
        h = math.sqrt(np.finfo(float).eps) * max(1.0, abs(x[i]))
        if x[i] + h > hi[i]:
            h = -h
        xh = x.copy()
        xh[i] += h
        g[i] = (fun(xh) - fx) / ((x[i] + h) - x[i])
    return g


def _padded_dim(d, dims):
    """The smallest dimension compiled into ``Auto`` that holds ``d``."""
    for k in sorted(dims):
        if k >= d:
            return k
    raise ValueError(f"no compiled dimension holds {d}")


def hrla_api(d):
    """How :func:`hrla_minimize` calls the installed hrla in dimension ``d``."""
    import hrla

    if _has_scipy_api(hrla):
        return "scipy api"
    dp = _padded_dim(d, hrla.DIMENSIONS)
    return f"batched api, unit box, forward differences{f', padded to D = {dp}' if dp != d else ''}"


def hrla_minimize(fun, bounds, maxfun, target, seed):
    """``hrla.minimize`` with its defaults on a scalar ``fun``.

    With scipy's API (``fun(x) -> float``, ``jac=None`` finite differences
    counted in ``nfev``, ``maxfun``, ``target``, ``rng``) this is one call.
    Before it, ``method="auto"`` takes a batched ``X (N, D) -> (U, G)``, one
    interval for every coordinate and a dimension of its compiled table:
    the function is then run in the unit box (``x = lo + z (hi - lo)``,
    ``∂U/∂z = (hi - lo) ∂U/∂x``), with forward differences (``1 + D``
    calls per point), padded with coordinates it does not depend on
    (gradient 0, no call) up to the next compiled dimension, and with a
    budget of ``maxfun // (1 + D)`` points.
    """
    import hrla

    lo = np.array([b[0] for b in bounds], dtype=float)
    hi = np.array([b[1] for b in bounds], dtype=float)
    if _has_scipy_api(hrla):
        hrla.minimize(fun, list(zip(lo, hi)), jac=None, maxfun=maxfun, target=target, rng=seed)
        return
    d = lo.size
    width = hi - lo
    dp = _padded_dim(d, hrla.DIMENSIONS)

    def batched(Z):
        Z = np.atleast_2d(np.asarray(Z, dtype=float))
        U = np.empty(Z.shape[0])
        G = np.zeros_like(Z)
        for r, z in enumerate(Z):
            x = lo + np.clip(z[:d], 0.0, 1.0) * width
            U[r] = fun(x)
            G[r, :d] = _forward_differences(fun, x, U[r], lo, hi) * width
        return U, G

    hrla.minimize(batched, (0.0, 1.0), dim=dp, method="auto", budget=max(maxfun // (1 + d), 1), seed=seed)


# ------------------------------------------------------------------ peers

def run_dual_annealing(p, f, seed, cap):
    from scipy.optimize import dual_annealing

    dual_annealing(f, p.bounds, maxfun=cap, rng=np.random.default_rng(seed))


def run_differential_evolution(p, f, seed, cap):
    from scipy.optimize import differential_evolution

    differential_evolution(f, p.bounds, maxiter=10**9, rng=np.random.default_rng(seed))


def run_ipop_cma_es(p, f, seed, cap):
    import cma

    rng = np.random.default_rng(seed)
    lo, hi = p.lo, p.hi
    cma.fmin2(
        f,
        lambda: lo + (hi - lo) * rng.random(p.d),
        0.3,
        options={"bounds": [list(lo), list(hi)], "CMA_stds": list(hi - lo), "seed": seed + 1,
                 "verbose": -9, "verb_log": 0, "verb_disp": 0, "maxfevals": cap},
        restarts=9,
        incpopsize=2,
    )


def run_hrla(p, f, seed, cap):
    hrla_minimize(f, p.bounds, cap, p.target, seed)


RUNNERS = {
    "hrla": run_hrla,
    "dual-annealing": run_dual_annealing,
    "differential-evolution": run_differential_evolution,
    "ipop-cma-es": run_ipop_cma_es,
}


def run_one(task):
    name, method, seed, cap = task
    p = problems.make(name)
    f = Counted(p.fun, p.target, cap)
    note = hrla_api(p.d) if method == "hrla" else ""
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            RUNNERS[method](p, f, seed, cap)
        except (TargetReached, BudgetExhausted):
            pass
        except Exception as e:  # a method failing: keep what it found, say so
            note = f"{type(e).__name__}: {e}"
    wall = time.perf_counter() - t0
    return {
        "problem": name, "d": p.d, "method": method, "seed": seed, "cap": cap,
        "reached": int(f.hit is not None),
        "evals_to_target": "" if f.hit is None else f.hit,
        "evaluations": f.calls,
        "best": repr(f.best),
        "wall_seconds": f"{wall:.3f}",
        "note": note,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--problems", default=",".join(problems.PROBLEMS))
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--cap", type=int, default=CAP, help="evaluations at most per run (default %(default)s)")
    ap.add_argument("--append", action="store_true")
    ap.add_argument("--jobs", type=int, default=1)
    args = ap.parse_args(argv)

    names = [s for s in args.problems.split(",") if s]
    methods = [s for s in args.methods.split(",") if s]
    for m in methods:
        if m not in RUNNERS:
            raise SystemExit(f"unknown method {m!r}; known: {', '.join(RUNNERS)}")
    for n in names:
        problems.make(n)
    tasks = [(n, m, s, args.cap) for n in names for s in int_list(args.seeds) for m in methods]

    import cma
    import scipy

    try:
        import hrla
        hv = getattr(hrla, "__version__", "?") + (" (scipy api)" if _has_scipy_api(hrla) else " (batched api)")
    except ImportError:
        hv = "not installed"
    print(f"run.py: {len(tasks)} runs -> {args.out}; python {sys.version.split()[0]}, numpy {np.__version__}, "
          f"scipy {scipy.__version__}, cma {cma.__version__}, hrla {hv}; jobs {args.jobs}", file=sys.stderr)

    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fresh = not (args.append and out.exists() and out.stat().st_size > 0)
    t0 = time.perf_counter()
    with open(out, "w" if fresh else "a", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        if fresh:
            w.writeheader()
        if args.jobs > 1:
            import multiprocessing as mp

            pool = mp.get_context("fork").Pool(args.jobs)
            results = pool.imap_unordered(run_one, tasks, chunksize=1)
        else:
            pool = None
            results = map(run_one, tasks)
        for i, row in enumerate(results, 1):
            w.writerow(row)
            fh.flush()
            print(f"  [{i}/{len(tasks)}, {time.perf_counter() - t0:.0f} s] {row['problem']} {row['method']} "
                  f"seed {row['seed']}: {'reached at ' + str(row['evals_to_target']) if row['reached'] else 'not reached'}"
                  f" ({row['evaluations']} calls, best {float(row['best']):.10g}, {row['wall_seconds']} s)"
                  f"{' ' + row['note'] if row['note'] else ''}", file=sys.stderr, flush=True)
        if pool is not None:
            pool.close()
            pool.join()
    print(f"run.py: done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()

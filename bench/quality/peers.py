#!/usr/bin/env python3
"""Quality benchmark of the peers: what a user would pick instead of hrla to
find a global minimum, run on the problems of functions.py under a strict
evaluation budget, one CSV row per run.

    python peers.py --out target/quality/peers.csv
    python peers.py --out /tmp/q.csv --problems rastrigin,lj7 --d 2 --seeds 0-4 \\
        --budgets 10000 --methods ipop-cma-es

Methods (all with the problem's analytic gradient where they can use one):

  dual-annealing  scipy.optimize.dual_annealing(f, bounds=box, maxfun=B,
                  maxiter=10**9, rng=default_rng(seed), minimizer_kwargs=
                  {method: L-BFGS-B, jac: grad, bounds: box, options:
                  {maxiter: min(max(6 d, 100), 1000)}}). The bounds and maxiter
                  of the local search are what dual_annealing uses by itself
                  when no minimizer_kwargs are given; as soon as any are
                  given it passes neither, so they are restated here.
  dual-annealing-plain  (not in the default set) the same with
                  minimizer_kwargs = {method: L-BFGS-B, jac: grad} only:
                  local searches unbounded, L-BFGS-B's maxiter 15000.
  basinhopping    scipy.optimize.basinhopping(f, x0 uniform in the box,
                  niter=10**9, rng=default_rng(seed), minimizer_kwargs=
                  {method: L-BFGS-B, jac: grad, bounds: box}); the rest its
                  defaults (T = 1, stepsize = 0.5, adapted every 50 steps).
  ipop-cma-es     cma.fmin2(f, x0, sigma0 = 0.3 (hi - lo), restarts=9,
                  incpopsize=2, options={bounds: [lo, hi], seed: seed + 1})
                  with x0 a callable drawing uniformly in the box at each
                  (re)start (pycma's advice for restarts; seed 0 would mean
                  "from the clock" to pycma, hence seed + 1). No gradient.
  differential-evolution  scipy.optimize.differential_evolution(f, bounds=box,
                  maxiter=10**9, rng=default_rng(seed)); the rest its
                  defaults (best1bin, popsize 15, tol 0.01, then its own
                  L-BFGS-B polish with finite differences). It may stop by
                  itself before B (its tolerance), as a user would run it.

Counting (the same rule for every method): the problem is wrapped so that
every call of value, gradient or value-and-gradient at a point is one
evaluation, except that calls at the point of the previous call (value then
gradient at the same x, as L-BFGS-B makes them) count once. The run records
the best U among the first B evaluations, the index (1-based) of the first
evaluation with U - U* < 1e-3, the number of evaluations made (B, or fewer
when the method stopped by itself) and the wall time; the attempt at
evaluation B + 1 raises an exception that ends the method, and is caught.
U is computed at every evaluated point, also where a method asked only for
the gradient (which L-BFGS-B never does first).

Columns: problem,d,method,budget,seed,best_gap,evals_to_1e-3,evaluations,wall_seconds
(best_gap = best U - U*; evals_to_1e-3 empty when never reached).
"""

import os

for _k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_k, "1")

import argparse
import csv
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import functions  # noqa: E402

COLUMNS = ["problem", "d", "method", "budget", "seed", "best_gap", "evals_to_1e-3", "evaluations", "wall_seconds"]
METHODS = ["dual-annealing", "basinhopping", "ipop-cma-es", "differential-evolution"]
EXTRA_METHODS = ["dual-annealing-plain"]  # run only when named in --methods
HIT = 1e-3


class BudgetExhausted(Exception):
    """Raised at the attempt of evaluation B + 1."""


class Counted:
    """A problem under a budget of evaluations: see the module's docstring."""

    def __init__(self, problem, budget):
        self.p = problem
        self.budget = int(budget)
        self.count = 0
        self.best = math.inf
        self.first_hit = None
        self._x = None
        self._u = None
        self._g = None

    def _same(self, x):
        return self._x is not None and x.shape == self._x.shape and np.array_equal(x, self._x)

    def _evaluate(self, x, need_grad):
        if self.count >= self.budget:
            raise BudgetExhausted
        self.count += 1
        u, g = self.p.vg(x, need_grad)
        self._x, self._u, self._g = x, u, g
        if u < self.best:
            self.best = u
        if self.first_hit is None and u - self.p.fstar < HIT:
            self.first_hit = self.count

    def value(self, x):
        x = np.array(x, dtype=float).ravel()
        if not self._same(x):
            self._evaluate(x, False)
        return self._u

    def grad(self, x):
        x = np.array(x, dtype=float).ravel()
        if not self._same(x):
            self._evaluate(x, True)
        elif self._g is None:
            self._g = self.p.vg(x, True)[1]
        return self._g.copy()

    def value_and_grad(self, x):
        g = self.grad(x)
        return self._u, g


def run_dual_annealing(p, f, seed, budget):
    from scipy.optimize import dual_annealing

    ls_maxiter = min(max(6 * p.d, 100), 1000)  # dual_annealing's own default
    dual_annealing(
        f.value,
        bounds=p.bounds,
        maxiter=10**9,
        maxfun=budget,
        rng=np.random.default_rng(seed),
        minimizer_kwargs={
            "method": "L-BFGS-B",
            "jac": f.grad,
            "bounds": p.bounds,
            "options": {"maxiter": ls_maxiter},
        },
    )


def run_dual_annealing_plain(p, f, seed, budget):
    """Not run by default: dual_annealing with minimizer_kwargs = {method,
    jac} only, so its local searches run without bounds and with
    L-BFGS-B's own maxiter (15000)."""
    from scipy.optimize import dual_annealing

    dual_annealing(
        f.value,
        bounds=p.bounds,
        maxiter=10**9,
        maxfun=budget,
        rng=np.random.default_rng(seed),
        minimizer_kwargs={"method": "L-BFGS-B", "jac": f.grad},
    )


def run_basinhopping(p, f, seed, budget):
    from scipy.optimize import basinhopping

    rng = np.random.default_rng(seed)
    x0 = p.start(rng)
    basinhopping(
        f.value,
        x0,
        niter=10**9,
        rng=rng,
        minimizer_kwargs={"method": "L-BFGS-B", "jac": f.grad, "bounds": p.bounds},
    )


def run_ipop_cma_es(p, f, seed, budget):
    import cma

    rng = np.random.default_rng(seed)
    cma.fmin2(
        f.value,
        lambda: p.start(rng),
        0.3 * p.width,
        options={
            "bounds": [p.lo, p.hi],
            "seed": seed + 1,
            "verbose": -9,
            "verb_log": 0,
            "verb_disp": 0,
        },
        restarts=9,
        incpopsize=2,
    )


def run_differential_evolution(p, f, seed, budget):
    from scipy.optimize import differential_evolution

    differential_evolution(
        f.value,
        p.bounds,
        maxiter=10**9,
        rng=np.random.default_rng(seed),
    )


RUNNERS = {
    "dual-annealing": run_dual_annealing,
    "basinhopping": run_basinhopping,
    "ipop-cma-es": run_ipop_cma_es,
    "differential-evolution": run_differential_evolution,
    "dual-annealing-plain": run_dual_annealing_plain,
}


def run_one(task):
    """One run; returns (row, note) where note is None or the text of an
    exception other than the budget's."""
    name, d, method, budget, seed = task
    p = functions.make(name, d)
    f = Counted(p, budget)
    note = None
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            RUNNERS[method](p, f, seed, budget)
        except BudgetExhausted:
            pass
        except Exception as e:  # a peer failing: keep what it found, say so
            note = f"{type(e).__name__}: {e}"
    wall = time.perf_counter() - t0
    row = {
        "problem": name,
        "d": d,
        "method": method,
        "budget": budget,
        "seed": seed,
        "best_gap": repr(float(f.best - p.fstar)),
        "evals_to_1e-3": "" if f.first_hit is None else f.first_hit,
        "evaluations": f.count,
        "wall_seconds": f"{wall:.4f}",
    }
    return row, note


def _int_list(text):
    """'0-19' or '0..19' or '1,2,5-7' -> [ints]."""
    out = []
    for part in text.split(","):
        part = part.strip().replace("_", "")
        if not part:
            continue
        sep = ".." if ".." in part else ("-" if "-" in part[1:] else None)
        if sep:
            a, b = part.split(sep, 1)
            out.extend(range(int(a), int(b) + 1))
        else:
            out.append(int(part))
    return out


def _str_list(text, known, what):
    out = [t.strip() for t in text.split(",") if t.strip()]
    for t in out:
        if t not in known:
            raise SystemExit(f"unknown {what} {t!r}; known: {', '.join(known)}")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="CSV file to write (its folder is created)")
    ap.add_argument("--problems", default=",".join(functions.PROBLEMS),
                    help="comma list (default: all: %(default)s)")
    ap.add_argument("--d", default="2,10",
                    help="dimensions of the textbook problems (default %(default)s); the others run in "
                         "their own (functions.DIMS)")
    ap.add_argument("--seeds", default="0-19", help="e.g. 0-19, 0..4 or 1,3 (default %(default)s)")
    ap.add_argument("--budgets", default="10000,125000", help="evaluation budgets B (default %(default)s)")
    ap.add_argument("--methods", default=",".join(METHODS), help="comma list (default: %(default)s)")
    ap.add_argument("--append", action="store_true",
                    help="add rows to --out (header written only if it is new or empty)")
    ap.add_argument("--jobs", type=int, default=1,
                    help="runs in parallel processes (default 1; wall times then share the cores)")
    args = ap.parse_args(argv)

    problems = _str_list(args.problems, functions.PROBLEMS, "problem")
    dims = _int_list(args.d)
    seeds = _int_list(args.seeds)
    budgets = _int_list(args.budgets)
    methods = _str_list(args.methods, METHODS + EXTRA_METHODS, "method")

    tasks = []
    for budget in budgets:
        for p in functions.all_problems(dims=dims, names=problems):
            for method in methods:
                for seed in seeds:
                    tasks.append((p.name, p.d, method, budget, seed))

    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pycma's "no matplotlib" notice
        import cma
        import scipy

    print(f"peers.py: {len(tasks)} runs -> {out}; python {sys.version.split()[0]}, numpy {np.__version__}, "
          f"scipy {scipy.__version__}, cma {cma.__version__}; jobs {args.jobs}", file=sys.stderr)
    t0 = time.perf_counter()
    failures = 0
    fresh = not (args.append and out.exists() and out.stat().st_size > 0)
    if not fresh:
        with open(out, newline="") as fh:
            header = next(csv.reader(fh), None)
        if header != COLUMNS:
            raise SystemExit(f"--append: {out} has columns {header}, not {COLUMNS}")
    with open(out, "w" if fresh else "a", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        if fresh:
            w.writeheader()
        fh.flush()
        if args.jobs > 1:
            import multiprocessing as mp

            pool = mp.get_context("fork").Pool(args.jobs)
            results = pool.imap(run_one, tasks, chunksize=1)
        else:
            pool = None
            results = map(run_one, tasks)
        last_group = None
        for i, (row, note) in enumerate(results, 1):
            w.writerow(row)
            fh.flush()
            if note:
                failures += 1
                print(f"  NOTE {row['problem']} d={row['d']} {row['method']} B={row['budget']} "
                      f"seed={row['seed']}: {note}", file=sys.stderr)
            group = (row["budget"], row["problem"], row["d"], row["method"])
            if group != last_group:
                last_group = group
                print(f"  [{i}/{len(tasks)}, {time.perf_counter() - t0:.0f} s] B={row['budget']} "
                      f"{row['problem']} d={row['d']} {row['method']}", file=sys.stderr)
        if pool is not None:
            pool.close()
            pool.join()
    print(f"peers.py: done, {len(tasks)} runs in {time.perf_counter() - t0:.1f} s"
          f"{f', {failures} ended by an error (see NOTE lines)' if failures else ''}", file=sys.stderr)


if __name__ == "__main__":
    main()

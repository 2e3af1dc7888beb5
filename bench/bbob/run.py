#!/usr/bin/env python3
"""Runs solvers on COCO's noiseless bbob suite, every call of ``fun``
counted, and stores each run's improvements.

    # from the repository root (run.sh installs the requirements, runs this
    # and then ecdf.py):
    nice -n 10 python bench/bbob/run.py --dims 2,5 --instances 1-5 --functions 1-24
    nice -n 10 python bench/bbob/run.py --dims 10 --solvers hrla --budget 1000

Problems: ``cocoex.Suite("bbob", "", "dimensions:.. instance_indices:..
function_indices:..")``, each on its box ``[-5, 5]^d``; ``f_opt`` from
``cocoex.BareProblem(...).best_value()``. Budget ``B = budget * d`` calls
(``--budget``, default 10^4). One run per (solver, function, instance),
with ``seed = 10000 d + 100 f + i``.

Solvers, each called as a scipy user would, with ``fun`` alone (no
gradient; finite differences, where a solver takes them, are calls too):

  hrla                    hrla.minimize(fun, [(-5, 5)] * d, maxfun=B, rng=seed):
                          its default, Auto for the first 100 d calls, then
                          the ensemble of hrla_dyn::Ensemble
  ipop-cma-es             cma.fmin2(fun, x0, 2.0, options={bounds: [-5, 5],
                          maxfevals: B, seed: seed + 1, verbose: -9,
                          verb_log: 0}, restarts=9, incpopsize=2), x0 drawn
                          uniform in [-4, 4]^d at each (re)start
  dual-annealing          scipy.optimize.dual_annealing(fun, [(-5, 5)] * d,
                          maxfun=B, rng=seed)
  differential-evolution  scipy.optimize.differential_evolution(fun,
                          [(-5, 5)] * d, maxiter=10**9, rng=seed,
                          polish=True): its defaults, until its tolerance
                          stops it or the cap does

Extra solvers, run only when named: ``hrla-auto`` (``method=hrla.Auto()``:
Auto alone, the default before the ensemble) and ``hrla-noconverge``
(``converge=False``: every run spends B); ``ensemble`` (bench/bbob/ensemble.py,
a gradient-free ensemble Langevin prototype, ``ensemble.minimize(fun,
[(-5, 5)] * d, maxfun=B, rng=seed)``) and its ablations ``ensemble-od``,
``-iso``, ``-norestart``, ``-raw``, ``-noaldi``, ``-n2``, ``-nhalf``,
``-n2raw``, ``-n2cool``, ``-n2cool15``
(ENSEMBLE below); ``portfolio``: hrla's Auto to ``100 d`` calls, then
``ensemble-n2`` with the calls left (``portfolio-300``: Auto to ``300 d``;
``portfolio-cool``: then ``ensemble-n2cool15``, the prototype of hrla's
default; PORTFOLIO below).

Counting (the same wrapper for every solver): each call of ``fun`` is one
evaluation; the attempt of call B + 1 raises a private exception that ends
the solver and is caught here. The wrapper keeps the calls at which the
best ``f - f_opt`` fell, and that value: ``improvements = [[calls, best],
...]``. ``returned`` is the number of calls at which the solver returned
by itself (null when the cap stopped it).

Store: JSON lines (``--out``, default target/bbob/runs.jsonl), one run a
line: solver, d, f, i, budget (calls), seed, calls, returned, best,
wall_s, version, note (an error other than the cap), improvements.
Runs of the selected (solver, d, f, i) replace those already stored; other
lines stay, so ``--solvers hrla`` re-runs hrla alone. ``--resume`` keeps
the stored runs of the selection made with the same budget and runs the
rest.
"""

import os

for _k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_k, "1")

import argparse
import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from counting import BudgetExhausted, Counted, int_list  # noqa: E402

SOLVERS = ["hrla", "ipop-cma-es", "dual-annealing", "differential-evolution"]
BOX = (-5.0, 5.0)


class Recorded(Counted):
    """A bbob problem as ``fun(x) -> float``: counts calls, stops past the
    budget, keeps the improvements of the best ``f - f_opt``."""

    def __init__(self, problem, f_opt, budget):
        super().__init__(problem, budget)
        self.f_opt = float(f_opt)
        self.best = math.inf
        self.improvements = []

    def __call__(self, x, *args):
        f = self.evaluate(x)
        delta = f - self.f_opt
        if delta < self.best:
            self.best = delta
            self.improvements.append([self.calls, delta])
        return f


def run_hrla(fun, d, budget, seed):
    import hrla

    hrla.minimize(fun, [BOX] * d, maxfun=budget, rng=seed)


def run_hrla_variant(**options):
    """hrla.minimize with ``options``: ``method=hrla.Auto()`` is Auto
    alone (no ensemble phase), ``converge=False`` spends every budget."""

    def runner(fun, d, budget, seed):
        import hrla

        given = {k: (v() if callable(v) else v) for k, v in options.items()}
        hrla.minimize(fun, [BOX] * d, maxfun=budget, rng=seed, **given)

    return runner


def run_ipop_cma_es(fun, d, budget, seed):
    import cma

    rng = np.random.default_rng(seed)
    cma.fmin2(fun, lambda: rng.uniform(-4.0, 4.0, d), 2.0,
              options={"bounds": list(BOX), "maxfevals": budget, "seed": seed + 1,
                       "verbose": -9, "verb_log": 0, "verb_disp": 0},
              restarts=9, incpopsize=2)


def run_dual_annealing(fun, d, budget, seed):
    from scipy.optimize import dual_annealing

    dual_annealing(fun, [BOX] * d, maxfun=budget, rng=seed)


def run_differential_evolution(fun, d, budget, seed):
    from scipy.optimize import differential_evolution

    differential_evolution(fun, [BOX] * d, maxiter=10**9, rng=seed, polish=True)


# The ensemble Langevin prototype (bench/bbob/ensemble.py) and its
# ablations: extra solvers, never run by default.
ENSEMBLE = {
    "ensemble": {},
    "ensemble-od": {"order": 1},  # overdamped (ALDI / EKS) step
    "ensemble-iso": {"precondition": False},  # scale only, no covariance
    "ensemble-norestart": {"restarts": False},
    "ensemble-raw": {"values": "raw"},  # U itself, not its rank scores
    "ensemble-noaldi": {"aldi": False},
    "ensemble-n2": {"pop_factor": 2.0},  # twice the initial population
    "ensemble-nhalf": {"pop_factor": 0.5},
    "ensemble-n2raw": {"pop_factor": 2.0, "values": "raw"},
    # cooling when stalled: kappa x2 (x1.5) after every 10 iterations of a
    # restart without a new best, so a spread ensemble contracts
    "ensemble-n2cool": {"pop_factor": 2.0, "cool": 2.0},
    "ensemble-n2cool15": {"pop_factor": 2.0, "cool": 1.5},
}


def run_ensemble(options):
    def runner(fun, d, budget, seed):
        import ensemble

        ensemble.minimize(fun, [BOX] * d, maxfun=budget, rng=seed, **options)

    return runner


def run_portfolio(share, **options):
    """hrla's Auto for the first ``share d`` calls (its lead at 100 d),
    then the ensemble prototype with twice its initial population for the
    rest (its lead from 1000 d): a sequential portfolio, measured as one
    solver."""

    def runner(fun, d, budget, seed):
        import ensemble
        import hrla

        hrla.minimize(fun, [BOX] * d, maxfun=min(budget, share * d), rng=seed, method=hrla.Auto())
        left = budget - fun.calls
        if left > 0:
            ensemble.minimize(fun, [BOX] * d, maxfun=left, rng=seed,
                              **{"pop_factor": 2.0, **options})

    return runner


# The portfolios: name -> (Auto's share in calls / d, ensemble.py's options).
PORTFOLIO = {
    "portfolio": (100, {}),
    "portfolio-300": (300, {}),
    "portfolio-cool": (100, {"cool": 1.5}),
}


RUNNERS = {
    "hrla": run_hrla,
    "ipop-cma-es": run_ipop_cma_es,
    "dual-annealing": run_dual_annealing,
    "differential-evolution": run_differential_evolution,
}
RUNNERS.update({name: run_ensemble(opts) for name, opts in ENSEMBLE.items()})
RUNNERS["hrla-auto"] = run_hrla_variant(method=lambda: __import__("hrla").Auto())
RUNNERS["hrla-noconverge"] = run_hrla_variant(converge=False)
RUNNERS.update({name: run_portfolio(share, **opts) for name, (share, opts) in PORTFOLIO.items()})


def versions():
    import cma
    import scipy

    try:
        import hrla
        hv = getattr(hrla, "__version__", "?")
    except ImportError:
        hv = "not installed"
    out = {"hrla": f"hrla {hv}", "ipop-cma-es": f"cma {cma.__version__}",
           "dual-annealing": f"scipy {scipy.__version__}",
           "differential-evolution": f"scipy {scipy.__version__}"}
    out.update({name: f"ensemble.py {opts or 'defaults'}" for name, opts in ENSEMBLE.items()})
    out["hrla-auto"] = f"{out['hrla']} method=hrla.Auto() (Auto alone)"
    out["hrla-noconverge"] = f"{out['hrla']} converge=False"
    for name, (share, opts) in PORTFOLIO.items():
        extra = "".join(f" {k}={v}" for k, v in opts.items())
        out[name] = f"{out['hrla']} Auto to {share} d, then ensemble.py pop_factor=2{extra}"
    return out


def seed_of(d, f, i):
    return 10000 * d + 100 * f + i


def run_one(problem, f_opt, solver, budget, seed, version):
    d = problem.dimension
    fun = Recorded(problem, f_opt, budget)
    note = ""
    returned = None
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            RUNNERS[solver](fun, d, budget, seed)
            returned = fun.calls
        except BudgetExhausted:
            pass
        except Exception as e:  # a solver failing: keep what it found, say so
            note = f"{type(e).__name__}: {e}"
    wall = time.perf_counter() - t0
    return {"solver": solver, "d": d, "f": problem.id_function, "i": problem.id_instance,
            "budget": budget, "seed": seed, "calls": fun.calls, "returned": returned,
            "best": fun.best, "wall_s": round(wall, 3), "version": version, "note": note,
            "improvements": fun.improvements}


def read_store(path):
    rows = []
    if path.exists():
        with open(path) as fh:
            for line in fh:
                line = line.strip()
                if line:
                    rows.append(json.loads(line))
    return rows


def key(r):
    return (r["solver"], int(r["d"]), int(r["f"]), int(r["i"]))


def estimate(rows, planned):
    """Seconds the planned runs should take, from the stored runs' mean wall
    time per (solver, d, budget); None where nothing like them is stored."""
    mean = {}
    for r in rows:
        mean.setdefault((r["solver"], int(r["d"]), int(r["budget"])), []).append(float(r["wall_s"]))
    total, unknown = 0.0, set()
    for solver, d, f, i, budget in planned:
        w = mean.get((solver, d, budget))
        if w:
            total += sum(w) / len(w)
        else:
            unknown.add(f"{solver} d={d}")
    return total, sorted(unknown)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="target/bbob/runs.jsonl", help="the store (default %(default)s)")
    ap.add_argument("--dims", default="2,5", help="dimensions (default %(default)s)")
    ap.add_argument("--instances", default="1-5", help="instance numbers (default %(default)s)")
    ap.add_argument("--functions", default="1-24", help="function indices (default %(default)s)")
    ap.add_argument("--solvers", default=",".join(SOLVERS), help="default: all, %(default)s")
    ap.add_argument("--budget", type=float, default=1e4, help="calls per run / d (default %(default)g)")
    ap.add_argument("--resume", action="store_true", help="keep stored runs of the selection at this budget")
    ap.add_argument("--estimate", action="store_true", help="print the time estimate and stop")
    args = ap.parse_args(argv)

    solvers = [s for s in args.solvers.split(",") if s]
    for s in solvers:
        if s not in RUNNERS:
            raise SystemExit(f"run.py: unknown solver {s!r}; known: {', '.join(RUNNERS)}")
    dims, insts, funcs = int_list(args.dims), int_list(args.instances), int_list(args.functions)
    if not all(1 <= f <= 24 for f in funcs):
        raise SystemExit("run.py: bbob's functions are 1-24")
    if "hrla" in solvers:
        import hrla  # noqa: F401  (fail now, not after the peers' runs)

    out = Path(args.out)
    stored = read_store(out)
    planned = [(s, d, f, i, int(round(args.budget * d))) for d in dims for f in funcs for i in insts for s in solvers]
    if args.resume:
        have = {key(r) for r in stored if int(r["budget"]) == int(round(args.budget * r["d"]))}
        planned = [p for p in planned if p[:4] not in have]
    total, unknown = estimate(stored, planned)
    print(f"run.py: {len(planned)} runs -> {out}; estimate {total / 60:.1f} min from the stored runs"
          f"{' (no stored runs for ' + ', '.join(unknown) + ')' if unknown else ''}", file=sys.stderr)
    if args.estimate:
        return

    replaced = {p[:4] for p in planned}
    kept = [r for r in stored if key(r) not in replaced]
    out.parent.mkdir(parents=True, exist_ok=True)
    if len(kept) != len(stored) or not out.exists():
        tmp = out.with_suffix(".tmp")
        with open(tmp, "w") as fh:
            for r in kept:
                fh.write(json.dumps(r) + "\n")
        tmp.replace(out)

    import cocoex
    import scipy

    ver = versions()
    print(f"run.py: python {sys.version.split()[0]}, numpy {np.__version__}, scipy {scipy.__version__}, "
          f"cocoex {cocoex.__version__}, {ver['ipop-cma-es']}, {ver['hrla']}", file=sys.stderr)
    todo = {}
    for p in planned:
        todo.setdefault(p[1:4], []).append(p)
    # the instances by number ("instances: ..."): the default suite holds
    # 1-5 and 71-80, so instance_indices 6-10 would name 71-75
    suite = cocoex.Suite("bbob", f"instances: {','.join(map(str, insts))}",
                         f"dimensions:{','.join(map(str, dims))} "
                         f"function_indices:{','.join(map(str, funcs))}")
    t0 = time.perf_counter()
    done = 0
    with open(out, "a") as fh:
        for problem in suite:
            k = (problem.dimension, problem.id_function, problem.id_instance)
            if k not in todo:
                continue
            d, f, i = k
            f_opt = cocoex.BareProblem("bbob", f, d, i).best_value()
            for solver, d, f, i, budget in todo[k]:
                row = run_one(problem, f_opt, solver, budget, seed_of(d, f, i), ver[solver])
                fh.write(json.dumps(row) + "\n")
                fh.flush()
                done += 1
                ret = f"returned at {row['returned']}" if row["returned"] is not None else "capped"
                print(f"  [{done}/{len(planned)}, {time.perf_counter() - t0:.0f} s] d={d} f{f} i{i} {solver}: "
                      f"best {row['best']:.3g} after {row['calls']} calls ({ret}, {row['wall_s']:.1f} s)"
                      f"{' ' + row['note'] if row['note'] else ''}", file=sys.stderr, flush=True)
            problem.free()
    print(f"run.py: done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Summarise quality-benchmark CSVs (peers.py's, and the crate's runner's,
which writes the same columns with methods such as `hrla-default`) as
Markdown tables, one per budget, a row per problem / d / method:

    python summarize.py target/quality/peers.csv [more.csv ...]

Columns of the input: problem,d,method,budget,seed,best_gap,evals_to_1e-3,evaluations,wall_seconds

Per problem, d, budget and method:
  solved      runs with best_gap < 1e-6, out of N runs
  mean gap    mean of best_gap over the N runs
  evals to 1e-3  median of evals_to_1e-3 over the runs that reached a gap
              below 1e-3, with how many did ("-" when none)
  evals used  median number of evaluations a run made (B, or fewer when
              the method stopped by itself)
  wall s      median wall time of one run, seconds

Needs only Python's standard library. Rows with the same (problem, d,
method, budget, seed) in several files are all kept (and counted) — give
each file once.
"""

import argparse
import csv
import math
import statistics
import sys
from collections import OrderedDict
from pathlib import Path

SOLVED = 1e-6

# The benchmark's problem order (functions.PROBLEMS), without importing numpy.
ORDER = ["rastrigin_paper", "rastrigin", "ackley", "levy", "rosenbrock",
         "styblinski_tang", "griewank", "zakharov", "lj7"]


def _problem_key(name):
    return (ORDER.index(name), name) if name in ORDER else (len(ORDER), name)


def _fmt_gap(x):
    if math.isnan(x):
        return "nan"
    if x == 0.0:
        return "0"
    return f"{x:.2e}"


def _fmt_wall(x):
    if x >= 100:
        return f"{x:.0f}"
    if x >= 1:
        return f"{x:.2f}"
    return f"{x:.3f}"


def read(paths):
    rows = []
    for path in paths:
        with open(path, newline="") as fh:
            for r in csv.DictReader(fh):
                rows.append(r)
    return rows


def summarise(rows):
    groups = OrderedDict()
    for r in rows:
        key = (int(r["budget"]), r["problem"], int(r["d"]), r["method"])
        groups.setdefault(key, []).append(r)
    out = []
    for key in sorted(groups, key=lambda k: (k[0], _problem_key(k[1]), k[2], k[3])):
        rs = groups[key]
        gaps = [float(r["best_gap"]) for r in rs]
        hits = [int(r["evals_to_1e-3"]) for r in rs if r["evals_to_1e-3"].strip()]
        walls = [float(r["wall_seconds"]) for r in rs if r.get("wall_seconds", "").strip()]
        out.append({
            "budget": key[0], "problem": key[1], "d": key[2], "method": key[3],
            "n": len(rs),
            "solved": sum(1 for g in gaps if g < SOLVED),
            "mean_gap": statistics.fmean(gaps) if gaps else float("nan"),
            "median_hit": statistics.median(hits) if hits else None,
            "hits": len(hits),
            "median_wall": statistics.median(walls) if walls else float("nan"),
            "median_evals": statistics.median(int(r["evaluations"]) for r in rs),
        })
    return out


def markdown(summary, file=sys.stdout):
    budgets = sorted({s["budget"] for s in summary})
    for b in budgets:
        print(f"\n### Budget B = {b:,} evaluations\n".replace(",", "_"), file=file)
        print("| problem | d | method | solved (gap < 1e-6) | mean best gap | median evals to 1e-3 (runs) | median evals used | median wall s / run |", file=file)
        print("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: |", file=file)
        for s in summary:
            if s["budget"] != b:
                continue
            hit = "-" if s["median_hit"] is None else f"{s['median_hit']:.0f}"
            print(f"| {s['problem']} | {s['d']} | {s['method']} | {s['solved']}/{s['n']} | "
                  f"{_fmt_gap(s['mean_gap'])} | {hit} ({s['hits']}/{s['n']}) | {s['median_evals']:.0f} | {_fmt_wall(s['median_wall'])} |",
                  file=file)


def main(argv=None):
    ap = argparse.ArgumentParser(description="Markdown summary of quality-benchmark CSVs.")
    ap.add_argument("csv", nargs="+", type=Path, help="one or more CSV files")
    args = ap.parse_args(argv)
    rows = read(args.csv)
    if not rows:
        raise SystemExit("no rows in " + ", ".join(map(str, args.csv)))
    print(f"Quality benchmark: {len(rows)} runs from {', '.join(map(str, args.csv))}; "
          f"solved = best gap < {SOLVED:g}; gap = best U among the first B evaluations - U*.")
    markdown(summarise(rows))


if __name__ == "__main__":
    main()

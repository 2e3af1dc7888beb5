#!/usr/bin/env python3
"""Summary of run.py's CSVs as a Markdown table, a row per problem and
method:

    python bench/expensive/summarize.py target/expensive/runs.csv [more.csv ...]

  reached        runs that reached the target, out of N
  median evals   median, over ALL N runs, of the call at which the target
                 was reached, a run that did not reach it counting as
                 infinitely many ("> cap" when that is the median)
  median (reached)  the same over the runs that reached it
  quartiles      25% and 75% of the same as "median evals"
  best seen      the lowest value any run saw (a value below the problem's
                 best known value is flagged: the target was set too high)
  wall s         median wall time of one run

and, per problem, hrla's median against the best peer's. Needs only
Python's standard library. Rows with the same (problem, method, seed)
in several files are all counted: give each file once.
"""

import argparse
import csv
import math
import statistics
import sys
from collections import OrderedDict
from pathlib import Path

ORDER = ["ode", "peaks", "lj8"]
METHOD_ORDER = ["hrla", "dual-annealing", "differential-evolution", "ipop-cma-es"]
# The best known values (problems.py), repeated so that this script needs no numpy.
FSTAR = {"ode": 0.2909183053759802, "peaks": 1.8968657598679426, "lj8": -19.821489}


def _key(name, order):
    return (order.index(name), name) if name in order else (len(order), name)


def quantile(xs, q):
    """The q-quantile (linear interpolation) of xs, which may hold inf."""
    xs = sorted(xs)
    pos = q * (len(xs) - 1)
    i = int(math.floor(pos))
    j = min(i + 1, len(xs) - 1)
    a, b = xs[i], xs[j]
    if pos == i or a == b:
        return a
    if math.isinf(a) or math.isinf(b):
        return math.inf
    return a + (pos - i) * (b - a)


def summarise(rows):
    groups = OrderedDict()
    for r in rows:
        groups.setdefault((r["problem"], r["method"]), []).append(r)
    out = []
    for key in sorted(groups, key=lambda k: (_key(k[0], ORDER), _key(k[1], METHOD_ORDER))):
        rs = groups[key]
        hits = [int(r["evals_to_target"]) for r in rs if r["reached"] == "1"]
        evals = [int(r["evals_to_target"]) if r["reached"] == "1" else math.inf for r in rs]
        out.append({
            "problem": key[0], "method": key[1], "d": rs[0]["d"], "n": len(rs),
            "cap": max(int(r["cap"]) for r in rs),
            "reached": len(hits),
            "median": quantile(evals, 0.5), "q1": quantile(evals, 0.25), "q3": quantile(evals, 0.75),
            "median_reached": statistics.median(hits) if hits else None,
            "best": min(float(r["best"]) for r in rs),
            "wall": statistics.median(float(r["wall_seconds"]) for r in rs),
            "notes": sorted({r["note"] for r in rs if r["note"]}),
        })
    return out


def _n(x, cap):
    return f"> {cap:,}" if math.isinf(x) else f"{x:,.0f}"


def markdown(summary, file=sys.stdout):
    print("| problem | D | method | reached | median evals to target | quartiles | median (reached runs) | best seen | median wall s |", file=file)
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|", file=file)
    for s in summary:
        fstar = FSTAR.get(s["problem"])
        flag = " (below f*)" if fstar is not None and s["best"] < fstar - 1e-12 * abs(fstar) else ""
        mr = "-" if s["median_reached"] is None else f"{s['median_reached']:,.0f}"
        print(f"| {s['problem']} | {s['d']} | {s['method']} | {s['reached']}/{s['n']} | {_n(s['median'], s['cap'])} | "
              f"{_n(s['q1'], s['cap'])} - {_n(s['q3'], s['cap'])} | {mr} | {s['best']:.10g}{flag} | {s['wall']:.2f} |",
              file=file)
    print(file=file)
    for p in sorted({s["problem"] for s in summary}, key=lambda n: _key(n, ORDER)):
        mine = [s for s in summary if s["problem"] == p and s["method"] == "hrla"]
        peers = [s for s in summary if s["problem"] == p and s["method"] != "hrla"]
        if not mine or not peers:
            continue
        best = min(peers, key=lambda s: (s["median"], -s["reached"]))
        m = mine[0]
        if math.isinf(m["median"]) and math.isinf(best["median"]):
            ratio = "both medians above the cap"
        elif math.isinf(best["median"]):
            ratio = "hrla reaches it in most runs, no peer does"
        elif math.isinf(m["median"]):
            ratio = "hrla's median is above the cap"
        else:
            ratio = f"{m['median'] / best['median']:.2f}x"
        print(f"- {p}: hrla {m['reached']}/{m['n']}, median {_n(m['median'], m['cap'])}; best peer by median: "
              f"{best['method']} {best['reached']}/{best['n']}, median {_n(best['median'], best['cap'])}; "
              f"hrla / best peer: {ratio}", file=file)
    notes = [(s["problem"], s["method"], n) for s in summary for n in s["notes"]]
    if notes:
        print(file=file)
        for p, m, n in notes:
            print(f"- note, {p} {m}: {n}", file=file)


def main(argv=None):
    ap = argparse.ArgumentParser(description="Markdown summary of run.py's CSVs.")
    ap.add_argument("csv", nargs="+", type=Path)
    args = ap.parse_args(argv)
    rows = []
    for path in args.csv:
        with open(path, newline="") as fh:
            rows.extend(csv.DictReader(fh))
    if not rows:
        raise SystemExit("no rows")
    markdown(summarise(rows))


if __name__ == "__main__":
    main()

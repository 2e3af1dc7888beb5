#!/usr/bin/env python3
"""The ablation and peer tables of docs/QUALITY.md from the benchmark's CSVs.

    python ablation.py target/quality/hrla.csv [peers.csv ...]

Prints, per budget, one row per problem: solved / median evaluations to
1e-3 for the default and each ablation, each marked `-` (worse than the
default), `+` (better) or `=` (neither, within noise); then the default
beside the peers. Noise: a difference in runs solved counts when a
two-sided Fisher exact test on the two 20-run samples gives p < 0.05; a
difference in median evaluations to 1e-3 (with at least half the runs of
both reaching 1e-3) counts when it is a factor 1.5 or more. The last
column of the peers' table divides the default's median evaluations to
1e-3 by the lowest median of a peer that reached 1e-3 in at least half
its runs, where the default did too. Needs only the
standard library.
"""

import csv
import math
import statistics
import sys
from collections import defaultdict

ABLATIONS = ["hrla-jump", "hrla-fixed-step", "hrla-no-quench"]
PEERS = ["dual-annealing", "basinhopping", "ipop-cma-es", "differential-evolution"]


def fisher_p(a, n1, b, n2):
    """Two-sided Fisher exact test of a/n1 against b/n2."""
    k = a + b
    n = n1 + n2

    def pmf(x):
        return math.comb(n1, x) * math.comb(n2, k - x) / math.comb(n, k)

    p0 = pmf(a)
    lo, hi = max(0, k - n2), min(k, n1)
    return min(1.0, sum(pmf(x) for x in range(lo, hi + 1) if pmf(x) <= p0 * (1 + 1e-9)))


def cell(rows):
    if not rows:
        return None
    solved = sum(float(r["best_gap"]) < 1e-6 for r in rows)
    hits = [int(r["evals_to_1e-3"]) for r in rows if r["evals_to_1e-3"]]
    med = statistics.median(hits) if hits else None
    return solved, len(rows), med, len(hits)


def fmt(c):
    if c is None:
        return "n/a"
    s, n, med, h = c
    return f"{s}/{n} / {int(med) if med is not None else '-'}"


def verdict(d, a):
    """How ablation cell a compares with default cell d: -, + or =."""
    ds, dn, dm, dh = d
    as_, an, am, ah = a
    if ds != as_ and fisher_p(ds, dn, as_, an) < 0.05:
        return "-" if as_ < ds else "+"
    if dm is not None and am is not None and min(dh, ah) >= dn // 2:
        if am >= 1.5 * dm:
            return "-"
        if dm >= 1.5 * am:
            return "+"
    if dm is not None and am is None:
        return "-" if dh >= dn // 2 else "="
    if am is not None and dm is None:
        return "+" if ah >= an // 2 else "="
    return "="


def main(paths):
    data = defaultdict(list)
    order = []
    for p in paths:
        with open(p, newline="") as fh:
            for r in csv.DictReader(fh):
                key = (int(r["budget"]), r["problem"], int(r["d"]))
                if key not in order:
                    order.append(key)
                data[key + (r["method"],)].append(r)
    for budget in sorted({k[0] for k in order}):
        keys = [k for k in order if k[0] == budget]
        print(f"\n### Ablations, B = {budget:,}\n")
        print("| problem | d | default | jump for sampling | fixed step | no quenches |")
        print("|---|---:|---:|---:|---:|---:|")
        tally = defaultdict(lambda: defaultdict(int))
        for k in keys:
            d = cell(data.get(k + ("hrla-default",)))
            if d is None:
                continue
            cells = [fmt(d)]
            for m in ABLATIONS:
                a = cell(data.get(k + (m,)))
                if a is None:
                    cells.append("n/a")
                    continue
                v = verdict(d, a)
                tally[m][v] += 1
                cells.append(f"{fmt(a)} {v}")
            print(f"| {k[1]} | {k[2]} | " + " | ".join(cells) + " |")
        print("\nworse (-) / same (=) / better (+) than the default: " + "; ".join(
            f"{m}: {t['-']} / {t['='] } / {t['+']}" for m, t in tally.items()))
        print(f"\n### Default and peers, B = {budget:,}\n")
        print("| problem | d | default | " + " | ".join(PEERS) + " | default / best peer |")
        print("|---|---:|---:|" + "---:|" * len(PEERS) + "---:|")
        for k in keys:
            d = cell(data.get(k + ("hrla-default",)))
            ps = [cell(data.get(k + (m,))) for m in PEERS]
            if d is None or all(p is None for p in ps):
                continue
            # The ratio of the default's median evaluations to 1e-3 to the
            # lowest median of a peer that reached 1e-3 in at least half
            # its runs, where the default did too (a median over 1 or 2
            # lucky runs is no yardstick).
            meds = [p[2] for p in ps if p is not None and p[2] is not None and p[3] >= p[1] // 2]
            ratio = f"{d[2] / min(meds):.1f}" if meds and d[2] is not None and d[3] >= d[1] // 2 else "-"
            print(f"| {k[1]} | {k[2]} | {fmt(d)} | " + " | ".join(fmt(p) for p in ps) + f" | {ratio} |")


if __name__ == "__main__":
    main(sys.argv[1:])

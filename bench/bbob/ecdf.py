#!/usr/bin/env python3
"""Runtime ECDFs of the bbob runs, as COCO draws them, with the tables and
plots of docs/bbob/.

    python bench/bbob/ecdf.py [--store target/bbob/runs.jsonl] [--docs docs/bbob]
                              [--base docs/bbob/runs.csv] [--solvers a,b,...]

Targets: the 51 values ``10^(2 - 0.2 k)``, k = 0..50, on ``f - f_opt``. A
run's runtime to a target is the number of calls after which its best
``f - f_opt`` was first at or below it (never: infinite). The ECDF of a
solver at ``b`` is the share of its (function, instance, target) triples
whose runtime is at most ``b d`` calls.

Runs: those of the store (run.py's JSON lines) and, for every (solver, d,
f, i) the store lacks, those of ``DOCS/runs.csv`` (this script's own
compact copy: per run its budget, calls, the calls at which it returned by
itself, best ``f - f_opt``, wall time, version and runtimes to the targets
it reached, ``hits``); so a re-run of one solver is compared with the
others' committed runs. Writes, into ``DOCS``: runs.csv (the merged runs),
ecdf.md (the tables) and, per dimension, ecdf-dD.png (all functions) and
ecdf-groups-dD.png (all functions and the five bbob groups).

Reference: "best 2009", the virtual best of the algorithms of BBOB 2009 per
(function, target), read from the archive cocopp ships
(refalgs/best2009-bbob.tar.gz, one runtime per (function, target), its
best expected runtime); drawn in grey and given in the tables.
"""

import argparse
import csv
import importlib.util
import io
import json
import math
import re
import sys
import tarfile
from pathlib import Path

import numpy as np

TARGETS = [10.0 ** ((10 - k) / 5) for k in range(51)]
SOLVERS = ["hrla", "ipop-cma-es", "dual-annealing", "differential-evolution"]
REF = "best 2009"
GROUPS = [
    ("all functions", range(1, 25)),
    ("f1–5 separable", range(1, 6)),
    ("f6–9 low or moderate conditioning", range(6, 10)),
    ("f10–14 high conditioning, unimodal", range(10, 15)),
    ("f15–19 multimodal, adequate global structure", range(15, 20)),
    ("f20–24 multimodal, weak global structure", range(20, 25)),
]
SHORT = ["all", "f1–5", "f6–9", "f10–14", "f15–19", "f20–24"]
BUDGETS = [10, 100, 1000, 10000]
STYLE = {
    "hrla": dict(color="C3", lw=2.6, zorder=5),
    "ipop-cma-es": dict(color="C0", lw=1.6),
    "dual-annealing": dict(color="C2", lw=1.6),
    "differential-evolution": dict(color="C1", lw=1.6),
    # Auto alone (the default before the ensemble phase): hrla's colour, dashed.
    "hrla-auto": dict(color="C3", lw=1.4, ls="--", alpha=0.8),
    REF: dict(color="0.55", lw=5, alpha=0.45, zorder=1),
}
COLUMNS = ["solver", "d", "f", "i", "budget", "seed", "calls", "returned", "best", "wall_s", "version", "hits"]


def hits_of(improvements):
    """Runtimes to the targets reached, easiest first (a prefix of TARGETS)."""
    out, k = [], 0
    for calls, best in improvements:
        while k < len(TARGETS) and best <= TARGETS[k]:
            out.append(int(calls))
            k += 1
    return out


def encode_hits(hits):
    """``1 1 1 4 4`` as ``1*3 4*2``: runs of equal runtimes as ``value*count``."""
    out, n = [], 0
    while n < len(hits):
        m = n
        while m < len(hits) and hits[m] == hits[n]:
            m += 1
        out.append(str(hits[n]) if m - n == 1 else f"{hits[n]}*{m - n}")
        n = m
    return " ".join(out)


def decode_hits(text):
    out = []
    for part in text.split():
        v, _, c = part.partition("*")
        out.extend([int(v)] * (int(c) if c else 1))
    return out


def load_store(path):
    runs = {}
    if path.exists():
        with open(path) as fh:
            for line in fh:
                if not line.strip():
                    continue
                r = json.loads(line)
                run = {c: r.get(c) for c in COLUMNS if c != "hits"}
                run["hits"] = hits_of(r["improvements"])
                runs[(r["solver"], int(r["d"]), int(r["f"]), int(r["i"]))] = run
    return runs


def load_csv(path):
    runs = {}
    if path.exists():
        with open(path, newline="") as fh:
            for r in csv.DictReader(fh):
                run = dict(r)
                for c in ("d", "f", "i", "budget", "seed", "calls"):
                    run[c] = int(r[c])
                run["returned"] = int(r["returned"]) if r["returned"] else None
                run["best"] = float(r["best"])
                run["wall_s"] = float(r["wall_s"])
                run["hits"] = decode_hits(r["hits"])
                runs[(r["solver"], run["d"], run["f"], run["i"])] = run
    return runs


def write_csv(path, runs):
    order = {s: n for n, s in enumerate(SOLVERS)}
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(COLUMNS)
        for k in sorted(runs, key=lambda k: (k[1], order.get(k[0], 99), k[0], k[2], k[3])):
            r = runs[k]
            w.writerow([r["solver"], r["d"], r["f"], r["i"], r["budget"], r["seed"], r["calls"],
                        "" if r["returned"] is None else r["returned"], f"{r['best']:.3e}",
                        f"{float(r['wall_s']):.2f}", r["version"], encode_hits(r["hits"])])


def best2009():
    """{(d, f): [runtime per target]} from cocopp's best-2009 archive, or {}."""
    spec = importlib.util.find_spec("cocopp")
    if spec is None or not spec.submodule_search_locations:
        return {}
    tgz = Path(list(spec.submodule_search_locations)[0]) / "refalgs" / "best2009-bbob.tar.gz"
    if not tgz.exists():
        return {}
    ref = {}
    with tarfile.open(tgz) as tar:
        for m in tar.getmembers():
            hit = re.search(r"bestalg_f(\d+)_d(\d+)\.dat$", m.name)
            if not hit:
                continue
            f, d = int(hit.group(1)), int(hit.group(2))
            traj = []
            for line in io.TextIOWrapper(tar.extractfile(m)):
                if line.startswith("%") or not line.strip():
                    continue
                parts = line.split()
                traj.append((float(parts[0]), float(parts[1])))
            rt = []
            for t in TARGETS:
                rt.append(next((e for e, v in traj if v <= t * (1 + 1e-9)), math.inf))
            ref[(d, f)] = rt
    return ref


def runtimes(runs, solver, d, funcs):
    """Runtimes / d of every (f, instance, target) triple of a solver's runs."""
    out = []
    for (s, dd, f, i), r in runs.items():
        if s == solver and dd == d and f in funcs:
            h = r["hits"]
            out.extend(h[k] / d if k < len(h) else math.inf for k in range(len(TARGETS)))
    return np.array(out)


def ref_runtimes(ref, d, funcs, runs=None):
    """The best-2009 runtimes / d of the (function, target) pairs, over the
    functions of ``funcs`` that ``runs`` hold at ``d`` (all when None)."""
    if runs is not None:
        funcs = [f for f in funcs if any(k[1] == d and k[2] == f for k in runs)]
    out = []
    for f in funcs:
        if (d, f) in ref:
            out.extend(np.array(ref[(d, f)]) / d)
    return np.array(out)


def share(rt, b):
    return float(np.mean(rt <= b)) if rt.size else math.nan


def pct(x):
    return "–" if x is None or math.isnan(x) else f"{100 * x:.0f}"


def solver_budget(runs, solver, d):
    b = [r["budget"] / d for (s, dd, _, _), r in runs.items() if s == solver and dd == d]
    return min(b) if b else 0


def tables(runs, ref, dims, solvers):
    lines = []
    lines.append("Share (%) of the (function, instance, target) triples reached within "
                 "10·d / 100·d / 1000·d / 10⁴·d calls, 51 targets `10^(2 - 0.2k)` on `f - f_opt` "
                 f"(best 2009: of the (function, target) pairs). \"returned\": runs the solver ended by itself "
                 "with 1% or more of the budget unused, and their median calls / d; wall: the solver's runs "
                 "one after another, on a shared machine.\n")
    lines.append("| d | solver | runs | 10·d | 100·d | 1000·d | 10⁴·d | returned | wall |")
    lines.append("|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for d in dims:
        for s in solvers + [REF]:
            if s == REF:
                rt = ref_runtimes(ref, d, range(1, 25), runs)
                if not rt.size:
                    continue
                cells = [pct(share(rt, b)) for b in BUDGETS]
                lines.append(f"| {d} | *{REF}* | | " + " | ".join(cells) + " | | |")
                continue
            rs = [r for (ss, dd, _, _), r in runs.items() if ss == s and dd == d]
            if not rs:
                continue
            rt = runtimes(runs, s, d, range(1, 25))
            top = solver_budget(runs, s, d)
            cells = [pct(share(rt, b)) if b <= top else "–" for b in BUDGETS]
            ret = [r["returned"] / d for r in rs if r["returned"] is not None and r["returned"] < 0.99 * r["budget"]]
            rtxt = f"{len(ret)} ({np.median(ret):.0f})" if ret else "0"
            wall = sum(float(r["wall_s"]) for r in rs)
            lines.append(f"| {d} | {s} | {len(rs)} | " + " | ".join(cells) + f" | {rtxt} | {wall / 60:.1f} min |")
    lines.append("")
    lines.append("Per group, the same shares (%) at 10·d / 100·d / 1000·d / 10⁴·d:\n")
    lines.append("| d | solver | " + " | ".join(SHORT[1:]) + " |")
    lines.append("|---:|---|" + "---:|" * 5)
    for d in dims:
        for s in solvers + [REF]:
            cells = []
            for _, funcs in GROUPS[1:]:
                if s == REF:
                    rt = ref_runtimes(ref, d, funcs, runs)
                    top = math.inf
                else:
                    rt = runtimes(runs, s, d, funcs)
                    top = solver_budget(runs, s, d)
                if not rt.size:
                    cells.append("")
                    continue
                cells.append(" / ".join(pct(share(rt, b)) if b <= top else "–" for b in BUDGETS))
            if any(cells):
                name = f"*{s}*" if s == REF else s
                lines.append(f"| {d} | {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def per_function(runs, ref, dims, solvers):
    lines = ["Per function, share (%) of the (instance, target) pairs reached within 1000·d calls:\n"]
    for d in dims:
        have = [s for s in solvers if any(k[0] == s and k[1] == d for k in runs)]
        cols = have + ([REF] if any((d, f) in ref for f in range(1, 25)) else [])
        lines.append(f"d = {d}:\n")
        lines.append("| f | " + " | ".join(cols) + " |")
        lines.append("|---:|" + "---:|" * len(cols))
        for f in range(1, 25):
            cells = []
            for s in cols:
                rt = ref_runtimes(ref, d, [f]) if s == REF else runtimes(runs, s, d, [f])
                cells.append(pct(share(rt, 1000)) if rt.size else "")
            if any(cells[:len(have)]):
                lines.append(f"| {f} | " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def draw(ax, runs, ref, d, funcs, solvers, xmax):
    for s in solvers + [REF]:
        if s == REF:
            rt = ref_runtimes(ref, d, funcs, runs)
            top = xmax
        else:
            rt = runtimes(runs, s, d, funcs)
            top = solver_budget(runs, s, d)
        if not rt.size:
            continue
        x = np.sort(rt[np.isfinite(rt) & (rt <= top)])
        y = np.arange(1, x.size + 1) / rt.size
        xs = np.concatenate([[1.0], np.maximum(x, 1.0), [top]])
        ys = np.concatenate([[np.mean(rt <= 1.0)], y, [y[-1] if y.size else 0.0]])
        ax.step(xs, ys, where="post", label=s, **STYLE.get(s, {}))
        if s != REF:
            ax.plot([top], [ys[-1]], marker="x", color=STYLE.get(s, {}).get("color"), ms=7, mew=2)
    ax.set_xscale("log")
    ax.set_xlim(1, xmax)
    ax.set_ylim(0, 1)
    ax.grid(True, which="major", alpha=0.4)
    ax.set_xlabel("calls / d")


def span(values, what):
    """``f1–24``, ``instances 1–5``, ``instance 3``, ``f1, 8, 15``."""
    plural = what if what == "f" else what + "s"
    if len(values) == 1:
        return f"{what} {values[0]}" if what != "f" else f"f{values[0]}"
    if values == list(range(values[0], values[-1] + 1)):
        return f"{plural}{'' if what == 'f' else ' '}{values[0]}–{values[-1]}"
    return f"{plural}{'' if what == 'f' else ' '}" + ", ".join(map(str, values))


def plots(runs, ref, dims, solvers, docs):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = []
    for d in dims:
        have = [s for s in solvers if any(k[0] == s and k[1] == d for k in runs)]
        if not have:
            continue
        xmax = max(solver_budget(runs, s, d) for s in have)
        insts = span(sorted({k[3] for k in runs if k[1] == d}), "instance")
        funcs = span(sorted({k[2] for k in runs if k[1] == d}), "f")
        fig, ax = plt.subplots(figsize=(7.5, 5.2))
        draw(ax, runs, ref, d, range(1, 25), have, xmax)
        ax.set_ylabel("share of (f, instance, target) reached")
        ax.set_title(f"bbob, d = {d}: {funcs}, {insts}, 51 targets 1e2…1e-8", fontsize=11)
        ax.legend(loc="upper left", fontsize=9)
        fig.tight_layout()
        p = docs / f"ecdf-d{d}.png"
        fig.savefig(p, dpi=90)
        plt.close(fig)
        written.append(p)

        fig, axes = plt.subplots(2, 3, figsize=(13, 7.6), sharey=True)
        for ax, (name, fs) in zip(axes.flat, GROUPS):
            draw(ax, runs, ref, d, fs, have, xmax)
            ax.set_title(name, fontsize=10)
        for ax in axes[:, 0]:
            ax.set_ylabel("share of (f, instance, target) reached")
        axes[0, 0].legend(loc="upper left", fontsize=8)
        fig.suptitle(f"bbob, d = {d}, {funcs}, {insts}: runtime ECDF per group, 51 targets 1e2…1e-8")
        fig.tight_layout()
        p = docs / f"ecdf-groups-d{d}.png"
        fig.savefig(p, dpi=80)
        plt.close(fig)
        written.append(p)
    return written


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--store", default="target/bbob/runs.jsonl")
    ap.add_argument("--docs", default="docs/bbob")
    ap.add_argument("--base", default=None,
                    help="the committed runs to merge (default DOCS/runs.csv); e.g. --docs /tmp/x "
                         "--base docs/bbob/runs.csv writes the tables elsewhere")
    ap.add_argument("--solvers", default=None, help="only these solvers (comma-separated; default all)")
    args = ap.parse_args(argv)

    docs = Path(args.docs)
    docs.mkdir(parents=True, exist_ok=True)
    runs = load_csv(Path(args.base) if args.base else docs / "runs.csv")
    fresh = load_store(Path(args.store))
    runs.update(fresh)
    if args.solvers:
        keep = set(args.solvers.split(","))
        runs = {k: v for k, v in runs.items() if k[0] in keep}
    if not runs:
        raise SystemExit(f"ecdf.py: no runs in {args.store} or {docs / 'runs.csv'}")
    print(f"ecdf.py: {len(fresh)} runs from {args.store}, {len(runs) - len(fresh)} from {docs / 'runs.csv'}",
          file=sys.stderr)
    dims = sorted({k[1] for k in runs})
    solvers = [s for s in SOLVERS if any(k[0] == s for k in runs)] + sorted({k[0] for k in runs} - set(SOLVERS))
    for d in dims:
        sets = {s: {k[2:] for k in runs if k[0] == s and k[1] == d} for s in solvers}
        sets = {s: v for s, v in sets.items() if v}
        if len({frozenset(v) for v in sets.values()}) > 1:
            print(f"ecdf.py: warning: at d = {d} the solvers ran different (f, instance) sets: "
                  + ", ".join(f"{s} {len(v)}" for s, v in sets.items()), file=sys.stderr)

    write_csv(docs / "runs.csv", runs)
    ref = best2009()
    if not ref:
        print("ecdf.py: no cocopp best-2009 archive found; no reference line", file=sys.stderr)
    text = tables(runs, ref, dims, solvers)
    md = ("# COCO bbob: runtime ECDF tables\n\nWritten by `bench/bbob/ecdf.py` (run by `bench/bbob/run.sh`); "
          "see \"Black-box: COCO bbob\" in [../QUALITY.md](../QUALITY.md).\n\n"
          + text + "\n" + per_function(runs, ref, dims, solvers))
    (docs / "ecdf.md").write_text(md)
    written = plots(runs, ref, dims, solvers, docs)
    print(text)
    print("ecdf.py: wrote " + ", ".join(str(p) for p in [docs / "runs.csv", docs / "ecdf.md"] + written),
          file=sys.stderr)


if __name__ == "__main__":
    main()

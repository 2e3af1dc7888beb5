"""The paper's T1 (docs/REPRODUCTION.md) from Python: 10-D Rastrigin, HRLA,
h in {0.001, 0.01, 0.1} x a in {1, 2, 3, 4}, M = 100 runs of N = 10 chains,
K = 14 000 steps from N(3·1, 10 I), running best at stride 100; run i
seeded as the repro tool seeds it (2025 ^ splitmix64(i)), so the table is
the tool's. Runs go to a pool of threads: each run releases the GIL.

    target/python-venv/bin/python python/bench/t1.py [--threads 2]
"""

import argparse
import csv
import math
import os
import statistics
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import hrla

MASK = (1 << 64) - 1


def splitmix64(z):
    z = (z + 0x9E3779B97F4A7C15) & MASK
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return z ^ (z >> 31)


def run(h, a, i, base=2025):
    opt = hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(h), float(a),
                         hrla.Gaussian([3.0] * 10, math.sqrt(10.0)), chains=10,
                         seed=base ^ splitmix64(i), stride=100, stop=hrla.Stop().steps(14_000))
    return opt.run().value


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--threads", type=int, default=os.cpu_count())
    args = p.parse_args()
    configs = [(h, a) for h in (0.001, 0.01, 0.1) for a in (1, 2, 3, 4)]
    jobs = [(h, a, i) for h, a in configs for i in range(100)]
    load = os.getloadavg()
    t0, c0 = time.perf_counter(), time.process_time()
    with ThreadPoolExecutor(args.threads) as pool:
        values = list(pool.map(lambda j: run(*j), jobs))
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    steps = len(jobs) * 10 * 14_000
    tool = {}
    summary = Path(__file__).resolve().parents[2] / "docs/repro/t1/summary.csv"
    if summary.exists():
        for row in csv.DictReader(summary.open()):
            tool[(float(row["h"]), int(row["a"]))] = float(row["mean"])
    print("| h | a | mean | median | SD | SE | mean in docs/repro |")
    print("|---|---|---|---|---|---|---|")
    worst = 0.0
    for k, (h, a) in enumerate(configs):
        v = values[100 * k:100 * (k + 1)]
        mean, sd = statistics.fmean(v), statistics.stdev(v)
        ref = tool.get((h, a), float("nan"))
        worst = max(worst, abs(mean - ref) / abs(ref))
        print(f"| {h} | {a} | {mean:.4f} | {statistics.median(v):.4f} | {sd:.4f} | "
              f"{sd / 10:.4f} | {ref:.4f} |")
    print(f"\nwall time {wall:.2f} s for {steps:,} chain-steps ({steps / wall:.3e}/s) on "
          f"{args.threads} threads, {cpu:.2f} s of CPU ({cpu / steps * 1e9:.0f} ns per chain-step); "
          f"load average before {load[0]:.2f}, after {os.getloadavg()[0]:.2f}")
    print(f"largest relative difference of the means from docs/repro/t1/summary.csv: {worst:.1e}")


if __name__ == "__main__":
    main()

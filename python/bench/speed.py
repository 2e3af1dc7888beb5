"""Speed per coordinate-step on 10-D Rastrigin, 1000 chains, the paper's
parameters (a = 4, b = 10, alpha = beta = 1, h = 0.01): this package with
the built-in potential and with a batched numpy potential, against the
numpy and numba peers of bench/peers/peers.py (value and running best
every step, as the optimiser keeps). Measurements are interleaved: every
repeat times each implementation back to back, in a rotating order, and
the ratios are taken within a repeat; the table gives medians.

    target/python-venv/bin/python python/bench/speed.py [-K 200] [--repeats 9]

numba comes from bench/peers/requirements.txt (pip install numba==...).
"""

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(k, "1")

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench" / "peers"))
import numpy as np  # noqa: E402
import peers  # noqa: E402

import hrla  # noqa: E402

D, N = peers.D, peers.CHAINS


def rastrigin(X):
    t = 2 * np.pi * X
    return D + np.sum(X * X - np.cos(t), axis=1), 2 * X + 2 * np.pi * np.sin(t)


class Package:
    def __init__(self, potential):
        self.opt = hrla.Optimizer(potential, hrla.Hrla.paper(peers.H), peers.A,
                                  hrla.Gaussian([3.0] * D, math.sqrt(10.0)), chains=N, seed=1)

    def run(self, k):
        self.opt.step(k)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("-K", type=int, default=200)
    p.add_argument("--repeats", type=int, default=9)
    args = p.parse_args()
    rng = np.random.default_rng(1)
    x0 = 3.0 + math.sqrt(10.0) * rng.standard_normal((D, N))
    y0 = np.zeros((D, N))
    impls = {
        "hrla, built-in Rastrigin": Package(hrla.Rastrigin()),
        "hrla, batched numpy Rastrigin": Package(rastrigin),
        "numpy peer": peers.NumpyHrla(x0, y0, 1, True),
        "numba peer": peers.NumbaHrla(x0, y0, 1, True),
    }
    for impl in impls.values():  # compile and warm up
        impl.run(5)
    names = list(impls)
    ns = {name: [] for name in names}
    for r in range(args.repeats):
        for name in names[r % len(names):] + names[:r % len(names)]:
            t0 = time.perf_counter()
            impls[name].run(args.K)
            ns[name].append((time.perf_counter() - t0) / (args.K * N * D) * 1e9)
    base = ns[names[0]]
    print(f"10-D Rastrigin, {N} chains, K = {args.K} steps x {args.repeats} interleaved repeats; "
          f"load average {os.getloadavg()[0]:.2f}")
    print("\n| implementation | ns per coordinate-step, median (min-max) | "
          "time / built-in's, median of per-repeat ratios |")
    print("|---|---|---|")
    for name in names:
        ratio = statistics.median(a / b for a, b in zip(ns[name], base))
        v = ns[name]
        print(f"| {name} | {statistics.median(v):.1f} ({min(v):.1f}-{max(v):.1f}) | {ratio:.2f} |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""GPU mode of the peer harness: JAX's HRLA step beside hrla-gpu, on one
device, in one run.

JAX's step is the one of peers.py (`jax.jit` over `lax.fori_loop` of K
steps carrying the state, the value and the running best with its point
and iteration, every step; normals from `jax.random.normal` with the key
folded with the step index), on JAX's default device: the GPU where
`jax[cuda12]` is installed, else the CPU. hrla-gpu's figure comes from its
throughput benchmark (`gpu/benches/throughput.rs`, built by gpu.sh), run
as a process once per repeat, between JAX's repeats, on wgpu's first
adapter: the same GPU through Vulkan, or lavapipe (a software Vulkan on
the CPU) where there is none.

For each N (chains) and float type: ns per coordinate-step = wall time of
K steps / (K N d), median over the repeats (min-max beside it), compile and
warm-up excluded on both sides; chain-steps per second; and JAX's time over
hrla-gpu's (above 1: hrla-gpu is faster). A side that cannot run a size (out
of memory, a buffer beyond the adapter's limit, no f64) says why in its cell.

Run through gpu.sh; see README.md beside this file.
"""

import os

# JAX may use every core of the CPU here (lavapipe does too): peers.py's
# one-thread defaults are for its CPU table, not for this one.
os.environ.setdefault("XLA_FLAGS", "")

import argparse
import datetime
import statistics
import subprocess
import sys
import time

import numpy as np

import peers

D = peers.D


def jax_device():
    jax, _, _ = peers.jax_modules()
    d = jax.devices()[0]
    return f"{d.platform}: {getattr(d, 'device_kind', d)}"


def jax_run(n, dtype, prng, steps, seed=7):
    """JAX's value+best step over n chains, warmed up (compiled, one run)."""
    rng = np.random.default_rng(2024)
    x0 = rng.uniform(-5.12, 5.12, (D, n))
    y0 = np.zeros((D, n))
    impl = peers.JaxHrla(x0, y0, seed, True, dtype, prng)
    del x0, y0
    impl.run(steps)
    return impl


def jax_time(impl, steps):
    t0 = time.perf_counter()
    impl.run(steps)
    return time.perf_counter() - t0


def hrla_gpu_once(binary, n, dtype, arithmetic, steps):
    """(ns per coordinate-step, adapter line) from one run of the benchmark,
    or (None, reason) when it refuses the size or the float type."""
    precision = "f32" if dtype == "float32" else "f64"
    cmd = [binary, "--chains", str(n), "--steps", str(steps), "--precision", precision,
           "--arithmetic", arithmetic]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        last = (out.stderr.strip().splitlines() or ["failed"])[-1]
        return None, last
    adapter, ns = "", None
    for line in out.stdout.splitlines():
        if line.startswith("adapter:"):
            adapter = line.split(":", 1)[1].strip()
        fields = line.split()
        if len(fields) == 6 and fields[0] == str(n):
            # From chain-steps/s (four significant digits) rather than the
            # printed ns, whose three decimals round 0.0105 to 0.011 on a GPU.
            ns = 1e9 / (float(fields[5]) * D)
    if ns is None:
        return None, "no figure in the benchmark's output"
    return ns, adapter


def cell(values):
    if not values:
        return None
    return statistics.median(values), min(values), max(values)


def shown(c, reason):
    if c is None:
        return reason or "n/a"
    med, lo, hi = c
    return f"{med:.4g} ({lo:.4g}–{hi:.4g})"


def rate(c):
    return "" if c is None else f"{1.0 / c[0]:.3g}"  # G coordinate-steps/s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hrla-gpu", required=True, help="hrla-gpu's throughput benchmark binary (gpu.sh builds it)")
    ap.add_argument("--chains", default="1e4,1e5,1e6,1e7", help="comma list of N")
    ap.add_argument("--steps", "-K", type=int, default=100, help="steps per timed repeat")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--dtypes", default="float32,float64")
    ap.add_argument("--prng", default="threefry2x32", help="JAX's PRNG: threefry2x32 or rbg")
    ap.add_argument("--arithmetic", default="ieee,fused", help="hrla-gpu's arithmetics: ieee, fused")
    args = ap.parse_args()
    chains = [int(float(c)) for c in args.chains.split(",")]
    dtypes = args.dtypes.split(",")
    arithmetics = args.arithmetic.split(",")
    started = datetime.datetime.now(datetime.timezone.utc)
    load_before = os.getloadavg()

    # JAX's step checked once per float type (moments of one step against
    # the closed form), as peers.py checks it.
    checks = {}
    for dt in dtypes:
        ok, _, msg = peers.check_one_step(lambda x, y, s, dt=dt: peers.JaxHrla(x, y, s, True, dt, args.prng))
        checks[dt] = ok
        print(f"[check] jax {dt}: {'ok' if ok else 'FAILED'} ({msg})", file=sys.stderr, flush=True)

    rows = []
    adapter = ""
    for n in chains:
        for dt in dtypes:
            impl, jax_reason = None, None
            try:
                impl = jax_run(n, dt, args.prng, args.steps)
            except Exception as e:  # out of memory, most often
                jax_reason = f"JAX: {type(e).__name__}: {str(e).splitlines()[0][:80]}"
            jax_ns, ours = [], {a: [] for a in arithmetics}
            reasons = {a: None for a in arithmetics}
            for rep in range(args.repeats):
                if impl is not None:
                    jax_ns.append(jax_time(impl, args.steps) / (args.steps * n * D) * 1e9)
                for a in arithmetics:
                    if reasons[a] is not None:
                        continue
                    ns, info = hrla_gpu_once(args.hrla_gpu, n, dt, a, args.steps)
                    if ns is None:
                        reasons[a] = f"hrla-gpu: {info[:100]}"
                    else:
                        ours[a].append(ns)
                        adapter = info
                print(f"[time] N = {n} {dt}: repeat {rep + 1}/{args.repeats}", file=sys.stderr, flush=True)
            del impl
            rows.append((n, dt, cell(jax_ns), jax_reason, {a: cell(v) for a, v in ours.items()}, reasons))

    load_after = os.getloadavg()
    print(f"HRLA step, Rastrigin d = {D}, value and running best every step, K = {args.steps} steps per "
          f"repeat, {args.repeats} repeats (JAX and hrla-gpu alternating); {started:%Y-%m-%d %H:%M} UTC")
    print(f"load average before {load_before[0]:.2f} {load_before[1]:.2f} {load_before[2]:.2f}, "
          f"after {load_after[0]:.2f} {load_after[1]:.2f} {load_after[2]:.2f}")
    print(f"JAX device: {jax_device()}; PRNG {args.prng}; versions: "
          + ", ".join(f"{k} {v}" for k, v in peers.versions().items() if k in ("numpy", "jax", "jaxlib", "python")))
    print(f"hrla-gpu adapter: {adapter or 'none ran'}")
    print()
    head = "| chains | float | JAX ns / coordinate-step (median, min–max) | JAX G coord-steps/s "
    for a in arithmetics:
        head += f"| hrla-gpu {a} ns (median, min–max) | hrla-gpu {a} G coord-steps/s | JAX / hrla-gpu {a} "
    print(head + "|")
    print("| ---: | --- | ---: | ---: " + "| ---: | ---: | ---: " * len(arithmetics) + "|")
    for n, dt, jc, jr, oc, orr in rows:
        line = f"| {n:.0e} | {dt}{'' if checks[dt] else ' (check FAILED)'} | {shown(jc, jr)} | {rate(jc)} "
        for a in arithmetics:
            ratio = f"{jc[0] / oc[a][0]:.2f}x" if jc and oc[a] else ""
            line += f"| {shown(oc[a], orr[a])} | {rate(oc[a])} | {ratio} "
        print(line + "|")
    print()
    print("JAX / hrla-gpu = JAX's median time over hrla-gpu's for the same N and float type: above 1, "
          "hrla-gpu is faster. ieee: hrla-gpu keeps the CPU kernel's roundings (its bits where the device "
          "rounds as IEEE 754 does); fused: the driver may contract and reorder.")
    return 0 if all(checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main())

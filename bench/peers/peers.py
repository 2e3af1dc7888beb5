#!/usr/bin/env python3
"""Peer harness: the HRLA step (docs: shared spec, section 4) on Rastrigin in
numpy, numba and JAX, timed per coordinate-step and compared with this crate.

    U(x) = d + |x|^2 - sum_i cos(2 pi x_i),   grad U = 2x + 2 pi sin(2 pi x)

Paper parameters a = 4, b = 10, alpha = beta = 1, h = 0.01 (gamma = a/b,
sx2 = beta/a, sy2 = alpha/b). Every implementation uses the same constants,
computed once in float64 by `coefficients` below, and the same algebra:

    G = x + pi sin(2 pi x)                      (so grad U = 2 G)
    x' = x + c1 y - kx G + Lxy z1 + Lxx z2
    y' = e y  - ky G + Lyy z1

with c1 = (1 - e)/alpha, kx = 2 (beta h + (gamma/alpha)(h - (1 - e)/alpha)),
ky = 2 (gamma/alpha)(1 - e), and (Lyy, Lxy, Lxx) the 2x2 Cholesky factor of
the step's covariance. The "value+best" variants also evaluate U(x_k) from
the same angle (sin and cos both) and keep, per chain, the running minimum of
U with the position and the iteration where it was reached (as the crate's
`Optimizer::step` does).

Run through run.sh (which creates the virtualenv and pins threads); see
README.md beside this file.
"""

import os

# Thread pinning must happen before numpy / numba / jax are imported.
for _k, _v in {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "NUMBA_NUM_THREADS": "1",
    "XLA_FLAGS": "--xla_cpu_multi_thread_eigen=false",
}.items():
    os.environ.setdefault(_k, _v)

import sys


def _pin_cpu_early():
    """--cpu N pins the whole process (and every thread pool created later:
    OpenBLAS, XLA) to CPU N, so that no tool gets more than one core;
    default: the last CPU this process may run on; --cpu none: no pinning.
    Done before numpy/numba/jax are imported."""
    arg = "last"
    for i, a in enumerate(sys.argv):
        if a == "--cpu" and i + 1 < len(sys.argv):
            arg = sys.argv[i + 1]
        elif a.startswith("--cpu="):
            arg = a.split("=", 1)[1]
    if arg == "none" or not hasattr(os, "sched_setaffinity"):
        return None
    cpu = max(os.sched_getaffinity(0)) if arg == "last" else int(arg)
    os.sched_setaffinity(0, {cpu})
    return cpu


PINNED_CPU = _pin_cpu_early() if __name__ == "__main__" else None

import argparse
import datetime
import json
import math
import platform
import shlex
import statistics
import subprocess
import time
from pathlib import Path

import numpy as np

D = 10
CHAINS = 1000
PI = math.pi
TWO_PI = 2.0 * math.pi
# Paper parameters.
A, B, ALPHA, BETA, H = 4.0, 10.0, 1.0, 1.0, 0.01


# ---------------------------------------------------------------------------
# Coefficients (float64, once), with the cancellations of section 4 avoided.
# ---------------------------------------------------------------------------

def _bracket(u):
    """2u - e^2 + 4e - 3 with e = exp(-u), accurate for small u."""
    if u < 0.5:
        # sum_{n>=3} (-1)^n (4 - 2^n) u^n / n!
        s, term = 0.0, 1.0
        for n in range(1, 40):
            term *= u / n  # u^n / n!
            if n >= 3:
                s += (-1) ** n * (4.0 - 2.0 ** n) * term
        return s
    e = math.exp(-u)
    return 2.0 * u - e * e + 4.0 * e - 3.0


def _u_minus_one_minus_e(u):
    """u - (1 - exp(-u)), accurate for small u."""
    if u < 0.5:
        # sum_{n>=2} -(-u)^n / n!
        s, term = 0.0, 1.0
        for n in range(1, 40):
            term *= u / n
            if n >= 2:
                s -= (-1) ** n * term
        return s
    return u + math.expm1(-u)


def coefficients(a=A, b=B, alpha=ALPHA, beta=BETA, h=H):
    gamma, sx2, sy2 = a / b, beta / a, alpha / b
    u = alpha * h
    om = -math.expm1(-u)  # 1 - e
    e = 1.0 - om
    q = _u_minus_one_minus_e(u) / alpha  # h - (1 - e)/alpha
    cgx = beta * h + (gamma / alpha) * q  # coefficient of g in mean_x
    cgy = (gamma / alpha) * om  # coefficient of g in mean_y
    one_minus_e2 = -math.expm1(-2.0 * u)
    sxx = (sy2 / alpha**3) * _bracket(u) + 2.0 * sx2 * h
    syy = sy2 * one_minus_e2 / alpha
    sxy = sy2 * om * om / alpha**2
    # Schur complement Sxx - Sxy^2/Syy = sy2/alpha^3 (bracket - om^3/(1+e)) + 2 sx2 h
    schur = (sy2 / alpha**3) * (_bracket(u) - om**3 / (1.0 + e)) + 2.0 * sx2 * h
    lyy = math.sqrt(syy)
    return dict(
        e=e, c1=om / alpha, kx=2.0 * cgx, ky=2.0 * cgy,
        lyy=lyy, lxy=sxy / lyy, lxx=math.sqrt(schur),
        sxx=sxx, syy=syy, sxy=sxy, cgx=cgx, cgy=cgy,
    )


C = coefficients()


def closed_form(x0, y0, a=A, b=B, alpha=ALPHA, beta=BETA, h=H):
    """Mean and covariance of one step straight from the spec's formulas
    (deliberately a different code path from the folded coefficients)."""
    gamma, sx2, sy2 = a / b, beta / a, alpha / b
    e = math.exp(-alpha * h)
    g = 2.0 * x0 + TWO_PI * np.sin(TWO_PI * x0)
    mean_x = x0 - beta * h * g + (1 - e) / alpha * y0 - (gamma / alpha) * (h - (1 - e) / alpha) * g
    mean_y = e * y0 - (gamma / alpha) * (1 - e) * g
    sxx = (sy2 / alpha**3) * (2 * alpha * h - e * e + 4 * e - 3) + 2 * sx2 * h
    syy = sy2 * (1 - e * e) / alpha
    sxy = sy2 * (1 - e) ** 2 / alpha**2
    return mean_x, mean_y, sxx, syy, sxy


def rastrigin(x):
    """U per chain, x of shape (d, n)."""
    return x.shape[0] + np.sum(x * x - np.cos(TWO_PI * x), axis=0)


# ---------------------------------------------------------------------------
# Implementations. Each `make_*` returns an object with
#   .run(K)   advance all chains K steps (timed),
#   .state()  (x, y) as float64 arrays of shape (d, n),
#   .best()   (best value per chain, best x (d, n)) or None.
# All state is set from float64 (d, n) arrays x0, y0.
# ---------------------------------------------------------------------------

BIT_GENERATOR = "SFC64"  # fastest numpy BitGenerator for normals here (measured, see README)


def new_generator(seed):
    return np.random.Generator(getattr(np.random, BIT_GENERATOR)(seed))


class NumpyHrla:
    """Preallocated (d, n) arrays, in-place ufuncs, one block of 2 d n
    normals per step via Generator.standard_normal(out=...)."""

    def __init__(self, x0, y0, seed, value):
        d, n = x0.shape
        self.value = value
        self.x = x0.copy()
        self.y = y0.copy()
        self.t = np.empty_like(self.x)  # angle, then scratch
        self.s = np.empty_like(self.x)  # sin, then G
        self.c = np.empty_like(self.x)  # cos (value only)
        self.z = np.empty((2, d, n))
        self.u = np.empty(n)
        self.imp = np.empty(n, dtype=bool)
        self.best_u = np.full(n, np.inf)
        self.best_x = self.x.copy()
        self.best_k = np.zeros(n, dtype=np.int64)
        self.k = 0
        self.rng = new_generator(seed)

    def run(self, K):
        x, y, t, s, c, z, u = self.x, self.y, self.t, self.s, self.c, self.z, self.u
        z1, z2 = z[0], z[1]
        e, c1, kx, ky = C["e"], C["c1"], C["kx"], C["ky"]
        lyy, lxy, lxx = C["lyy"], C["lxy"], C["lxx"]
        mul, add, sub = np.multiply, np.add, np.subtract
        d = float(x.shape[0])
        std_normal = self.rng.standard_normal
        for _ in range(K):
            mul(x, TWO_PI, out=t)
            np.sin(t, out=s)
            if self.value:
                # U(x_k) = d + sum_i (x_i^2 - cos(2 pi x_i)); running best of x_k.
                np.cos(t, out=c)
                mul(x, x, out=t)
                sub(t, c, out=t)
                np.sum(t, axis=0, out=u)
                add(u, d, out=u)
                np.less(u, self.best_u, out=self.imp)
                np.copyto(self.best_u, u, where=self.imp)
                np.copyto(self.best_x, x, where=self.imp)  # broadcasts over d
                np.copyto(self.best_k, self.k, where=self.imp)
            mul(s, PI, out=s)
            add(s, x, out=s)  # s = G = x + pi sin(2 pi x); grad U = 2 G
            std_normal(out=z)
            # x' = x + c1 y - kx G + Lxy z1 + Lxx z2 (uses the old y)
            mul(y, c1, out=t)
            add(x, t, out=x)
            mul(s, kx, out=t)
            sub(x, t, out=x)
            mul(z1, lxy, out=t)
            add(x, t, out=x)
            mul(z2, lxx, out=t)
            add(x, t, out=x)
            # y' = e y - ky G + Lyy z1
            mul(y, e, out=y)
            mul(s, ky, out=t)
            sub(y, t, out=y)
            mul(z1, lyy, out=t)
            add(y, t, out=y)
            self.k += 1

    def state(self):
        return self.x, self.y

    def best(self):
        return (self.best_u, self.best_x) if self.value else None


class NumpyMatmulHrla:
    """As NumpyHrla, but the whole linear part of the step is one BLAS call:
    with W = [x; y; sin(2 pi x); z1; z2] stored as five contiguous rows,
    [x'; y'] = M @ W for a constant 2x5 matrix M (G = x + pi sin folded into
    M). Double-buffered W; OpenBLAS pinned to one thread."""

    def __init__(self, x0, y0, seed, value):
        d, n = x0.shape
        self.value, self.shape = value, (d, n)
        self.w = [np.empty((5, d * n)), np.empty((5, d * n))]
        self.w[0][0] = x0.ravel()
        self.w[0][1] = y0.ravel()
        kx, ky = C["kx"], C["ky"]
        self.m = np.array([
            [1.0 - kx, C["c1"], -kx * PI, C["lxy"], C["lxx"]],
            [-ky, C["e"], -ky * PI, C["lyy"], 0.0],
        ])
        self.t = np.empty((d, n))
        self.c = np.empty((d, n))
        self.u = np.empty(n)
        self.imp = np.empty(n, dtype=bool)
        self.best_u = np.full(n, np.inf)
        self.best_x = x0.copy()
        self.best_k = np.zeros(n, dtype=np.int64)
        self.k = 0
        self.rng = new_generator(seed)

    def run(self, K):
        mul, sub, add = np.multiply, np.subtract, np.add
        t, c, u, m, shape = self.t, self.c, self.u, self.m, self.shape
        d = float(shape[0])
        std_normal = self.rng.standard_normal
        w = self.w
        for _ in range(K):
            a, b = w
            x = a[0].reshape(shape)
            s = a[2].reshape(shape)
            mul(x, TWO_PI, out=t)
            np.sin(t, out=s)
            if self.value:
                np.cos(t, out=c)
                mul(x, x, out=t)
                sub(t, c, out=t)
                np.sum(t, axis=0, out=u)
                add(u, d, out=u)
                np.less(u, self.best_u, out=self.imp)
                np.copyto(self.best_u, u, where=self.imp)
                np.copyto(self.best_x, x, where=self.imp)
                np.copyto(self.best_k, self.k, where=self.imp)
            std_normal(out=a[3:5])
            np.matmul(m, a, out=b[0:2])
            w.reverse()
            self.k += 1

    def state(self):
        a = self.w[0]
        return a[0].reshape(self.shape), a[1].reshape(self.shape)

    def best(self):
        return (self.best_u, self.best_x) if self.value else None


# --- numba ---------------------------------------------------------------

_numba_kernels = None


def numba_kernels():
    global _numba_kernels
    if _numba_kernels is not None:
        return _numba_kernels
    from numba import njit

    @njit(cache=False, fastmath=False, error_model="numpy")
    def run_novalue(x, y, K, rng, e, c1, kx, ky, lyy, lxy, lxx):
        n, d = x.shape
        for _ in range(K):
            for j in range(n):
                for i in range(d):
                    xi = x[j, i]
                    yi = y[j, i]
                    g = xi + PI * math.sin(TWO_PI * xi)
                    z1 = rng.standard_normal()
                    z2 = rng.standard_normal()
                    x[j, i] = xi + c1 * yi - kx * g + lxy * z1 + lxx * z2
                    y[j, i] = e * yi - ky * g + lyy * z1

    @njit(cache=False, fastmath=False, error_model="numpy")
    def run_value(x, y, K, k0, rng, e, c1, kx, ky, lyy, lxy, lxx,
                  best_u, best_x, best_k, gbuf):
        n, d = x.shape
        for k in range(k0, k0 + K):
            for j in range(n):
                u = 0.0
                for i in range(d):
                    xi = x[j, i]
                    ang = TWO_PI * xi
                    gbuf[i] = xi + PI * math.sin(ang)
                    u += xi * xi - math.cos(ang)
                u += d
                if u < best_u[j]:
                    best_u[j] = u
                    best_k[j] = k
                    for i in range(d):
                        best_x[j, i] = x[j, i]
                for i in range(d):
                    xi = x[j, i]
                    yi = y[j, i]
                    g = gbuf[i]
                    z1 = rng.standard_normal()
                    z2 = rng.standard_normal()
                    x[j, i] = xi + c1 * yi - kx * g + lxy * z1 + lxx * z2
                    y[j, i] = e * yi - ky * g + lyy * z1

    _numba_kernels = (run_novalue, run_value)
    return _numba_kernels


class NumbaHrla:
    """@njit loop over steps, chains (outer) and coordinates (inner); the
    numpy Generator is passed in and drawn from with scalar
    rng.standard_normal(). Chain-major (n, d) layout so a chain's value and
    running best are computed next to its update."""

    def __init__(self, x0, y0, seed, value):
        self.value = value
        self.x = np.ascontiguousarray(x0.T)
        self.y = np.ascontiguousarray(y0.T)
        n, d = self.x.shape
        self.best_u = np.full(n, np.inf)
        self.best_x = self.x.copy()
        self.best_k = np.zeros(n, dtype=np.int64)
        self.gbuf = np.empty(d)
        self.k = 0
        self.rng = new_generator(seed)
        self.kernels = numba_kernels()

    def run(self, K):
        cs = (C["e"], C["c1"], C["kx"], C["ky"], C["lyy"], C["lxy"], C["lxx"])
        if self.value:
            self.kernels[1](self.x, self.y, K, self.k, self.rng, *cs,
                            self.best_u, self.best_x, self.best_k, self.gbuf)
        else:
            self.kernels[0](self.x, self.y, K, self.rng, *cs)
        self.k += K

    def state(self):
        return self.x.T, self.y.T

    def best(self):
        return (self.best_u, self.best_x.T) if self.value else None


# --- JAX -----------------------------------------------------------------

_jax = None


def jax_modules():
    global _jax
    if _jax is None:
        import jax

        jax.config.update("jax_enable_x64", True)
        import jax.numpy as jnp
        from jax import lax

        _jax = (jax, jnp, lax)
    return _jax


_jax_cache = {}


def jax_runner(dtype_name, value, K, prng_impl):
    """jit(fori_loop of K steps) over a carried state; cached per signature."""
    key = (dtype_name, value, K)
    if key in _jax_cache:
        return _jax_cache[key]
    jax, jnp, lax = jax_modules()
    dt = jnp.float64 if dtype_name == "float64" else jnp.float32
    cst = {k: np.asarray(C[k], dtype=dt) for k in ("e", "c1", "kx", "ky", "lyy", "lxy", "lxx")}
    pi, two_pi = np.asarray(PI, dtype=dt), np.asarray(TWO_PI, dtype=dt)

    def step(k, carry):
        x, y, rkey, bu, bx, bk = carry
        ang = two_pi * x
        g = x + pi * jnp.sin(ang)  # grad U = 2 g
        if value:
            u = x.shape[0] + jnp.sum(x * x - jnp.cos(ang), axis=0)
            imp = u < bu
            bu = jnp.where(imp, u, bu)
            bx = jnp.where(imp[None, :], x, bx)
            bk = jnp.where(imp, k, bk)
        z = jax.random.normal(jax.random.fold_in(rkey, k), (2,) + x.shape, dt)
        xn = x + cst["c1"] * y - cst["kx"] * g + cst["lxy"] * z[0] + cst["lxx"] * z[1]
        yn = cst["e"] * y - cst["ky"] * g + cst["lyy"] * z[0]
        return (xn, yn, rkey, bu, bx, bk)

    @jax.jit
    def run(carry, k0):
        return lax.fori_loop(k0, k0 + K, step, carry)

    _jax_cache[key] = run
    return run


class JaxHrla:
    """jax.jit over lax.fori_loop of K steps; jax.random normals from a key
    folded with the step index; (d, n) layout."""

    def __init__(self, x0, y0, seed, value, dtype="float64", prng_impl="threefry2x32"):
        jax, jnp, _ = jax_modules()
        dt = jnp.float64 if dtype == "float64" else jnp.float32
        self.value, self.dtype, self.prng_impl = value, dtype, prng_impl
        n = x0.shape[1]
        rkey = jax.random.key(seed, impl=prng_impl)
        self.carry = (jnp.asarray(x0, dt), jnp.asarray(y0, dt), rkey,
                      jnp.full((n,), jnp.inf, dt), jnp.asarray(x0, dt),
                      jnp.zeros((n,), jnp.int32))
        self.k = 0

    def run(self, K):
        f = jax_runner(self.dtype, self.value, K, self.prng_impl)
        self.carry = f(self.carry, np.int32(self.k))
        self.carry[0].block_until_ready()
        self.k += K

    def state(self):
        return np.asarray(self.carry[0], np.float64), np.asarray(self.carry[1], np.float64)

    def best(self):
        if not self.value:
            return None
        return np.asarray(self.carry[3], np.float64), np.asarray(self.carry[4], np.float64)


# ---------------------------------------------------------------------------
# Correctness: one step from a fixed state against the closed form.
# ---------------------------------------------------------------------------

def check_one_step(factory, m=50000, sigmas=5.0):
    """One step of m chains from the same (x0, y0): per coordinate, the
    empirical means of x' and y', their variances and covariance within `sigmas`
    standard errors of the closed form; for value variants, the recorded best
    equals U(x0). Returns (ok, worst |z-score|, message)."""
    x0c = np.linspace(-4.7, 4.9, D)  # spans several Rastrigin wells
    y0c = np.linspace(20.0, -15.0, D)  # large momenta, so that c1 y is resolved
    x0 = np.repeat(x0c[:, None], m, axis=1)
    y0 = np.repeat(y0c[:, None], m, axis=1)
    impl = factory(x0, y0, 12345)
    impl.run(1)
    x1, y1 = impl.state()
    mx, my, sxx, syy, sxy = closed_form(x0c, y0c)
    zs = []
    zs += list((x1.mean(axis=1) - mx) / math.sqrt(sxx / m))
    zs += list((y1.mean(axis=1) - my) / math.sqrt(syy / m))
    vx = x1.var(axis=1, ddof=1)
    vy = y1.var(axis=1, ddof=1)
    zs += list((vx - sxx) / (sxx * math.sqrt(2.0 / (m - 1))))
    zs += list((vy - syy) / (syy * math.sqrt(2.0 / (m - 1))))
    cxy = np.mean((x1 - x1.mean(axis=1, keepdims=True)) * (y1 - y1.mean(axis=1, keepdims=True)), axis=1)
    zs += list((cxy - sxy) / math.sqrt((sxx * syy + sxy * sxy) / m))  # Var of a Gaussian product
    worst = float(np.max(np.abs(zs)))
    ok = worst < sigmas
    msg = f"max |z| = {worst:.2f} over {len(zs)} moments"
    b = impl.best()
    if b is not None:
        u0 = rastrigin(x0c[:, None])[0]
        tol = 1e-4 if getattr(impl, "dtype", "float64") == "float32" else 1e-12
        err_u = float(np.max(np.abs(b[0] - u0))) / u0
        err_x = float(np.max(np.abs(b[1] - x0)))
        ok = ok and err_u < tol and err_x < tol * 10
        msg += f"; best = U(x0) to rel {err_u:.1e}"
    return ok, worst, msg


# ---------------------------------------------------------------------------
# Timing.
# ---------------------------------------------------------------------------

def time_once(impl, K):
    c0, t0 = time.process_time(), time.perf_counter()
    impl.run(K)
    t1, c1 = time.perf_counter(), time.process_time()
    return t1 - t0, c1 - c0


def summarise(impl, K, walls, cpus):
    n = impl.state()[0].shape[1]
    per = [w / (K * n * D) * 1e9 for w in walls]
    per_cpu = [c / (K * n * D) * 1e9 for c in cpus]
    return dict(median=statistics.median(per), lo=min(per), hi=max(per),
                cpu_median=statistics.median(per_cpu), cpu_wall=sum(cpus) / sum(walls))


def hrla_figures(args):
    """This crate's ns per coordinate-step, keyed by (float, value+best?),
    and where they came from."""
    figs, sources = {}, []
    if args.hrla_ns is not None:
        figs[("f64", True)] = args.hrla_ns
        if args.hrla_ns_novalue is not None:
            figs[("f64", False)] = args.hrla_ns_novalue
        return figs, "command line (--hrla-ns / --hrla-ns-novalue)"
    target = os.environ.get("CARGO_TARGET_DIR", str(Path(__file__).resolve().parents[2] / "target"))
    root = Path(target) / "criterion"
    # criterion names the directory of group "f64/d10", function "hrla/best",
    # value "1000" as f64_d10/hrla_best/1000 (see its benchmark.json).
    for fl in ("f64", "f32"):
        for value, name in ((True, "hrla_best"), (False, "hrla_no-value")):
            new = root / f"{fl}_d10" / name / "1000" / "new"
            est = new / "estimates.json"
            if not est.exists():
                continue
            median_ns = json.loads(est.read_text())["median"]["point_estimate"]
            elems = CHAINS * D  # criterion's Throughput::Elements: coordinate-steps per iteration
            bj = new / "benchmark.json"
            if bj.exists():
                elems = json.loads(bj.read_text()).get("throughput", {}).get("Elements", elems)
            figs[(fl, value)] = median_ns / elems
            mtime = datetime.datetime.fromtimestamp(est.stat().st_mtime, datetime.timezone.utc)
            sources.append(f"{est} (median {median_ns / 1e3:.1f} us per {elems} coordinate-steps, "
                           f"written {mtime:%Y-%m-%d %H:%M} UTC)")
    if not figs:
        return figs, f"not found under {root}; pass --hrla-ns"
    return figs, "criterion: " + "; ".join(sources)


def versions():
    v = {"python": platform.python_version(), "numpy": np.__version__}
    try:
        import numba, llvmlite
        v["numba"] = numba.__version__
        v["llvmlite"] = llvmlite.__version__
    except ImportError:
        pass
    try:
        import jax, jaxlib
        v["jax"] = jax.__version__
        v["jaxlib"] = jaxlib.__version__
    except ImportError:
        pass
    return v


def print_paired(paired, crate_ns):
    """The same-stretch ratios: peer repeat r over the crate's run r."""
    if not paired:
        return
    print()
    print(f"Same stretch: the crate (f64 value+best) ran between the peers' repeats: "
          f"{statistics.median(crate_ns):.2f} ns median ({min(crate_ns):.2f}-{max(crate_ns):.2f}); "
          f"ratio = peer repeat r / crate run r, median of {len(crate_ns)} pairs")
    print()
    print("| implementation | variant | ratio to hrla (median of pairs) | min–max |")
    print("| --- | --- | ---: | ---: |")
    for tool, variant, med, lo, hi in paired:
        print(f"| {tool} | {variant} | {med:.2f}x | {lo:.2f}–{hi:.2f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hrla-ns", type=float, help="hrla ns per coordinate-step, value + running best")
    ap.add_argument("--hrla-ns-novalue", type=float, help="hrla ns per coordinate-step, no value")
    ap.add_argument("--hrla-cmd",
                    help="a command printing the crate's f64 value+best ns per coordinate-step (e.g. "
                         "target/release/step f64 2000), run once per repeat between the peers' repeats: "
                         "the ratios are then per pair, from one stretch of time")
    ap.add_argument("--steps", "-K", type=int, default=2000)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--only", default="", help="comma list among numpy,numba,jax")
    ap.add_argument("--cpu", default="last",
                    help="pin the process to this CPU (default: the last allowed one; 'none': do not pin)")
    args = ap.parse_args()
    if args.repeats < 5:
        ap.error("--repeats must be >= 5")

    only = set(filter(None, args.only.split(",")))
    want = lambda name: not only or name in only

    # (tool, variant, value?, factory)
    impls = []
    if want("numpy"):
        impls += [
            ("numpy", f"no value ({BIT_GENERATOR})", False, lambda x, y, s: NumpyHrla(x, y, s, False)),
            ("numpy", f"value+best ({BIT_GENERATOR})", True, lambda x, y, s: NumpyHrla(x, y, s, True)),
            ("numpy", f"no value, matmul update ({BIT_GENERATOR})", False,
             lambda x, y, s: NumpyMatmulHrla(x, y, s, False)),
            ("numpy", f"value+best, matmul update ({BIT_GENERATOR})", True,
             lambda x, y, s: NumpyMatmulHrla(x, y, s, True)),
        ]
    if want("numba"):
        impls += [
            ("numba", f"no value ({BIT_GENERATOR})", False, lambda x, y, s: NumbaHrla(x, y, s, False)),
            ("numba", f"value+best ({BIT_GENERATOR})", True, lambda x, y, s: NumbaHrla(x, y, s, True)),
        ]
    if want("jax"):
        for dt in ("float64", "float32"):
            for impl in ("threefry2x32", "rbg"):
                impls += [
                    ("jax", f"{dt} value+best ({impl})", True,
                     lambda x, y, s, dt=dt, impl=impl: JaxHrla(x, y, s, True, dt, impl)),
                ]
        impls += [
            ("jax", "float64 no value (threefry2x32)", False,
             lambda x, y, s: JaxHrla(x, y, s, False, "float64", "threefry2x32")),
        ]

    load_before = os.getloadavg()
    started = datetime.datetime.now(datetime.timezone.utc)
    figs, source = hrla_figures(args)

    rng0 = np.random.default_rng(2024)
    x_start = rng0.uniform(-5.12, 5.12, (D, CHAINS))
    y_start = np.zeros((D, CHAINS))

    # Check every implementation, then warm each up (compilation excluded),
    # then time them round-robin: repeat r of every implementation runs in
    # the same stretch of time, so changes in the machine's load hit all alike.
    live = []
    for tool, variant, value, factory in impls:
        ok, worst, msg = check_one_step(factory)
        print(f"[check] {tool} {variant}: {'ok' if ok else 'FAILED'} ({msg})", file=sys.stderr, flush=True)
        impl = factory(x_start, y_start, 7)
        impl.run(args.steps)  # warm-up: compilation (numba, JAX), caches, page faults
        live.append((tool, variant, value, impl, ok, [], []))
    crate_ns = []
    for rep in range(args.repeats):
        for tool, variant, value, impl, ok, walls, cpus in live:
            w, c = time_once(impl, args.steps)
            walls.append(w)
            cpus.append(c)
        if args.hrla_cmd:
            out = subprocess.run(shlex.split(args.hrla_cmd), check=True, capture_output=True, text=True)
            crate_ns.append(float(out.stdout.split()[-1]))
        print(f"[time]  repeat {rep + 1}/{args.repeats} done", file=sys.stderr, flush=True)
    if crate_ns:
        figs[("f64", True)] = statistics.median(crate_ns)
        source = f"`{args.hrla_cmd}`, run between the peers' repeats"
    rows = []
    paired = []
    for tool, variant, value, impl, ok, walls, cpus in live:
        r = summarise(impl, args.steps, walls, cpus)
        if crate_ns and value and "float32" not in variant:
            n = impl.state()[0].shape[1]
            ratios = [w / (args.steps * n * D) * 1e9 / h for w, h in zip(walls, crate_ns)]
            paired.append((tool, variant, statistics.median(ratios), min(ratios), max(ratios)))
        fl = "f32" if "float32" in variant else "f64"
        ref = figs.get((fl, value))
        note = ""
        if ref is None and fl == "f32":  # no f32 figure for the crate: compare with its f64 one
            ref, note = figs.get(("f64", value)), " (vs f64)"
        ratio = f"{r['median'] / ref:.1f}x{note}" if ref else "n/a"
        rows.append((tool, variant, r, ratio, ok))

    load_after = os.getloadavg()
    print(f"HRLA step, Rastrigin d = {D}, {CHAINS} chains, K = {args.steps} steps per repeat, "
          f"{args.repeats} repeats (round-robin over the implementations); {started:%Y-%m-%d %H:%M} UTC, {os.cpu_count()} CPUs, "
          + (f"process pinned to CPU {PINNED_CPU}" if PINNED_CPU is not None else "process not pinned"))
    print(f"load average before {load_before[0]:.2f} {load_before[1]:.2f} {load_before[2]:.2f}, "
          f"after {load_after[0]:.2f} {load_after[1]:.2f} {load_after[2]:.2f}")
    print("versions: " + ", ".join(f"{k} {v}" for k, v in versions().items()))
    print("hrla: " + ", ".join(f"{fl} {'value+best' if v else 'no value'} {x:.2f} ns"
                               for (fl, v), x in sorted(figs.items())) + f"; from {source}")
    print()
    print("| implementation | variant | ns / coordinate-step (median) | min–max | CPU-time ns (median) | cpu/wall "
          "| one-step check | ratio to hrla |")
    print("| --- | --- | ---: | ---: | ---: | ---: | --- | ---: |")
    for (fl, v), x in sorted(figs.items(), key=lambda kv: (kv[0][0] != "f64", not kv[0][1])):
        print(f"| hrla (this crate) | {fl} {'value+best' if v else 'no value'} | {x:.1f} | | | "
              f"| crate's own tests | 1.0x |")
    if not figs:
        print("| hrla (this crate) | f64 value+best | n/a | | | | | |")
    for tool, variant, r, ratio, ok in rows:
        print(f"| {tool} | {variant} | {r['median']:.1f} | {r['lo']:.1f}–{r['hi']:.1f} | "
              f"{r['cpu_median']:.1f} | {r['cpu_wall']:.2f} | {'ok' if ok else 'FAILED'} | {ratio} |")
    print()
    print("ratio = peer median / hrla median for the same float and variant (value+best or no value); "
          "numpy and numba are float64; ns figures and the ratio are wall time; CPU-time ns = process "
          "CPU time (all threads) per coordinate-step; cpu/wall = CPU time / wall time while timed "
          "(< 1: the core was shared with other processes; > 1: more than one thread working).")
    print_paired(paired, crate_ns)
    return 0 if all(r[4] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())

"""Hostile input: wrong types, huge counts, calls while a run runs,
Ctrl-C, potentials unbounded below or undefined at a start. Each gets a
typed exception (the hierarchy under `hrla.HrlaError`, `MemoryError`,
`KeyboardInterrupt`) or a correct answer, never a panic, an abort, a hang
or a silently wrong value."""

import resource
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import hrla

HERE = Path(__file__).resolve().parent


def isolated(code, timeout=120):
    """Runs `code` in a fresh interpreter limited to 4 GiB of address
    space, so that an abort or a runaway allocation fails this test
    instead of the test session or the machine. Returns the process."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))

    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                          preexec_fn=limit)


def sphere(X):
    return np.sum(X * X, axis=1), 2 * X


def pointwise(batch):
    """A batched potential as minimize's fun with jac=True: x (D,) -> (f, g)."""
    def fun(x):
        u, g = batch(np.asarray(x)[None, :])
        return u[0], g[0]
    return fun


# --- the values a potential returns ------------------------------------


@pytest.mark.parametrize("fun, what", [
    (lambda X: (np.sum(X * X, axis=1) + 1j, 2 * X), "U .*complex"),
    (lambda X: (np.sum(X * X, axis=1), (2 * X).astype(complex)), "G .*complex"),
    (lambda X: (np.sum(X * X, axis=1), X > 0), "G .*bool"),
    (lambda X: (np.array([str(v) for v in np.sum(X * X, axis=1)]), 2 * X), "U .*<U"),
    (lambda X: (np.sum(X * X, axis=1).astype(object), 2 * X), "U .*object"),
    (lambda X: ([True] * len(X), 2 * X), "U .*bool"),
])
def test_a_potential_must_return_real_numbers(fun, what):
    # The batched call (initial points and steps), and one row at a time
    # (Auto, the polish).
    with pytest.raises(TypeError, match=f"the potential's {what}"):
        hrla.Optimizer(fun, hrla.Hrla.paper(0.01), 1.0, hrla.Interval(-1, 1), dim=2)
    with pytest.raises(TypeError, match="must be real numbers"):
        hrla.Auto().minimize(fun, hrla.Interval(-1, 1), 2_000, dim=2)
    # minimize's vectorized fun with jac=True (columns).
    def columns(x):
        u, g = fun(x.T)
        return u, np.asarray(g).T

    with pytest.raises(TypeError, match="fun's (values|gradient) must be real numbers"):
        hrla.minimize(columns, [(-1, 1)] * 2, jac=True, vectorized=True, maxfun=2_000)


@pytest.mark.parametrize("value", [1j, True, "1.5", None, np.array([1.0, 2.0]), object()])
def test_a_scalar_fun_must_return_one_real_number(value):
    for method in ("auto", "hrla"):
        with pytest.raises(TypeError, match="fun must return a real number"):
            hrla.minimize(lambda x: value, [(-1, 1)] * 2, method=method, maxfun=2_000)


def test_real_values_of_every_real_dtype_are_accepted():
    for dtype in (np.float16, np.float32, np.float64, np.int64, np.uint8):
        def fun(X, dtype=dtype):
            return np.round(np.sum(X * X, axis=1)).astype(dtype), np.round(2 * X).astype(dtype)

        opt = hrla.Optimizer(fun, hrla.Ola.paper(0.01), 1.0, hrla.Point([0.5, 0.5]), chains=2,
                             stop=hrla.Stop().steps(3))
        assert opt.run().iterations == 3
    # Plain Python lists of floats and ints.
    opt = hrla.Optimizer(lambda X: ([1.0] * len(X), [[0, 1]] * len(X)), hrla.Ola.paper(0.01), 1.0,
                         hrla.Point([0.5, 0.5]), chains=2, stop=hrla.Stop().steps(3))
    assert opt.run().iterations == 3


def test_bounds_must_be_real_numbers():
    for bounds in ([("-1", "1")] * 2, [(-1 + 0j, 1)] * 2, [(False, True)] * 2, ("0", "1")):
        with pytest.raises(TypeError, match="bounds must be real numbers"):
            hrla.minimize(sphere, bounds, dim=2, method="hrla", maxfun=2_000)


# --- huge chain counts ---------------------------------------------------


@pytest.mark.parametrize("chains, potential", [
    (2**40, "hrla.Rastrigin()"),
    (2**62, "hrla.Rastrigin()"),
    (2**63, "lambda X: (np.sum(X * X, axis=1), 2 * X)"),
    (2**64 - 1, "lambda X: (np.sum(X * X, axis=1), 2 * X)"),
])
def test_huge_chain_counts_raise_memory_error_and_allocate_nothing(chains, potential):
    p = isolated(f"""
import numpy as np, hrla
try:
    hrla.Optimizer({potential}, hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.0] * 10), chains={chains})
except MemoryError as e:
    print("MemoryError:", e)
try:
    hrla.Auto().minimize({potential}, hrla.Interval(-1, 1), 10**6, chains={chains}, dim=10)
except MemoryError as e:
    print("MemoryError:", e)
""")
    assert p.returncode == 0, p.stderr[-2000:]
    lines = p.stdout.splitlines()
    assert len(lines) == 2 and all(line.startswith(f"MemoryError: chains={chains}:") for line in lines), p.stdout


def test_a_count_out_of_range_is_an_error_naming_it():
    with pytest.raises(OverflowError, match="chains = 18446744073709551616 is too large"):
        hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.0]), chains=2**64)
    # Negative: ValueError naming the argument, not Python's OverflowError
    # ("can't convert negative int to unsigned").
    for name in ("chains", "seed", "stride", "dim"):
        with pytest.raises(ValueError, match=f"{name} must be >= 0, got -1"):
            hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.0]), **{name: -1})
    for name in ("seed", "chains", "dim"):
        with pytest.raises(ValueError, match=f"{name} must be >= 0, got -1"):
            hrla.Auto().minimize(hrla.Rastrigin(), hrla.Interval(-1, 1), 1_000, **{name: -1})
    with pytest.raises(ValueError, match="budget must be >= 0, got -5"):
        hrla.Auto().minimize(hrla.Rastrigin(), hrla.Interval(-1, 1), -5, dim=2)
    for name in ("steps", "quench", "stall"):
        with pytest.raises(ValueError, match=f"{name} must be >= 0, got -2"):
            hrla.Auto(**{name: -2})
    with pytest.raises(ValueError, match="steps must be >= 0, got -1"):
        hrla.Stop().steps(-1)
    with pytest.raises(ValueError, match="evaluations must be >= 0, got -1"):
        hrla.PolishSettings(-1)
    with pytest.raises(TypeError, match="chains must be an int, got float"):
        hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.0]), chains=2.0)


# --- one call at a time --------------------------------------------------


def test_calls_from_the_potential_see_the_views_or_a_busy_error():
    seen = []

    def fun(X):
        if opt_box:
            opt = opt_box[0]
            seen.append(opt.x.shape)  # a view: always readable
            with pytest.raises(hrla.BusyError, match="the optimiser is running"):
                opt.iteration
            with pytest.raises(hrla.BusyError):
                opt.step()
        return sphere(X)

    opt_box = []
    opt = hrla.Optimizer(fun, hrla.Ola.paper(0.01), 1.0, hrla.Point([0.5, 0.5]), chains=3,
                         stop=hrla.Stop().steps(4))
    opt_box.append(opt)
    report = opt.run()
    assert report.iterations == 4 and opt.iteration == 4  # no step lost or added
    assert seen == [(3, 2)] * 4


def test_calls_from_another_thread_while_a_run_runs_raise_busy_error():
    """The second thread calls while the first is inside the potential,
    so the run is certainly in progress (no timing involved)."""
    outcomes = {}

    def other_thread(opt):
        outcomes["x"] = opt.x.copy()
        for name, call in [("run", opt.run), ("step", lambda: opt.step(5)), ("best", lambda: opt.best),
                           ("polish", lambda: opt.polish(0))]:
            try:
                call()
                outcomes[name] = "returned"
            except BaseException as e:  # noqa: BLE001 - the type is the verdict
                outcomes[name] = e

    def fun(X):
        if opt_box and not outcomes:
            t = threading.Thread(target=other_thread, args=(opt_box[0],))
            t.start()
            t.join()
        return sphere(X)

    opt_box = []
    opt = hrla.Optimizer(fun, hrla.Hrla.paper(0.01), 1.0, hrla.Point([0.5, 0.5]), chains=3,
                         stop=hrla.Stop().steps(6))
    opt_box.append(opt)
    assert opt.run().iterations == 6
    assert outcomes["x"].shape == (3, 2)
    for name in ("run", "step", "best", "polish"):
        e = outcomes[name]
        assert isinstance(e, hrla.BusyError), (name, e)
        assert isinstance(e, RuntimeError) and isinstance(e, hrla.HrlaError)
    # The busy calls did nothing: the run is the uninterrupted one.
    ref = hrla.Optimizer(sphere, hrla.Hrla.paper(0.01), 1.0, hrla.Point([0.5, 0.5]), chains=3,
                         stop=hrla.Stop().steps(6))
    ref.run()
    assert opt.evaluations == ref.evaluations == 3 * 7
    assert np.array_equal(opt.x, ref.x)


def test_two_threads_with_a_builtin_potential_never_panic_or_lose_steps():
    """Two threads each step one optimiser 200 times by 20 steps: every
    call either does its steps or raises BusyError having done nothing, so
    the iterations are the steps of the calls that returned."""
    opt = hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Gaussian([3.0] * 10, 3.0),
                         chains=500, seed=1)
    done, errors = [0, 0], []

    def worker(i):
        for _ in range(200):
            try:
                opt.step(20)
                done[i] += 20
            except BaseException as e:  # noqa: BLE001 - the type is the verdict
                errors.append(e)

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(isinstance(e, hrla.BusyError) for e in errors), errors[:3]
    assert opt.iteration == sum(done)


# --- Ctrl-C --------------------------------------------------------------


@pytest.mark.parametrize("case", ["run", "step", "minimize", "auto", "scalar", "python_potential"])
def test_ctrl_c_interrupts_a_run_that_can_resume(case):
    # A run ignoring the signal would go on for hours: the time limit
    # turns that into a failure.
    p = subprocess.run([sys.executable, str(HERE / "interrupts.py"), case], capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 0 and p.stdout.strip() == "ok", p.stderr[-3000:]


# --- failed runs never look like success ---------------------------------


def minus_exp(X):
    with np.errstate(over="ignore"):
        e = np.exp(X)
    return -e[:, 0], -e


def test_polish_on_a_potential_unbounded_below_raises():
    opt = hrla.Optimizer(minus_exp, hrla.Ola.paper(0.01), 1.0, hrla.Point([0.0]), chains=2,
                         stop=hrla.Stop().steps(5))
    opt.run()
    with pytest.raises(hrla.UnboundedBelowError):
        opt.polish(0, hrla.PolishSettings(1000))
    with pytest.raises(hrla.UnboundedBelowError):  # the run stays failed
        opt.run()
    with pytest.raises(hrla.UnboundedBelowError):
        opt.quench(1)
    # The same through minimize's polish.
    with pytest.raises(hrla.UnboundedBelowError):
        hrla.minimize(pointwise(minus_exp), None, jac=True, dim=1, start=hrla.Point([0.0]), method="ola",
                      maxfun=1_000, polish=500)


def log_well(X):
    """Defined for x0 > 0 only: NaN or inf elsewhere."""
    with np.errstate(invalid="ignore", divide="ignore"):
        lx = np.log(X[:, 0])
        u = lx * lx + (X[:, 1] - 0.5) ** 2
        g = np.stack([2 * lx / X[:, 0], 2 * (X[:, 1] - 0.5)], axis=1)
    return u, g


def test_a_start_where_the_potential_is_undefined_is_redrawn():
    res = hrla.minimize(pointwise(log_well), [(-2, 3)] * 2, jac=True)
    assert res.success, res
    assert res.fun < 1e-12 and np.allclose(res.x, [1.0, 0.5], atol=1e-5), res


def test_redrawn_starts_of_a_batched_potential_get_their_own_answers():
    """The initial points are evaluated in one call; a chain whose point is
    infeasible draws again, and the redraw is evaluated alone: every chain
    ends with the value of its own point."""
    box = hrla.Interval(-2.0, 3.0)
    opt = hrla.Optimizer(log_well, hrla.Hrla.paper(0.01), 1.0, box, chains=10, seed=3, domain=box, dim=2)
    assert np.all(opt.x[:, 0] > 0)
    assert opt.evaluations > 10  # some of the ten first draws had x0 <= 0 (seed 3)
    u, g = log_well(np.array(opt.x))
    assert np.array_equal(opt.value, u) and np.array_equal(opt.gradient, g)


def best_u(message):
    """The number after "best f = " in a message."""
    return float(message.split("best f = ", 1)[1].split()[0])


def test_the_result_says_why_it_ended_after_the_polish():
    res = hrla.minimize(hrla.Rastrigin(), [(-5.12, 5.12)] * 3, method="hrla", seed=1, maxfun=20_000)
    assert res.success and res.status == 0 and res.termination == "Steps", res
    assert not res.all_diverged and res.diverged_chains == 0
    # The message is the polished result's.
    assert best_u(res.message) == res.fun, res.message
    assert hrla.TERMINATIONS[res.status] == res.termination
    res = hrla.minimize(hrla.Rastrigin(), [(-5.12, 5.12)] * 3, seed=1, maxfun=20_000, converge=False)
    # A run that maxfun ended did not converge: no success, whatever it found.
    assert not res.success and hrla.TERMINATIONS[res.status] == res.termination == "Evaluations", res
    res = hrla.minimize(hrla.Rastrigin(), [(-5.12, 5.12)] * 3, seed=1, maxfun=20_000)
    assert res.success and hrla.TERMINATIONS[res.status] == res.termination == "Converged", res
    assert best_u(res.message) == res.fun and not res.all_diverged, res.message


# --- the exceptions ------------------------------------------------------


def test_the_exceptions_are_one_hierarchy():
    assert issubclass(hrla.HrlaError, ValueError)
    for e in (hrla.DivergedError, hrla.UnboundedBelowError, hrla.BusyError,
              hrla.InternalError):
        assert issubclass(e, hrla.HrlaError) and e.__module__ == "hrla", e
    assert issubclass(hrla.BusyError, RuntimeError) and issubclass(hrla.InternalError, RuntimeError)


def test_auto_with_absurd_counts_raises_a_typed_error_or_succeeds():
    for steps in (2**61, 2**64 - 1):
        try:
            hrla.Auto(steps=steps).minimize(hrla.Rastrigin(), hrla.Interval(-1, 1), 2_000, dim=2)
        except hrla.InternalError:
            raise
        except hrla.HrlaError:
            pass

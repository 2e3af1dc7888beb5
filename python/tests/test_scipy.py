"""`hrla.minimize` takes a scipy user's function as scipy does: each
convention is checked against the same call made to scipy."""

import importlib.metadata
import math
import pydoc
import warnings

import numpy as np
import pytest
import scipy.optimize as so
from scipy.optimize._numdiff import approx_derivative

import hrla
from hrla import _minimize, _objective

METHODS = ["auto", "hrla", "ula", "ola"]


def himmelblau(x):
    return (x[0] ** 2 + x[1] - 11) ** 2 + (x[0] + x[1] ** 2 - 7) ** 2


def himmelblau_grad(x):
    p, q = x[0] ** 2 + x[1] - 11, x[0] + x[1] ** 2 - 7
    return np.array([4 * x[0] * p + 2 * q, 2 * p + 4 * x[1] * q])


def himmelblau_and_grad(x):
    return himmelblau(x), himmelblau_grad(x)


def shifted_sphere(x, centre, scale):
    """With args, as scipy passes them."""
    return scale * float(np.sum((x - centre) ** 2))


HIMMELBLAU_MINIMA = np.array([[3.0, 2.0], [-2.805118, 3.131312], [-3.779310, -3.283186], [3.584428, -1.848127]])


def near_a_minimum(x):
    return np.min(np.linalg.norm(HIMMELBLAU_MINIMA - x, axis=1)) < 1e-4


# --- finite differences: scipy's steps, no probe outside the box ----------


@pytest.mark.parametrize("scheme", ["2-point", "3-point"])
def test_finite_differences_are_approx_derivatives_bits(scheme):
    """The gradient of every row equals `approx_derivative`'s with the
    same scheme and bounds and its absolute step `r sign(x) max(l, |x|)`
    (`l` the side over 10.24), bit for bit: inside the box, on each face,
    near one, and in a box narrower than the step. On the paper's box
    `[-5.12, 5.12]` that step is scipy's own."""
    lb, ub = np.array([-5.0, 0.0, 1.0, -5.12]), np.array([5.0, 1e-9, 1.0 + 1e-12, 5.12])

    def f(x):
        return float(np.sin(x[0]) * np.exp(x[1]) + x[0] * x[2] ** 3 + np.cos(3 * x[3]))

    rows = np.array([[0.3, 0.0, 1.0, 0.25], [5.0, 1e-9, 1.0 + 1e-12, 5.12], [-5.0, 5e-10, 1.0, -5.12],
                     [4.9999999999, 0.0, 1.0, 0.0], [-1e-3, 1e-10, 1.0 + 5e-13, -3.0]])
    obj = _objective.Objective(f, (), scheme, False, _objective.Mapper(1), lb, ub)
    u, g = obj(rows)
    r = _objective.EPS ** 0.5 if scheme == "2-point" else _objective.EPS ** (1 / 3)
    unit = (ub - lb) / 10.24
    assert unit[3] == 1.0
    for row, value, grad in zip(rows, u, g):
        sign = np.where(row >= 0, 1.0, -1.0)
        step = r * sign * np.maximum(unit, np.abs(row))
        want = approx_derivative(f, row, method=scheme, bounds=(lb, ub), abs_step=step)
        assert value == f(row)
        np.testing.assert_array_equal(grad, want)
        # The last coordinate, on the paper's box: scipy's own step.
        default = approx_derivative(f, row, method=scheme, bounds=(lb, ub))
        assert grad[3] == default[3]
    per_row = 1 + _objective.SCHEMES[scheme] * 4
    assert obj.nfev == len(rows) * per_row and obj.njev == len(rows)
    # Without a box: the same as approx_derivative without bounds.
    free = _objective.Objective(f, (), scheme, False, _objective.Mapper(1), -np.inf, np.inf)
    _, g = free(rows)
    for row, grad in zip(rows, g):
        np.testing.assert_array_equal(grad, approx_derivative(f, row, method=scheme))


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("jac", [None, "3-point"])
def test_no_call_leaves_the_box(method, jac):
    # The minimum on a corner of the box: the chains sit on its faces,
    # where a forward probe would leave it.
    lb, ub = np.array([1.0, 1.0]), np.array([3.0, 3.0])
    seen = []

    def f(x):
        seen.append(np.array(x))
        return float((x[0] + 1) ** 2 + (x[1] - 5) ** 2)

    res = hrla.minimize(f, list(zip(lb, ub)), jac=jac, method=method, maxfun=3_000, rng=2)
    seen = np.array(seen)
    assert np.all(seen >= lb) and np.all(seen <= ub)
    assert len(seen) == res.nfev <= 3_000
    np.testing.assert_allclose(res.x, [1.0, 3.0], atol=1e-6)


def test_an_infeasible_point_costs_one_call():
    """Where fun is NaN or infinite the point is refused whatever its
    gradient: its probes are not evaluated (a vectorized fun gets them in
    the same call, evaluated)."""
    def f(x):
        return float(np.sum(x * x)) if x[0] > 0 else np.nan

    rows = np.array([[0.5, 0.1, 0.2], [-0.5, 0.1, 0.2], [0.25, -1.0, 0.0], [-1.0, 0.0, 0.0]])
    for scheme, k in _objective.SCHEMES.items():
        obj = _objective.Objective(f, (), scheme, False, _objective.Mapper(1), -2.0, 2.0)
        u, g = obj(rows)
        assert obj.nfev == 2 * (1 + 3 * k) + 2 and obj.njev == 4
        assert np.all(np.isfinite(g[[0, 2]])) and np.isnan(u[[1, 3]]).all()
        columns = _objective.Objective(lambda x: np.where(x[0] > 0, np.sum(x * x, axis=0), np.nan), (), scheme,
                                       True, _objective.Mapper(1), -2.0, 2.0)
        cu, cg = columns(rows)
        assert columns.nfev == 4 * (1 + 3 * k)
        np.testing.assert_array_equal(cg[[0, 2]], g[[0, 2]])


# --- scalar fun, args, jac: as scipy.optimize.minimize ---------------------


@pytest.mark.parametrize("method", METHODS)
def test_a_scalar_function_as_scipy_takes_it(method):
    bounds = [(-5, 5), (-5, 5)]
    peer = so.dual_annealing(himmelblau, bounds, rng=1)
    res = hrla.minimize(himmelblau, bounds, method=method, rng=1, maxfun=40_000)
    assert peer.success and near_a_minimum(peer.x)
    assert res.success and near_a_minimum(res.x) and res.fun < 1e-9, res
    # scipy's fields, with message written last.
    for key in ("x", "fun", "jac", "nfev", "njev", "nit", "status", "success", "message"):
        assert key in res and (key in peer or key == "jac"), key
    assert list(res)[-1] == "message"
    # The message counts what the user counts (calls of fun, not the
    # kernel's gradients), with f to the last digit.
    assert f"after {res.nfev} calls of fun ({res.njev} gradients)" in res.message, res.message
    assert f"best f = {res.fun!r} " in res.message and "e-" in res.message, res.message
    assert res.x.shape == (2,) and res.jac.shape == (2,)
    # jac is the gradient at x (forward differences there: within their error).
    np.testing.assert_allclose(res.jac, himmelblau_grad(res.x), atol=1e-5)
    # Forward differences: D + 1 calls of fun per gradient, all counted;
    # "auto" without a gradient then spends values only (its ensemble).
    if method == "auto":
        assert 3 * res.njev < res.nfev <= 40_000
    else:
        assert res.nfev == 3 * res.njev <= 40_000


def test_args_are_passed_as_scipy_passes_them():
    centre = np.array([0.5, -0.25, 1.0])
    args = (centre, 2.0)
    peer = so.minimize(shifted_sphere, np.zeros(3), args=args)
    res = hrla.minimize(shifted_sphere, [(-2, 2)] * 3, args=args, rng=0, maxfun=20_000)
    np.testing.assert_allclose(peer.x, centre, atol=1e-5)
    np.testing.assert_allclose(res.x, centre, atol=1e-6)


@pytest.mark.parametrize("method", METHODS)
def test_jac_true_and_a_jac_callable_as_scipy_takes_them(method):
    bounds = [(-5, 5)] * 2
    for kw in ({"fun": himmelblau_and_grad, "jac": True}, {"fun": himmelblau, "jac": himmelblau_grad}):
        peer = so.minimize(x0=np.array([2.5, 2.5]), bounds=bounds, method="L-BFGS-B", **kw)
        assert peer.success and np.allclose(peer.x, [3.0, 2.0], atol=1e-5)
        res = hrla.minimize(bounds=bounds, method=method, rng=3, maxfun=20_000, **kw)
        assert res.success and near_a_minimum(res.x) and res.fun < 1e-12, res
        # An exact gradient: one call of fun a point, the gradient at x exact.
        assert res.nfev == res.njev <= 20_000
        np.testing.assert_array_equal(res.jac, himmelblau_grad(res.x))


def test_vectorized_takes_columns_as_differential_evolution():
    """`vectorized=True`: x of shape (D, S), a column per point, S values
    back; the same function runs under differential_evolution."""
    shapes = []

    def batch(x):
        shapes.append(x.shape)
        assert x.ndim == 2 and x.shape[0] == 2
        return himmelblau(x)

    peer = so.differential_evolution(batch, [(-5, 5)] * 2, vectorized=True, updating="deferred", rng=1)
    assert peer.success and near_a_minimum(peer.x)
    for method in METHODS:
        shapes.clear()
        res = hrla.minimize(batch, [(-5, 5)] * 2, vectorized=True, method=method, rng=1, maxfun=30_000)
        assert near_a_minimum(res.x), res
        assert res.nfev == sum(s for _, s in shapes) <= 30_000
        if method != "auto":
            # The first call: every chain's start and its two probes at once.
            assert shapes[0] == (2, 10 * 3)


def test_vectorized_with_its_gradient_gives_the_bits_of_the_optimizer():
    """Algorithm 1 through minimize (vectorized, jac=True) is the
    Optimizer's run, bit for bit, with no polish."""
    def rows(X):
        return 0.5 * ((0.0 + X[:, 0] * X[:, 0]) + X[:, 1] * X[:, 1]), X.copy()

    def columns(x):
        u, g = rows(x.T)
        return u, g.T

    res = hrla.minimize(columns, [(-3, 3)] * 2, jac=True, vectorized=True, method="hrla", chains=8, rng=5,
                        maxiter=200, polish=0)
    opt = hrla.Optimizer(rows, hrla.Hrla.paper(0.01), 4.0, [(-3, 3)] * 2, domain=[(-3, 3)] * 2, chains=8, seed=5,
                         stop=hrla.Stop().steps(200).evaluations(125_000 - 1))
    report = opt.run()
    x, value, _ = opt.best
    assert res.fun == value and np.array_equal(res.x, x) and res.nit == report.iterations == 200
    assert res.nfev == opt.evaluations


def test_scipy_bounds_objects_are_accepted():
    lb, ub = np.array([-5.0, -5.0]), np.array([5.0, 5.0])
    pairs = hrla.minimize(himmelblau, list(zip(lb, ub)), method="hrla", rng=4, maxfun=5_000)
    for bounds in (so.Bounds(lb, ub), so.Bounds(-5.0, 5.0)):
        res = hrla.minimize(himmelblau, bounds, dim=2, method="hrla", rng=4, maxfun=5_000)
        assert res.fun == pairs.fun and np.array_equal(res.x, pairs.x)
    res = hrla.minimize(himmelblau, so.Bounds(lb, ub), rng=4, maxfun=5_000)
    assert near_a_minimum(res.x), res


# --- rng ------------------------------------------------------------------


def test_rng_none_int_and_generator():
    run = dict(bounds=[(-5, 5)] * 2, method="hrla", maxfun=3_000)
    a, b = hrla.minimize(himmelblau, rng=7, **run), hrla.minimize(himmelblau, rng=7, **run)
    assert a.seed == b.seed == 7 and np.array_equal(a.x, b.x) and a.fun == b.fun
    # seed= is the same argument.
    c = hrla.minimize(himmelblau, seed=7, **run)
    assert np.array_equal(a.x, c.x)
    # A Generator: the seed is drawn from it, so equal generators give equal runs.
    g1, g2 = np.random.default_rng(3), np.random.default_rng(3)
    d, e = hrla.minimize(himmelblau, rng=g1, **run), hrla.minimize(himmelblau, rng=g2, **run)
    assert d.seed == e.seed and np.array_equal(d.x, e.x)
    assert d.seed == int(np.random.default_rng(3).integers(0, 2**64, dtype=np.uint64))
    # None: fresh entropy each call (two 64-bit seeds agree with probability 2^-64).
    f, g = hrla.minimize(himmelblau, **run), hrla.minimize(himmelblau, **run)
    assert f.seed != g.seed
    # The result's seed repeats the run.
    h = hrla.minimize(himmelblau, rng=f.seed, **run)
    assert np.array_equal(h.x, f.x) and h.fun == f.fun


# --- stopping rules, every method ------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_a_run_that_reaches_the_target_stops_there(method):
    # The samplers at a = 4 fluctuate about U ~ D / (2 a): a target they
    # reach while sampling; "auto" quenches every round.
    target = 1e-6 if method == "auto" else 1e-2
    res = hrla.minimize(himmelblau, [(-5, 5)] * 2, method=method, rng=1, maxfun=100_000, target=target)
    assert res.termination == "Target" and res.success and res.fun <= target, res
    assert res.nfev < 100_000 / 4, res
    if method != "auto":
        # Stopped there: the starts and the steps, no polish after.
        assert res.njev == 10 * (res.nit + 1), res
    assert res.status == hrla.TERMINATIONS.index("Target")


@pytest.mark.parametrize("method", METHODS)
def test_stall_and_maxiter_end_every_method(method):
    res = hrla.minimize(hrla.Rastrigin(), [(-5.12, 5.12)] * 2, method=method, rng=1, maxfun=10**8,
                        stall=(5, 1e-300), **({} if method == "auto" else {"polish": 0}))
    assert res.termination == "Stalled" and res.success and res.nfev < 10**8, res
    res = hrla.minimize(hrla.Rastrigin(), [(-5.12, 5.12)] * 2, method=method, rng=1, maxfun=10**8, maxiter=7,
                        **({} if method == "auto" else {"polish": 0}))
    assert res.termination == "Steps" and res.nit == 7, res


@pytest.mark.parametrize("method", METHODS)
def test_maxfun_counts_every_call(method):
    for jac in (None, "3-point", True):
        fun = himmelblau_and_grad if jac is True else himmelblau
        calls = []
        res = hrla.minimize(lambda x: calls.append(1) or fun(x), [(-5, 5)] * 2, jac=jac, method=method, rng=1,
                            maxfun=2_500)
        assert len(calls) == res.nfev <= 2_500, (jac, res)
        # "auto" may converge first: every call is counted either way.
        assert res.termination in ("Evaluations", "Steps", "Converged"), res


@pytest.mark.parametrize("method", METHODS)
def test_a_time_limit_of_zero_stops_at_the_first_look(method):
    res = hrla.minimize(himmelblau, [(-5, 5)] * 2, method=method, rng=1, maxtime=0)
    assert res.termination == "Time" and res.status == hrla.TERMINATIONS.index("Time"), res
    assert res.message.startswith("the time limit (maxtime) is reached")
    assert res.nfev < 5_000


@pytest.mark.parametrize("method", METHODS)
def test_the_time_limit_reads_the_clock_not_the_machine(method, monkeypatch):
    """A fake clock that moves one second at every reading: the limit of
    9.5 s ends the run at the 10th look, however fast the machine."""
    ticks = iter(range(10**6))
    monkeypatch.setattr(_minimize, "_clock", lambda: float(next(ticks)))
    looks = []
    res = hrla.minimize(himmelblau, [(-5, 5)] * 2, method=method, rng=1, maxtime=9.5,
                        callback=lambda intermediate_result: looks.append(intermediate_result.nit))
    assert res.termination == "Time", res
    # The clock read at the start, then once a look: the 10th look stops.
    # A sampler looks once a step, each a new step for the callback;
    # "auto" looks after every step of a round, the callback once a round.
    assert len(looks) == 9 if method != "auto" else 1 <= len(looks) <= 9


@pytest.mark.parametrize("method", METHODS)
def test_the_callback_sees_the_best_and_stops_the_run(method):
    seen = []

    def callback(intermediate_result):
        seen.append(intermediate_result)
        if len(seen) == 4:
            raise StopIteration

    res = hrla.minimize(himmelblau, [(-5, 5)] * 2, method=method, rng=1, callback=callback)
    assert len(seen) == 4 and res.termination == "Callback" and not res.success, res
    for r in seen:
        assert isinstance(r, hrla.OptimizeResult) and r.x.shape == (2,)
        assert r.fun == himmelblau(r.x)
    assert [r.fun for r in seen] == sorted((r.fun for r in seen), reverse=True)
    # Returning True stops it too (differential_evolution's older convention).
    count = []
    res = hrla.minimize(himmelblau, [(-5, 5)] * 2, method=method, rng=1,
                        callback=lambda intermediate_result: count.append(1) or len(count) == 2)
    assert len(count) == 2 and res.termination == "Callback"
    # Another parameter name: scipy's older convention, the point xk.
    points = []
    hrla.minimize(himmelblau, [(-5, 5)] * 2, method=method, rng=1, maxfun=3_000,
                  callback=lambda xk: points.append(xk))
    assert points and all(isinstance(p, np.ndarray) and p.shape == (2,) for p in points)


def test_the_callback_with_a_builtin_under_auto():
    seen = []
    res = hrla.minimize(hrla.Rastrigin(), [(-5.12, 5.12)] * 3, rng=1, maxfun=5_000,
                        callback=lambda intermediate_result: seen.append(intermediate_result))
    assert seen and np.isfinite(res.fun)
    for r in seen:
        u, _ = hrla.Rastrigin().value_and_gradient(r.x[None, :])
        assert u[0] == r.fun


@pytest.mark.parametrize("method", METHODS)
def test_disp_prints_a_progress_line(method, capsys):
    res = hrla.minimize(himmelblau, [(-5, 5)] * 2, method=method, rng=1, maxfun=3_000, disp=True)
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) >= 2, lines
    for line in lines:
        assert line.startswith(f"hrla {method}: ") and " evaluations, best " in line, line
    # The last line is the result's.
    assert f", {res.nfev} evaluations, best {res.fun:.10g}" in lines[-1], (lines[-1], res)
    hrla.minimize(himmelblau, [(-5, 5)] * 2, method=method, rng=1, maxfun=3_000)
    assert capsys.readouterr().out == ""


# --- x0 and workers --------------------------------------------------------


def test_x0_starts_a_chain():
    x0 = np.array([2.9, 2.1])
    seen = []
    res = hrla.minimize(lambda x: seen.append(np.array(x)) or himmelblau(x), [(-5, 5)] * 2, x0=x0,
                        method="hrla", rng=1, maxfun=5_000)
    assert any(np.array_equal(p, x0) for p in seen)
    assert res.success


CENTRE = np.array([0.5, -1.5, 2.0, -0.5, 1.0, -2.0])


def shifted_rastrigin(x):
    """6-D Rastrigin, its global minimum 0 at CENTRE among 11^6 local ones."""
    z = x - CENTRE
    return float(10 * len(z) + np.sum(z * z - 10 * np.cos(2 * np.pi * z)))


def test_x0_starts_auto_there():
    # Tiny budget (30 gradients of 7 calls): from x0 at the global minimum
    # auto returns it; without x0 none of these seeds comes near it.
    run = dict(bounds=[(-5.12, 5.12)] * 6, maxfun=7 * 31)
    for seed in range(3):
        res = hrla.minimize(shifted_rastrigin, x0=CENTRE, rng=seed, **run)
        assert res.fun < 1e-9 and np.allclose(res.x, CENTRE, atol=1e-6), res
        assert res.nfev <= run["maxfun"]
        without = hrla.minimize(shifted_rastrigin, rng=seed, **run)
        assert without.fun > 0.5, without
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        hrla.minimize(himmelblau, [(-5, 5)] * 2, x0=np.array([2.9, 2.1]), rng=1, maxfun=2_000)


def test_a_bad_x0_for_auto_is_named():
    with pytest.raises(ValueError, match="x0 must lie in the box"):
        hrla.minimize(himmelblau, [(-5, 5)] * 2, x0=[9.0, 0.0], rng=1, maxfun=2_000)
    with pytest.raises(hrla.HrlaError, match=r"`x0\[1\]` = NaN is outside the box's side \[-5, 5\]"):
        hrla.minimize(himmelblau, [(-5, 5)] * 2, x0=[0.0, float("nan")], rng=1, maxfun=2_000)

    def holed(x):
        return math.nan if x[0] > 4 else himmelblau(x)

    with pytest.raises(hrla.HrlaError, match="`U at x0` must be finite, got NaN"):
        hrla.minimize(holed, [(-5, 5)] * 2, x0=[4.5, 0.0], rng=1, maxfun=2_000)
    with pytest.raises(ValueError, match="dim has dimension 3 but x0 has 2"):
        hrla.Auto().minimize(hrla.Rastrigin(), hrla.Interval(-5, 5), 1_000, 1, dim=3, x0=[0.0, 0.0])


def square_sum(x):
    """Module level, so that a process pool can pickle it."""
    return float(np.sum((x - 0.25) ** 2))


def test_workers_evaluate_in_parallel_with_the_same_bits():
    run = dict(bounds=[(-1, 1)] * 3, rng=5, maxfun=4_000)
    for method in ("auto", "hrla"):
        serial = hrla.minimize(square_sum, method=method, **run)
        pooled = hrla.minimize(square_sum, method=method, workers=2, **run)
        assert pooled.fun == serial.fun and np.array_equal(pooled.x, serial.x) and pooled.nfev == serial.nfev
        mapped = []

        def mapper(f, points):
            points = list(points)
            mapped.append(len(points))
            return map(f, points)

        custom = hrla.minimize(square_sum, method=method, workers=mapper, **run)
        assert custom.fun == serial.fun and sum(mapped) == custom.nfev
        if method == "hrla":
            # A batch, two maps: the 10 starts, then their 3 probes each.
            assert mapped[:2] == [10, 10 * 3]


# --- bad arguments, each named ---------------------------------------------


@pytest.mark.parametrize("kw, error, text", [
    ({"maxfun": -1}, ValueError, "maxfun must be >= 1, got -1"),
    ({"maxfun": 0}, ValueError, "maxfun must be >= 1, got 0"),
    ({"maxfun": 2.5}, ValueError, "maxfun must be a whole number, got 2.5"),
    ({"maxiter": -1}, ValueError, "maxiter must be >= 0, got -1"),
    ({"chains": -3}, ValueError, "chains must be >= 1, got -3"),
    ({"dim": -1}, ValueError, "dim must be >= 1, got -1"),
    ({"rng": -1}, ValueError, "rng must be >= 0, got -1"),
    ({"seed": -1}, ValueError, "seed must be >= 0, got -1"),
    ({"seed": 2**64}, ValueError, "seed must be < 2\\*\\*64"),
    ({"rng": "abc"}, TypeError, "rng must be None, an int or a numpy.random.Generator"),
    ({"rng": 1, "seed": 1}, TypeError, "give rng or seed"),
    ({"maxtime": -1.0}, ValueError, "maxtime must be >= 0"),
    ({"target": float("nan")}, ValueError, "target must be a number"),
    ({"stall": (0, 1e-9)}, ValueError, "stall's window must be >= 1"),
    ({"stall": 5}, TypeError, "stall must be a pair"),
    ({"workers": 0}, ValueError, "workers must be >= 1, -1"),
    ({"workers": "4"}, TypeError, "workers must be an int or a map-like callable"),
    ({"workers": 2, "vectorized": True}, ValueError, "workers is not used with vectorized=True"),
    ({"workers": map, "vectorized": True}, ValueError, "workers is not used with vectorized=True"),
    ({"jac": "5-point"}, ValueError, "jac must be None, True, a callable, '2-point' or '3-point'"),
    ({"callback": 3}, TypeError, "callback must be callable"),
    ({"x0": [0.0, 0.0, 0.0], "method": "hrla"}, ValueError, "x0 has dimension 3 but bounds has 2"),
    ({"x0": [9.0, 0.0], "method": "hrla"}, ValueError, "x0 must lie in the box"),
    ({"h": 0.01}, ValueError, "h is not used by method='auto'"),
    ({"schedule": 2.0}, ValueError, "schedule is not used by method='auto'"),
    ({"start": hrla.Point([0.0, 0.0])}, ValueError, "start is not used by method='auto'"),
    ({"polish": 10}, ValueError, "polish is not used by method='auto'"),
    ({"polish": -1, "method": "hrla"}, ValueError, "polish must be >= 0, got -1"),
    ({"maxfun": 10, "budget": 10}, TypeError, "give maxfun or its older name budget"),
    ({"method": "nelder-mead"}, ValueError, "unknown method 'nelder-mead'"),
    ({"maxfun": 2}, ValueError, "maxfun=2 leaves no evaluation: each gradient costs 3 calls of fun"),
    ({"maxfun": 20}, ValueError, "maxfun=20 is too small for method='auto' with 4 chains: it needs 8 gradients "
                                 "of 3 calls of fun each and one more for the result, maxfun >= 27"),
    ({"maxfun": 20, "method": "hrla"}, ValueError, "maxfun leaves no step to 10 chains"),
])
def test_each_bad_argument_is_named(kw, error, text):
    with pytest.raises(error, match=text):
        hrla.minimize(himmelblau, [(-5, 5)] * 2, **kw)


@pytest.mark.parametrize("kw", [{"args": (1,)}, {"jac": True}, {"vectorized": True}, {"workers": 2}])
def test_conventions_a_builtin_does_not_use_are_errors(kw):
    name = next(iter(kw))
    with pytest.raises(ValueError, match=f"{name} is not used with a built-in potential"):
        hrla.minimize(hrla.Rastrigin(), [(-5, 5)] * 2, **kw)


def test_the_older_names_are_deprecated_aliases():
    run = dict(bounds=[(-5, 5)] * 2, method="hrla", rng=1, polish=0)
    new = hrla.minimize(himmelblau, maxfun=3_000, maxiter=40, **run)
    with pytest.warns(DeprecationWarning, match="budget= is deprecated: it is maxfun="):
        old = hrla.minimize(himmelblau, budget=3_000, maxiter=40, **run)
    assert old.fun == new.fun and np.array_equal(old.x, new.x)
    with pytest.warns(DeprecationWarning, match="steps= is deprecated: it is maxiter="):
        old = hrla.minimize(himmelblau, maxfun=3_000, steps=40, **run)
    assert old.fun == new.fun and old.nit == new.nit == 40


# --- the package -----------------------------------------------------------


def test_version_and_help():
    assert hrla.__version__ == importlib.metadata.version("hrla")
    text = pydoc.render_doc(hrla.minimize, renderer=pydoc.plaintext)
    for word in ("scipy.optimize", "vectorized", "approx_derivative", "maxfun", "callback", "OptimizeResult"):
        assert word in text, word
    assert "jac" in pydoc.render_doc(hrla.OptimizeResult, renderer=pydoc.plaintext)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        hrla.minimize(himmelblau, [(-5, 5)] * 2, maxfun=1_000, rng=1)


def test_observers_get_the_best_point_with_x():
    """``with_x=True``: the observer's fourth argument is the best point,
    where the potential's value is the third, for Auto and the samplers."""
    rastrigin = hrla.Rastrigin()
    seen = []

    def observer(iteration, evaluations, value, x):
        seen.append((value, np.array(x)))

    hrla.Auto().minimize(rastrigin, hrla.Interval(-5.12, 5.12), 3_000, 1, dim=3, observer=observer, with_x=True)
    # A Python potential: the observer is called after every step.
    opt = hrla.Optimizer(lambda x: rastrigin.value_and_gradient(x), hrla.Hrla.paper(0.01), 4.0, hrla.Interval(-5.12, 5.12), chains=4, seed=1,
                         stop=hrla.Stop().steps(50), dim=3)
    looked = len(seen)
    opt.run(observer, with_x=True)
    assert looked > 0 and len(seen) == looked + 50
    for value, x in seen:
        assert x.shape == (3,) and rastrigin.value_and_gradient(x[None, :])[0][0] == value
    # Without it, three arguments as before.
    opt.run(lambda iteration, evaluations, value: None)


def test_a_builtin_under_auto_runs_in_rust_with_a_callback():
    """The callback's point comes from the run: a built-in stays a
    built-in (the same bits and count as without a callback)."""
    run = dict(bounds=[(-5.12, 5.12)] * 3, rng=2, maxfun=4_000)
    quiet = hrla.minimize(hrla.Rastrigin(), **run)
    looked = hrla.minimize(hrla.Rastrigin(), callback=lambda intermediate_result: None, **run)
    assert np.array_equal(quiet.x, looked.x) and quiet.fun == looked.fun and quiet.nfev == looked.nfev


def test_dual_annealings_docstring_example_is_solved():
    # scipy.optimize.dual_annealing's own example, a 10-D Rastrigin as a
    # lambda without a gradient. The ensemble's restarts end with a few
    # coordinates in a neighbouring cell (0.995 on these seeds before the
    # ensemble scanned along the coordinates); a scan through the best
    # point moves each coordinate to its own cell's floor.
    func = lambda x: np.sum(x * x - 10 * np.cos(2 * np.pi * x)) + 10 * np.size(x)  # noqa: E731
    lw, up = [-5.12] * 10, [5.12] * 10
    for seed in (1, 2, 3):
        res = hrla.minimize(func, list(zip(lw, up)), rng=seed)
        assert res.fun < 1e-8, res
        assert np.all(np.abs(res.x) < 1e-4), res.x

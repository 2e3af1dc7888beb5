"""Any dimension: the sampler path runs D the kernel knows only at run time."""

import numpy as np
import pytest

import hrla


def bowl(X):
    """The unit quadratic as a Python function: U = |x|^2 / 2, G = x."""
    return 0.5 * np.sum(X * X, axis=1), X.copy()


@pytest.mark.parametrize("d", [1, 17, 24, 257, 10_000])
def test_optimizer_runs_any_dimension(d):
    for potential in (hrla.Rastrigin(), bowl):
        opt = hrla.Optimizer(potential, hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.5] * d), chains=3,
                             stop=hrla.Stop().steps(4))
        report = opt.run()
        assert opt.dim == d and len(opt) == 3
        assert opt.x.shape == (3, d) and opt.y.shape == (3, d) and opt.gradient.shape == (3, d)
        assert opt.best_x.shape == (3, d) and opt.best_value.shape == (3,)
        assert report.iterations == 4 and np.isfinite(report.value)
        # The views are the chains: the gradient at x is the potential's there.
        if potential is bowl:
            np.testing.assert_array_equal(opt.gradient, opt.x)
            np.testing.assert_array_equal(opt.value, 0.5 * np.sum(opt.x * opt.x, axis=1))
        best = np.argmin(opt.best_value)
        assert report.value == opt.best_value[best]


@pytest.mark.parametrize("d", [1, 17, 24, 257, 10_000])
def test_minimize_samplers_run_any_dimension(d):
    calls = []

    def fun(x):
        calls.append(x.shape)
        u, g = bowl(x.T)
        return u, g.T

    for method in ("hrla", "ula", "ola"):
        calls.clear()
        r = hrla.minimize(fun, [(-1.0, 2.0)] * d, jac=True, vectorized=True, method=method, chains=2, maxiter=3,
                          polish=0)
        assert r.x.shape == (d,) and np.isfinite(r.fun)
        # One call for the initial points, then one per step, each with
        # every chain (a column each).
        assert calls == [(d, 2)] * 4


def columns(x):
    """The bowl in scipy's vectorized layout: points are the columns of x (D, S)."""
    u, g = bowl(x.T)
    return u, g.T


@pytest.mark.parametrize("d", [1, 17, 24, 257, 10_000])
def test_minimize_auto_runs_any_dimension(d):
    budget = 400 if d == 10_000 else 3_000
    for fun, kw in ((hrla.Rastrigin(), {}), (columns, {"jac": True, "vectorized": True})):
        r = hrla.minimize(fun, [(-1.0, 2.0)] * d, method="auto", maxfun=budget, rng=0, **kw)
        assert r.x.shape == (d,) and np.isfinite(r.fun) and r.nfev <= budget
        assert np.all(r.x >= -1.0) and np.all(r.x <= 2.0)
        if d <= 24 and fun is columns:
            # The bowl's minimum at 0 is inside the box: Auto polishes it.
            assert r.fun < 1e-20 and np.max(np.abs(r.x)) < 1e-10


def test_minimize_auto_takes_a_box_per_coordinate():
    """Parameters on different scales: each coordinate's minimum in its own side."""
    centre = np.array([3.0, 70.0, 5.0])
    scale = np.array([10.0, 100.0, 20.0])

    def fit(x):
        z = (x - centre) / scale
        return float(z @ z), 2.0 * z / scale

    r = hrla.minimize(fit, [(0, 10), (0, 100), (0.1, 20)], jac=True, method="auto", maxfun=5_000, rng=0)
    assert r.x.shape == (3,) and r.fun < 1e-20
    np.testing.assert_allclose(r.x, centre, rtol=1e-9)

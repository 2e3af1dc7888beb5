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

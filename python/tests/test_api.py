"""The Python API: minimize, the step-by-step object and its views, the
batched Python potential, and errors as exceptions."""

import re
from pathlib import Path

import numpy as np
import pytest

import hrla


def rastrigin(X):
    """Batched Rastrigin in numpy: X (N, D) -> (U (N,), G (N, D))."""
    t = 2 * np.pi * X
    return X.shape[1] + np.sum(X * X - np.cos(t), axis=1), 2 * X + 2 * np.pi * np.sin(t)


def rastrigin_columns(x):
    """The same on columns, with its gradient: x (D, S) -> (U (S,), G (D, S))."""
    u, g = rastrigin(x.T)
    return u, g.T


def readme_python_blocks():
    """The ```python blocks of the README's Python section."""
    text = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    section = text.split("\n## Python\n", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, re.S)


def test_readme_example_finds_the_minimum_of_a_user_function(capsys):
    first, second, third = readme_python_blocks()
    # A scipy user's call: fun(x), a box per coordinate, no gradient.
    assert len([line for line in first.splitlines() if line.strip()]) == 5
    scope = {}
    exec(first, scope)
    res = scope["res"]
    assert res.success and res.fun < 1e-12, res
    minima = np.array([[3.0, 2.0], [-2.805118, 3.131312], [-3.779310, -3.283186], [3.584428, -1.848127]])
    assert np.min(np.linalg.norm(minima - res.x, axis=1)) < 1e-5
    # Auto's forward differences (D + 1 calls of fun per gradient), then
    # the ensemble's values, every call counted; the run converged by
    # itself, far below maxfun.
    assert res.njev >= 1 and 3 * res.njev < res.nfev < 125_000 and res.termination == "Converged", res
    # The batched and gradient forms.
    exec(second, scope)
    res = scope["res"]
    assert res.success and res.fun < 1e-10 and res.nfev == res.njev <= 20_000, res
    # The step-by-step example.
    scope = {"hrla": hrla}
    exec(third, scope)
    opt, x, report = scope["opt"], scope["x"], scope["report"]
    assert report.termination == "Steps" and report.iterations == 14_000
    assert np.array_equal(x, opt.x) and x.base is opt


def test_builtin_potential_agrees_with_numpy():
    X = np.random.default_rng(0).uniform(-5, 5, size=(64, 10))
    u, g = hrla.Rastrigin().value_and_gradient(X)
    u0, g0 = rastrigin(X)
    np.testing.assert_allclose(u, u0, rtol=1e-12, atol=1e-11)
    np.testing.assert_allclose(g, g0, rtol=1e-12, atol=1e-11)
    assert hrla.Rastrigin().global_minimum(10) == 0.0


def test_auto_and_the_methods_on_10d_rastrigin():
    box = [(-5.12, 5.12)] * 10
    res = hrla.minimize(hrla.Rastrigin(), box, seed=1)
    # It ends by itself: converged, well within the default maxfun.
    assert res.success and res.termination == "Converged" and res.fun < 1e-10, res
    assert res.nfev < 125_000
    # Algorithm 1 with a batched numpy potential: the same as the built-in
    # up to the last bits of numpy's sine, so only the quality is checked.
    res = hrla.minimize(rastrigin_columns, box, jac=True, vectorized=True, method="hrla", seed=1, maxfun=50_000,
                        schedule=hrla.Linear(0.1, 4.0, 4_000))
    assert res.termination == "Steps" and res.fun < 3.0, res


def test_auto_steers_its_step_by_the_acceptance_rate():
    # The default steers each rung's step to accept half its proposals;
    # 0 keeps the measured step, and a rate outside [0, 1] is refused.
    assert hrla.Auto().accept == 0.5 and hrla.Auto(accept=0.0).accept == 0.0
    box = [(-5.12, 5.12)] * 3
    steered = hrla.Auto().minimize(hrla.Rastrigin(), box, 5_000, 3)
    fixed = hrla.Auto(accept=0.0).minimize(hrla.Rastrigin(), box, 5_000, 3)
    # `step` is the measured step every rung starts from: the same for both.
    assert steered.step == fixed.step
    assert steered.value < 1e-10 and fixed.value < 1e-10, (steered, fixed)
    for bad in (-0.1, 1.5, float("nan")):
        with pytest.raises(hrla.HrlaError, match=r"accept \(in \[0, 1\]\)"):
            hrla.Auto(accept=bad).minimize(hrla.Rastrigin(), box, 5_000, 3)


def test_auto_stall_is_only_the_convergence_window():
    # No part of a round restarts chains after a stall: without the
    # convergence rule, `stall` changes nothing; with it, it sets the window.
    box = [(-5.12, 5.12)] * 4
    x = {}
    for stall in (3, 30):
        auto = hrla.Auto(stall=stall)
        assert auto.converged_window == 2 * stall
        s = auto.minimize(hrla.Rastrigin(), box, 20_000, 5)
        x[stall] = (s.value, s.evaluations, s.rounds, tuple(s.x))
    assert x[3] == x[30]
    with pytest.raises(TypeError):
        hrla.Auto(jump_rate=0.1)


def test_a_soft_budget_lets_the_first_quench_finish():
    # A 10-D ellipsoid of condition 1e6: 60 evaluations cut the best
    # start's quench short; a soft budget of 60 within 1 200 lets it end.
    scale = 10.0 ** (6 * np.arange(10) / 9)

    def ellipsoid(x):  # a batch of points, (n, 10)
        return (x * x) @ scale, 2 * scale * x

    box = [(-5.0, 5.0)] * 10
    cut = hrla.Auto().minimize(ellipsoid, box, 60, 1, chains=8)
    soft = hrla.Auto().minimize(ellipsoid, box, 1_200, 1, chains=8, soft_budget=60)
    assert cut.value > 1.0 and cut.termination == "Evaluations"
    assert soft.value < 1e-6 and soft.termination == "Evaluations" and soft.rounds == 0
    assert 60 < soft.evaluations <= 1_200
    # At the budget or above it, the soft budget changes nothing.
    same = hrla.Auto().minimize(ellipsoid, box, 60, 1, chains=8, soft_budget=600)
    assert (same.value, same.evaluations, tuple(same.x)) == (cut.value, cut.evaluations, tuple(cut.x))
    with pytest.raises(ValueError):
        hrla.Auto().minimize(hrla.Rastrigin(), box, 1_200, 1, soft_budget=-1)


def test_views_look_into_the_optimizer():
    opt = hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Gaussian([3.0] * 10, 3.0),
                         chains=5, seed=2, stop=hrla.Stop().steps(50))
    x, best_value = opt.x, opt.best_value
    assert x.shape == (5, 10) and best_value.shape == (5,)
    assert not x.flags.writeable and x.base is opt
    before = x.copy()
    opt.step()
    # Updated in place by the step: the same array, new numbers.
    assert not np.array_equal(before, x)
    assert np.array_equal(x, opt.x)
    with pytest.raises(ValueError):
        x[0, 0] = 1.0
    del opt  # the views keep the chains alive
    assert np.all(np.isfinite(x)) and np.all(best_value >= 0)


def test_the_function_is_called_once_per_step_for_the_live_chains():
    shapes = []

    def fun(X):
        shapes.append(X.shape)
        return rastrigin(X)

    opt = hrla.Optimizer(fun, hrla.Ola.paper(0.01), 1.0, hrla.Gaussian([0.0] * 3, 1.0), chains=7, seed=1,
                         stop=hrla.Stop().steps(30))
    report = opt.run()
    assert report.iterations == 30 and shapes == [(7, 3)] * 31
    # The polish calls it one point at a time.
    n = len(shapes)
    p = opt.polish(opt.best_chain, hrla.PolishSettings(50))
    assert shapes[n:] == [(1, 3)] * p.evaluations


def test_kernel_errors_become_exceptions_with_its_messages():
    with pytest.raises(hrla.HrlaError, match=r"`h` must be finite and > 0, got -1"):
        hrla.Hrla.paper(-1.0)
    with pytest.raises(hrla.HrlaError, match="hi - lo"):
        hrla.Interval(1.0, 1.0)
    with pytest.raises(hrla.HrlaError, match="no stopping rule"):
        hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.0, 0.0])).run()
    with pytest.raises(hrla.HrlaError, match="would cut the schedule of 100 steps short"):
        hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), hrla.Linear(1, 2, 100), hrla.Point([0.0]),
                       stop=hrla.Stop().steps(10))
    with pytest.raises(ValueError, match="dimension"):
        hrla.Optimizer(hrla.Quadratic(1.0, [0.0] * 3), hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.0] * 2))
    with pytest.raises(TypeError, match="sampler must be"):
        hrla.Optimizer(hrla.Rastrigin(), "hrla", 4.0, hrla.Point([0.0]))


def test_failed_runs_raise():
    # Every chain diverges: the gradient turns NaN after the initial points.
    calls = []

    def fun(X):
        calls.append(X.shape)
        g = np.zeros_like(X) if len(calls) == 1 else np.full_like(X, np.nan)
        return np.zeros(len(X)), g

    opt = hrla.Optimizer(fun, hrla.Hrla.paper(0.01), 1.0, hrla.Point([0.0, 0.0]), chains=3,
                         stop=hrla.Stop().steps(5))
    with pytest.raises(hrla.DivergedError, match="all 3 chains diverged"):
        opt.run()
    with pytest.raises(hrla.DivergedError):  # a failed run stays failed
        opt.step()
    # A potential unbounded below.
    opt = hrla.Optimizer(lambda X: (-1e300 * np.sum(X * X, axis=1), -2e300 * X), hrla.Ola.paper(0.01), 1.0,
                         hrla.Point([0.0]), chains=2, stop=hrla.Stop().steps(5))
    with pytest.raises(hrla.UnboundedBelowError, match="unbounded below"):
        opt.run()


def test_python_errors_and_bad_answers_propagate():
    def boom(x):
        raise KeyError("from the potential")

    with pytest.raises(KeyError, match="from the potential"):
        hrla.minimize(boom, [(-1, 1)] * 2, method="hrla")
    with pytest.raises(KeyError, match="from the potential"):
        hrla.minimize(boom, [(-1, 1)] * 2)  # Auto, one point at a time
    with pytest.raises(ValueError, match=r"U of shape \(10,\) and G of shape \(10, 2\)"):
        hrla.Optimizer(lambda X: (np.zeros(3), X), hrla.Ola.paper(0.01), 1.0, hrla.Interval(-1, 1), dim=2)
    with pytest.raises(TypeError, match="pair"):
        hrla.Optimizer(lambda X: 1.0, hrla.Ola.paper(0.01), 1.0, hrla.Interval(-1, 1), dim=2)
    # minimize's conventions: fun's own answers, named.
    # 10 chains and their probes (2 each): one call on 30 columns.
    with pytest.raises(ValueError, match=r"vectorized fun must return shape \(30,\) for x of shape \(2, 30\)"):
        hrla.minimize(lambda x: np.zeros(3), [(-1, 1)] * 2, vectorized=True, method="ola")
    with pytest.raises(TypeError, match=r"with jac=True, fun must return a pair \(f, g\)"):
        hrla.minimize(lambda x: 1.0, [(-1, 1)] * 2, jac=True, method="ola")
    with pytest.raises(TypeError, match=r"fun must return a real number \(with its gradient, pass jac=True\)"):
        hrla.minimize(lambda x: (1.0, x), [(-1, 1)] * 2, method="ola")


def test_known_minima_at_any_dimension():
    for d in (1, 17, 101):
        assert hrla.Rastrigin().global_minimum(d) == 0.0
        assert hrla.StyblinskiTang().global_minimum(d) == hrla.StyblinskiTang().global_minimum(1) * d
    with pytest.raises(hrla.HrlaError):
        hrla.Rastrigin().global_minimum(0)


def test_the_stubs_match_the_module():
    """Every public name of `hrla._hrla` is in `_hrla.pyi` and the other
    way round, every class with the same public methods and properties."""
    import ast

    from hrla import _hrla

    tree = ast.parse((Path(hrla.__file__).parent / "_hrla.pyi").read_text())
    stubs = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            stubs[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)} | {
                n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
        elif isinstance(node, ast.AnnAssign):
            stubs[node.target.id] = None
        elif isinstance(node, ast.FunctionDef):
            stubs[node.name] = None
    aliases = {"F64", "BatchedFunction", "Observer", "Sampler", "ScheduleLike", "StartLike", "PotentialLike", "BoxLike"}
    public = {n for n in dir(_hrla) if not n.startswith("_")}
    assert public == {n for n in stubs if not n.startswith("_")} - aliases
    for name, members in stubs.items():
        if members is None or name in aliases:
            continue
        cls = getattr(_hrla, name)
        own = {m for m in vars(cls) if not m.startswith("_")}
        if issubclass(cls, BaseException):
            assert own == members, name
        else:
            assert own == members - {"__init__", "__len__"}, (name, own ^ (members - {"__init__", "__len__"}))


def test_the_builtins_are_the_layers_list():
    # The classes come from the run-time layer's one list: each is
    # exported, a Potential, and named as the kernel's type.
    assert hrla.BUILTINS == ["Rastrigin", "Ackley", "Levy", "StyblinskiTang", "DoubleWell", "Quadratic"]
    for name in hrla.BUILTINS:
        cls = getattr(hrla, name)
        assert name in hrla.__all__
        assert issubclass(cls, hrla.Potential)
        assert cls.__name__ == name and cls.__module__ == "hrla"
        if name != "Quadratic":
            assert repr(cls()) == f"{name}()"
            assert cls.__doc__


def test_a_box_per_coordinate_is_the_layers_to_check():
    # Equal pairs run as the interval they all are, bit for bit; pairs that
    # differ run, Auto included; their number fixes D and must agree with
    # dim=.
    pairs = hrla.minimize(hrla.Rastrigin(), [(-5.12, 5.12)] * 3, method="hrla", maxfun=3_000, seed=4)
    interval = hrla.minimize(hrla.Rastrigin(), (-5.12, 5.12), dim=3, method="hrla", maxfun=3_000, seed=4)
    assert pairs.fun == interval.fun and np.array_equal(pairs.x, interval.x)
    solution = hrla.Auto().minimize(hrla.Rastrigin(), [(-1.0, 1.0), (0.5, 2.0)], 10_000)
    result = hrla.minimize(hrla.Rastrigin(), [(-1.0, 1.0), (0.5, 2.0)], maxfun=10_000)
    for x, fun in ((solution.x, solution.value), (result.x, result.fun)):
        # U = sum x_i^2 + 1 - cos(2 pi x_i): x0 = 0, and x1 the lowest point
        # of its term on [0.5, 2] (a grid of step 1e-6 finds it).
        grid = np.linspace(0.5, 2.0, 1_500_001)
        term = grid**2 + 1.0 - np.cos(2.0 * np.pi * grid)
        x1 = grid[np.argmin(term)]
        assert abs(x[0]) < 1e-8 and abs(x[1] - x1) < 1e-5
        assert fun == pytest.approx(term.min(), abs=1e-10)
    with pytest.raises(ValueError, match="bounds has dimension 2 but dim has 3"):
        hrla.minimize(hrla.Rastrigin(), [(-1.0, 1.0)] * 2, dim=3, maxfun=10_000)
    with pytest.raises(TypeError, match="a box must be"):
        hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.0]), domain="box")
    with pytest.raises(hrla.HrlaError, match="hi - lo"):
        hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, [(-1.0, 1.0), (2.0, 2.0)])


@pytest.mark.parametrize("d", [1, 3, 20])
def test_a_box_per_coordinate_with_different_sides(d):
    # Sides on scales 10^6 apart (an amplitude, a centre, a width): every
    # chain stays in its own coordinates' sides, as domain= and as bounds=,
    # for a built-in and a Python function.
    lo = np.array([[0.0, 0.0, 0.1][i % 3] for i in range(d)])
    hi = np.array([[10.0, 1e5, 0.1 + 1e-1][i % 3] for i in range(d)])
    box = list(zip(lo, hi))
    centre = (lo + hi) / 2

    def bowl(X):
        return 0.5 * np.sum((X - centre) ** 2, axis=1), X - centre

    for fun in (hrla.Rastrigin(), bowl):
        opt = hrla.Optimizer(fun, hrla.Hrla.paper(0.01), 4.0, box, domain=box, chains=5, seed=3)
        assert np.all(opt.x >= lo) and np.all(opt.x <= hi)
        opt.step(30)
        assert opt.dim == d and opt.x.shape == (5, d)
        assert np.all(opt.x >= lo) and np.all(opt.x <= hi), opt.x
        assert np.all(opt.best_x >= lo) and np.all(opt.best_x <= hi)
    r = hrla.minimize(lambda x: (0.5 * np.sum((x - centre) ** 2), x - centre), box, jac=True, method="hrla",
                      maxfun=4_000, seed=2, chains=8)
    assert r.x.shape == (d,) and np.all(r.x >= lo) and np.all(r.x <= hi)
    # The polish lands on the bowl's centre, inside every side.
    assert r.fun < 1e-12, r
    with pytest.raises(ValueError, match="bounds has dimension 2 but dim has 3"):
        hrla.minimize(hrla.Rastrigin(), [(-1.0, 1.0)] * 2, dim=3, maxfun=10_000)
    with pytest.raises(TypeError, match="a box must be"):
        hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Point([0.0]), domain="box")

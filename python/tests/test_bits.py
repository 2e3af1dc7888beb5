"""The Python package and the Rust crate give bit-identical results for the
same configuration and seed (the Rust side: python/examples/golden.rs)."""

import math

import numpy as np

import hrla


def bits(values):
    """Each float's 64 bits as 16 hex digits, as the golden example prints."""
    return [f"{v:016x}" for v in np.asarray(values, dtype=np.float64).ravel().view(np.uint64)]


def check_state(opt, report, g):
    assert report.termination == g["termination"]
    assert report.iterations == g["iterations"]
    assert report.evaluations == g["evaluations"]
    assert opt.best_chain == g["best_chain"]
    x, value, _ = opt.best
    assert bits([value]) == [g["best_value"]]
    assert bits(x) == g["best_x"]
    assert bits(opt.x) == g["x"]
    assert bits(opt.y) == g["y"]
    assert bits(opt.value) == g["value"]


def test_hrla_linear_rastrigin(golden):
    opt = hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), hrla.Linear(0.1, 4.0, 500),
                         hrla.Gaussian([3.0] * 10, math.sqrt(10.0)), chains=10, seed=7)
    check_state(opt, opt.run(), golden["hrla_linear_rastrigin"])


def test_ula_geometric_levy_with_builder(golden):
    opt = (hrla.Builder(hrla.Levy(), hrla.Ula.paper(0.005), hrla.Geometric(0.5, 20.0, 400),
                        hrla.Point([2.0] * 5))
           .seed(11).stop(hrla.Stop().steps(400).target(1e-3).stall(100, 1e-9)).build(chains=4))
    check_state(opt, opt.run(), golden["ula_geometric_levy"])


def quadratic_run(potential, step_by_step):
    opt = hrla.Optimizer(potential, hrla.Hrla.paper(0.05), 1.0, hrla.Gaussian([1.0, -1.0], 1.0),
                         chains=8, seed=5, stop=hrla.Stop().steps(200), dim=2)
    if step_by_step:
        # The same run driven by step(): the stopping rule then holds.
        for _ in range(4):
            opt.step(50)
        assert opt.termination() == "Steps"
    return opt, opt.run()


def test_builtin_quadratic(golden):
    opt, report = quadratic_run(hrla.Quadratic(1.0, [0.0, 0.0]), step_by_step=False)
    check_state(opt, report, golden["hrla_quadratic"])


def test_batched_python_potential_matches_the_builtin(golden):
    """A numpy quadratic, written in the kernel's order of operations
    (sum of (k r) r, then halved), gives the same bits as the built-in: the
    batched call sees exactly the points the kernel's step reaches."""
    calls = []

    def quadratic(X):
        calls.append(X.shape)
        u = 0.5 * ((0.0 + X[:, 0] * X[:, 0]) + X[:, 1] * X[:, 1])
        return u, X.copy()

    opt, report = quadratic_run(quadratic, step_by_step=True)
    check_state(opt, report, golden["hrla_quadratic"])
    # Once for the initial points, then once per step, for all 8 chains.
    assert calls == [(8, 2)] * 201


def test_minimize_with_a_vectorized_gradient_is_algorithm_1s_bits(golden):
    """The same quadratic through minimize's scipy conventions (columns,
    jac=True) and the same settings: the Rust crate's best, bit for bit."""
    g = golden["hrla_quadratic"]

    def columns(x):
        u = 0.5 * ((0.0 + x[0] * x[0]) + x[1] * x[1])
        return u, x.copy()

    res = hrla.minimize(columns, None, jac=True, vectorized=True, method="hrla", h=0.05, schedule=1.0,
                        start=hrla.Gaussian([1.0, -1.0], 1.0), chains=8, rng=5, maxiter=200, polish=0, dim=2)
    assert res.termination == g["termination"] and res.nit == g["iterations"]
    assert res.nfev == res.njev == g["evaluations"]
    assert bits([res.fun]) == [g["best_value"]] and bits(res.x) == g["best_x"]


def test_ola_box_ackley_and_polish(golden):
    g = golden["ola_box_ackley_polish"]
    box = hrla.Interval(-5.0, 5.0)
    opt = hrla.Optimizer(hrla.Ackley(), hrla.Ola.paper(0.001), 2.0, box, chains=6, seed=3,
                         stride=10, stop=hrla.Stop().steps(300), domain=box, dim=3)
    check_state(opt, opt.run(), g)
    polished = opt.polish(opt.best_chain, hrla.PolishSettings(200))
    assert bits([polished.value]) == [g["polished_value"]]
    assert polished.evaluations == g["polished_evaluations"]
    assert polished.end == g["polished_end"]
    x, value, _ = opt.best
    assert bits([value]) == [g["after_best_value"]]
    assert bits(x) == g["after_best_x"]
    assert opt.evaluations == g["after_evaluations"]


def test_auto(golden):
    g = golden["auto_rastrigin"]
    s = hrla.Auto().minimize(hrla.Rastrigin(), hrla.Interval(-5.12, 5.12), 20_000, 5, dim=4)
    assert bits(s.x) == g["x"]
    assert bits([s.value, s.step, s.inverse_temperature]) == [g["value"], g["step"], g["inverse_temperature"]]
    assert (s.evaluations, s.rounds) == (g["evaluations"], g["rounds"])

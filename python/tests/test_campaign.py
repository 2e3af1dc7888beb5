"""A property campaign over the public entry points (`minimize`,
`Optimizer` and its methods, `Auto`), with hostile arguments and hostile
potentials: numbers that are NaN, infinite, huge, tiny or negative, values
of the wrong type, counts near the integer limits, functions that return
NaN, infinities, complex numbers, wrong shapes or types, or raise.

Whatever the input, a call either returns or raises an `Exception` of a
documented kind (an `hrla.HrlaError` other than `InternalError`,
`TypeError`, `ValueError`, `OverflowError`, `MemoryError`, or the
potential's own exception): never `PanicException` (a `BaseException`), an
abort or a hang (every run has a small evaluation or step budget; the
pytest-timeout bound catches a hang). A result that claims success has a
finite `fun`, above `-sqrt(MAX)`, equal to `U(x)`, within its budget.

Derandomized (a fixed sequence of cases, the same on every run), no
example database: the campaign is a deterministic test.
"""

import math
import sys
from collections import Counter

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import hrla

FLOOR = -math.sqrt(sys.float_info.max)

# Hostile potentials overflow on purpose.
pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")



def campaign(cases):
    """Hypothesis's settings for `cases` derandomized cases."""
    return settings(derandomize=True, database=None, deadline=None, max_examples=cases,
                    suppress_health_check=list(HealthCheck))


refusals = Counter()


class Boom(Exception):
    """The exception a hostile potential raises."""


def allowed(e):
    """Whether `e` is an exception the package documents."""
    if isinstance(e, hrla.InternalError):
        return False
    return isinstance(e, (hrla.HrlaError, TypeError, ValueError, OverflowError, MemoryError, Boom))


def call(f, *args, **kw):
    """`f(...)`, or None when it raised a documented exception; anything
    else (PanicException, InternalError, ...) fails the case."""
    try:
        return f(*args, **kw)
    except BaseException as e:  # noqa: BLE001 - the type is the verdict
        if isinstance(e, Exception) and allowed(e):
            refusals[type(e).__name__ + ": " + str(e)[:60]] += 1
            return None
        raise AssertionError(f"undocumented exception {type(e).__module__}.{type(e).__name__}: {e}") from e


# --- numbers --------------------------------------------------------------


def mostly(sane, hostile):
    """`sane` about nine times in ten, else `hostile`: with a dozen
    arguments a call, a third of the calls get only sane ones and reach a
    run. (Hypothesis favours the ends of a range, so the hostile draw is
    one in the middle.)"""
    return st.integers(0, 9).flatmap(lambda i: hostile if i == 4 else sane)


SPECIAL_FLOATS = [0.0, -0.0, 5e-324, 1e-308, 1e-12, 1.0, -1.0, 1e12, 1e300, 1.7e308, -1.7e308,
                  math.inf, -math.inf, math.nan]
WRONG = [None, "1.0", "abc", 1j, [1.0], (), object(), b"1", True]
# Anything a float argument could be given.
hostile_float = st.one_of(st.sampled_from(SPECIAL_FLOATS), st.floats(), st.integers(-2**70, 2**70),
                          st.sampled_from(WRONG))
SPECIAL_COUNTS = [0, 1, 2**31 - 1, 2**32, 2**40, 2**62, 2**63, 2**64 - 1, 2**64, -1, -2**63, 2.0, 1.5, "3",
                  None, math.nan, True]
hostile_count = st.sampled_from(SPECIAL_COUNTS)
# Chain counts: never the gigabytes between small and absurd, a legitimate
# request that would only be slow.
hostile_chains = st.sampled_from([0, 2**40, 2**50, 2**62, 2**63, 2**64 - 1, 2**64, -1, 2.0, "3", True])
budgets = mostly(st.integers(0, 6_000), st.sampled_from([2**64, -1, -2**63, 1.5, "1000", None]))
seeds = mostly(st.integers(0, 2**64 - 1), st.sampled_from([-1, 2**64, 1.0, "0", None]))
steps_h = mostly(st.floats(1e-4, 0.1), hostile_float)
temperatures = mostly(st.floats(0.05, 20.0), hostile_float)


# --- potentials -----------------------------------------------------------

def sphere(X):
    return np.sum(X * X, axis=1), 2 * X


def shift(X):
    """A well in [1, 2]: deterministic, finite everywhere."""
    r = X - 1.5
    return np.sum(r * r, axis=1) + np.sin(np.sum(X, axis=1)), 2 * r + np.cos(np.sum(X, axis=1))[:, None]


def nan_everywhere(X):
    return np.full(len(X), np.nan), np.zeros_like(X)


def inf_everywhere(X):
    return np.full(len(X), np.inf), np.zeros_like(X)


def minus_inf(X):
    return np.full(len(X), -np.inf), np.zeros_like(X)


def unbounded(X):
    with np.errstate(over="ignore", invalid="ignore"):
        return -np.exp(X[:, 0]), -np.exp(X)


def nan_half_space(X):
    with np.errstate(invalid="ignore", divide="ignore"):
        lx = np.log(X[:, 0])
        return lx * lx + np.sum(X * X, axis=1), np.concatenate([(2 * lx / X[:, 0])[:, None] + 2 * X[:, :1],
                                                                  2 * X[:, 1:]], axis=1)


def nan_gradient(X):
    return np.sum(X * X, axis=1), np.full_like(X, np.nan)


def huge(X):
    return np.full(len(X), 1e308), np.full_like(X, 1e308)


def complex_values(X):
    return np.sum(X * X, axis=1) + 0j, 2 * X


def bool_gradient(X):
    return np.sum(X * X, axis=1), X > 0


def string_values(X):
    return np.sum(X * X, axis=1).astype(str), 2 * X


def transposed(X):
    return np.sum(X * X, axis=1), (2 * X).T


def scalar(X):
    return 1.0, 2 * X


def triple(X):
    return np.sum(X * X, axis=1), 2 * X, None


def nothing(X):
    return None


def boom(X):
    raise Boom("from the potential")


def ragged(X):
    return [1.0] * len(X), [[1.0]] * len(X)


def big_ints(X):
    return [2**80] * len(X), 2 * X


DETERMINISTIC = {sphere, shift, huge}
POTENTIALS = [sphere, shift, nan_everywhere, inf_everywhere, minus_inf, unbounded, nan_half_space,
              nan_gradient, huge, complex_values, bool_gradient, string_values, transposed, scalar, triple,
              nothing, boom, ragged, big_ints]
BUILTINS = [hrla.Rastrigin(), hrla.Levy(), hrla.Ackley(), hrla.DoubleWell(), hrla.StyblinskiTang()]
SANE = [sphere, shift]
# Half sane, a third hostile functions, the rest not a potential at all.
potentials = st.integers(0, 5).flatmap(
    lambda i: st.sampled_from(["sphere", 3.0, None]) if i == 3 else st.sampled_from(POTENTIALS) if i >= 4
    else st.sampled_from(BUILTINS + SANE))
boxes = mostly(st.tuples(st.floats(-10, 0), st.floats(0.5, 10)),
               st.tuples(st.sampled_from([-1e308, 0.0, 1.0, 1e308, math.nan, -math.inf, "1", 1j, None]),
                         st.sampled_from([-1e308, 0.0, 1.0, 1e308, math.nan, math.inf, "2", True, None])))
dims = mostly(st.sampled_from([1, 2, 3, 5, 10]), st.sampled_from([0, 17, -1, 2**64, None, 2.0, "2"]))


def check_result(res, fun, budget):
    """A result that claims success is finite, above the floor, U at x,
    within the budget."""
    assert res.status == hrla.TERMINATIONS.index(res.termination)
    assert res.all_diverged == (res.diverged_chains == res.chains)
    if not res.success:
        return
    # "auto" rejects an infeasible proposal and keeps the chain's basin:
    # every last proposal infeasible is no failure there.
    assert not res.all_diverged or res.method == "auto"
    assert math.isfinite(res.fun) and res.fun > FLOOR, res
    x = np.asarray(res.x, dtype=np.float64)
    assert np.all(np.isfinite(x)), res
    limit = 125_000 if budget is None else budget  # minimize's default maxfun
    assert isinstance(limit, int) and res.nfev <= limit, res
    if isinstance(fun, hrla.Potential):
        u, _ = fun.value_and_gradient(x[None, :])
        assert u[0] == res.fun, (u[0], res)
    elif fun in DETERMINISTIC:
        u, _ = fun(x[None, :])
        assert math.isclose(u[0], res.fun, rel_tol=1e-12, abs_tol=1e-300), (u[0], res)


cases = dict.fromkeys(["minimize", "minimize returned", "minimize succeeded", "optimizer", "optimizer built",
                       "operations", "operations returned", "auto", "auto returned"], 0)


def as_fun(potential, form):
    """A batched potential as minimize's fun: ``"columns"`` (vectorized,
    jac=True, x of shape (D, S)), ``"point"`` (jac=True, one point) or
    ``"values"`` (one point, no gradient: finite differences); anything
    else as it is."""
    if not callable(potential) or isinstance(potential, hrla.Potential):
        return potential, {}
    if form == "columns":
        def columns(x):
            answer = potential(x.T)
            try:
                u, g = answer
            except (TypeError, ValueError):
                return answer
            return u, np.asarray(g).T if isinstance(g, np.ndarray) else g
        return columns, {"jac": True, "vectorized": True}

    def point(x):
        answer = potential(np.asarray(x)[None, :])
        try:
            u, g = answer
            return u[0], g[0]
        except (TypeError, ValueError, IndexError, KeyError):
            return answer

    if form == "point":
        return point, {"jac": True}
    return (lambda x: point(x)[0]), {}


@pytest.mark.timeout(600)
@campaign(3000)
@given(fun=potentials, form=st.sampled_from(["columns", "point", "values"]), box=boxes, d=dims,
       method=mostly(st.sampled_from(["auto", "hrla", "ula", "ola"]), st.sampled_from(["bogus", 3, None])),
       budget=budgets, chains=mostly(st.one_of(st.none(), st.integers(1, 40)), hostile_chains), seed=seeds,
       h=steps_h, schedule=mostly(st.one_of(temperatures, st.builds(hrla.Linear, st.floats(0.1, 1), st.floats(1, 5),
                                                                    st.integers(1, 100))), hostile_float),
       steps=mostly(st.one_of(st.none(), st.integers(1, 300)), hostile_count),
       target=mostly(st.none(), hostile_float),
       polish=mostly(st.integers(0, 300), st.sampled_from([2**64, -1, 2.5, None])),
       sampler_settings_for_auto=mostly(st.just(False), st.just(True)))
def test_minimize_never_panics_and_never_claims_too_much(fun, form, box, d, method, budget, chains, seed, h,
                                                          schedule, steps, target, polish,
                                                          sampler_settings_for_auto):
    cases["minimize"] += 1
    # D pairs when D is a small count, else one pair and dim=.
    pairs = isinstance(d, int) and 0 <= d <= 20
    f, conventions = as_fun(fun, form)
    sampler = {"h": h, "schedule": schedule, "polish": polish}
    if method == "auto" and not sampler_settings_for_auto:
        sampler = {}  # else refused, naming the first
    res = call(hrla.minimize, f, [box] * d if pairs else box, dim=None if pairs else d, method=method,
               maxfun=budget, chains=chains, seed=seed, maxiter=steps, target=target, **sampler, **conventions)
    if res is not None:
        cases["minimize returned"] += 1
        cases["minimize succeeded"] += bool(res.success)
        check_result(res, fun, budget)


SAMPLERS = mostly(
    st.one_of(st.builds(hrla.Hrla.paper, st.floats(1e-3, 0.1)), st.builds(hrla.Ula.paper, st.floats(1e-3, 0.1)),
              st.builds(hrla.Ola.paper, st.floats(1e-3, 0.1))),
    st.one_of(
        st.builds(lambda h, b, a, be: call(hrla.Hrla, h, b=b, alpha=a, beta=be), hostile_float, hostile_float,
                  hostile_float, hostile_float),
        st.builds(lambda h: call(hrla.Ula.paper, h), hostile_float),
        st.builds(lambda h: call(hrla.Ola.paper, h), hostile_float),
        st.sampled_from(["hrla", None]),
    ),
)
STARTS = mostly(
    st.one_of(st.builds(lambda d, s: hrla.Gaussian([1.0] * d, s), st.sampled_from([1, 2, 3]), st.floats(0.1, 3)),
              st.builds(lambda d: hrla.Point([0.5] * d), st.sampled_from([1, 2, 3])),
              st.builds(hrla.Interval, st.floats(-5, 0), st.floats(0.5, 5))),
    st.one_of(
        st.builds(lambda m, s, d: call(hrla.Gaussian, [m] * d, s), hostile_float, hostile_float, st.integers(0, 4)),
        st.builds(lambda x, d: call(hrla.Point, [x] * d), hostile_float, st.integers(0, 4)),
        st.builds(lambda box: call(hrla.Interval, *box), boxes),
        st.sampled_from([None, (0.0, 1.0)]),
    ),
)
SCHEDULES = mostly(
    st.one_of(temperatures, st.builds(hrla.Linear, st.floats(0.1, 1), st.floats(1, 5), st.integers(1, 100)),
              st.builds(hrla.Geometric, st.floats(0.1, 1), st.floats(1, 5), st.integers(1, 100))),
    st.one_of(
        hostile_float,
        st.builds(lambda a, b, k: call(hrla.Linear, a, b, k), hostile_float, hostile_float, hostile_count),
        st.builds(lambda a, b, k: call(hrla.Geometric, a, b, k), hostile_float, hostile_float, hostile_count),
        st.builds(lambda a: call(hrla.Constant, a), hostile_float),
    ),
)


@st.composite
def stops(draw):
    """Stopping rules that always include a small budget (so that `run`
    ends), sometimes with hostile ones besides."""
    stop = hrla.Stop()
    if draw(st.booleans()):
        stop = call(stop.steps, draw(mostly(st.integers(1, 200), st.just(0)))) or stop
    else:
        stop = call(stop.evaluations, draw(mostly(st.integers(1, 3_000), st.just(0)))) or stop
    if draw(st.integers(0, 3)) == 0:
        stop = call(stop.target, draw(mostly(st.floats(-1, 1), hostile_float))) or stop
    if draw(st.integers(0, 3)) == 0:
        stop = call(stop.stall, draw(mostly(st.integers(1, 50), hostile_count)),
                    draw(mostly(st.floats(0, 1), hostile_float))) or stop
    return stop


chain_index = mostly(st.integers(0, 3), hostile_count)
# `step(n)` does what it is asked, however long that takes (Ctrl-C stops
# it): the campaign asks for few steps, or for counts it must refuse.
step_count = mostly(st.integers(0, 50), st.sampled_from([-1, 2**64, 1.5, "3", None, math.nan]))
operations = st.lists(st.one_of(
    st.tuples(st.just("step"), step_count),
    st.tuples(st.just("run")),
    st.tuples(st.just("polish"), chain_index, mostly(st.integers(0, 300), hostile_count)),
    st.tuples(st.just("quench"), chain_index, mostly(st.integers(0, 300), hostile_count)),
    st.tuples(st.just("restart"), chain_index, mostly(st.floats(-3, 3), hostile_float)),
    st.tuples(st.just("read")),
), max_size=6)


@pytest.mark.timeout(600)
@campaign(3000)
@given(fun=potentials, sampler=SAMPLERS, schedule=SCHEDULES, start=STARTS,
       chains=mostly(st.integers(1, 20), hostile_chains), seed=seeds,
       stride=mostly(st.integers(1, 10), hostile_count), stop=stops(),
       domain=mostly(st.one_of(st.none(), st.builds(hrla.Interval, st.floats(-5, 0), st.floats(0.5, 5))),
                     st.builds(lambda box: call(hrla.Interval, *box), boxes)),
       d=mostly(st.none(), dims), ops=operations)
def test_optimizer_never_panics_and_never_claims_too_much(fun, sampler, schedule, start, chains, seed, stride,
                                                           stop, domain, d, ops):
    cases["optimizer"] += 1
    opt = call(hrla.Optimizer, fun, sampler, schedule, start, chains=chains, seed=seed, stride=stride, stop=stop,
               domain=domain, dim=d if d is not None or not isinstance(start, hrla.Interval) else 2)
    if opt is None:
        return
    cases["optimizer built"] += 1
    for op in ops:
        cases["operations"] += 1
        if op[0] == "step":
            done = call(opt.step, op[1])
        elif op[0] == "run":
            done = report = call(opt.run)
            if report is not None:
                assert math.isfinite(report.value) and report.value > FLOOR, report
                assert report.value == opt.best[1]
                assert report.termination in hrla.TERMINATIONS
        elif op[0] in ("polish", "quench"):
            done = p = call(getattr(opt, op[0]), op[1], call(hrla.PolishSettings, op[2]))
            if p is not None:
                assert not math.isfinite(p.value) or p.value > FLOOR, p
        elif op[0] == "restart":
            done = call(opt.restart, op[1], [op[2]] * opt.dim)
        else:
            # Every reader answers, whatever the state.
            x, value, _ = opt.best
            assert x.shape == (opt.dim,) and opt.x.shape == (len(opt), opt.dim)
            assert opt.value.shape == opt.diverged.shape == (len(opt),)
            assert opt.iteration >= 0 and opt.evaluations >= len(opt)
            assert 0 <= opt.best_chain < len(opt)
            done = True
        cases["operations returned"] += done is not None


@pytest.mark.timeout(600)
@campaign(1500)
@given(fun=potentials, steps=mostly(st.none(), hostile_count), quench=mostly(st.none(), hostile_count),
       ladder=mostly(st.none(), hostile_float),
       scale=mostly(st.none(), hostile_float), stall=mostly(st.none(), hostile_count),
       accept=mostly(st.none(), hostile_float), box=boxes,
       budget=budgets, chains=mostly(st.one_of(st.none(), st.integers(1, 40)), hostile_chains), d=dims)
def test_auto_never_panics_and_never_claims_too_much(fun, steps, quench, ladder, scale, stall, accept,
                                                      box, budget, chains, d):
    cases["auto"] += 1
    auto = call(hrla.Auto, steps=steps, quench=quench, ladder=ladder, step_scale=scale,
                stall=stall, accept=accept)
    interval = call(hrla.Interval, *box)
    if auto is None or interval is None:
        return
    s = call(auto.minimize, fun, interval, budget, 0, chains=chains, dim=d)
    if s is not None:
        cases["auto returned"] += 1
        assert isinstance(budget, int) and s.evaluations <= budget
        if not s.all_diverged:
            assert math.isfinite(s.value) and s.value > FLOOR, s


def test_campaign_case_counts(capsys):
    """Runs last in this file: how many cases each property ran, and how
    many reached a result."""
    with capsys.disabled():
        print(f"\ncampaign cases: {cases}")
        print("refusals:", *(f"{n} {e}" for e, n in refusals.most_common(12)), sep="\n  ")

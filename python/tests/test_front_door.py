"""The front door's promises to a scipy user (issue #35): what ``minimize``
does with the user's ``fun``, callback and arguments, in every method and
every form of ``fun``."""

import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import hrla

METHODS = ["auto", "hrla", "ula", "ola"]
BOX = [(-2.0, 2.0)] * 3


def bits(a):
    return np.asarray(a, dtype=np.float64).tobytes()


def same(a, b):
    assert bits(a.x) == bits(b.x) and bits(a.fun) == bits(b.fun), (a.x, b.x, a.fun, b.fun)
    assert (a.nfev, a.nit, a.termination) == (b.nfev, b.nit, b.termination)


# --- Ctrl-C: at the next call of fun, in every method and form ----------


def sphere_value(x):
    return float(np.sum((np.asarray(x) - 0.3) ** 2))


def form(name, body):
    """``minimize``'s arguments for ``fun`` in the form ``name``, each call
    of ``fun`` (or of ``jac``) running ``body()`` first."""
    if name == "scalar":
        return dict(fun=lambda x: (body(), sphere_value(x))[1])
    if name == "3-point":
        return dict(fun=lambda x: (body(), sphere_value(x))[1], jac="3-point")
    if name == "jac":
        return dict(fun=lambda x: (body(), (sphere_value(x), 2 * (x - 0.3)))[1], jac=True)
    if name == "jac-callable":
        return dict(fun=sphere_value, jac=lambda x: (body(), 2 * (x - 0.3))[1])
    if name == "vectorized":
        return dict(fun=lambda x: (body(), np.sum((x - 0.3) ** 2, axis=0))[1], vectorized=True)
    if name == "map":
        return dict(fun=lambda x: (body(), sphere_value(x))[1], workers=lambda f, xs: [f(x) for x in xs])
    raise AssertionError(name)


FORMS = ["scalar", "3-point", "jac", "jac-callable", "vectorized", "map"]


@pytest.mark.timeout(600)
@settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(name=st.sampled_from(FORMS), method=st.sampled_from(METHODS), k=st.integers(1, 400),
       how=st.sampled_from(["signal", "raise"]), observed=st.booleans())
def test_ctrl_c_in_fun_reaches_the_caller_at_once(name, method, k, how, observed):
    # The k-th call of fun (or jac) is interrupted: by SIGINT, whose
    # handler raises KeyboardInterrupt inside it, or by raising it. The
    # run must end with it there: no call after it, whatever the method,
    # the form of fun, and whether a callback and time limit watch.
    calls = [0]

    def body():
        calls[0] += 1
        if calls[0] == k:
            if how == "signal":
                signal.raise_signal(signal.SIGINT)
            raise KeyboardInterrupt

    watch = dict(callback=lambda intermediate_result: None, maxtime=1e6) if observed else {}
    # A run long enough to reach the k-th call: auto's convergence rule off.
    endless = dict(converge=False) if method == "auto" else {}
    with pytest.raises(KeyboardInterrupt):
        hrla.minimize(bounds=BOX, method=method, maxfun=10**7, rng=k, **form(name, body), **watch, **endless)
    assert calls[0] == k


def test_ctrl_c_from_a_timer_while_fun_sleeps():
    # The case: a fun that takes 10 ms, the default method, no
    # observer, SIGINT from another thread. Each method must raise
    # KeyboardInterrupt with no call of fun after the signal was handled.
    # The 60 s limit only guards against a hang; the verdict is what
    # happened, not how fast.
    code = textwrap.dedent("""
        import signal, threading, time
        import numpy as np
        import hrla

        calls = [0]
        seen = []

        def handler(signum, frame):
            seen.append(calls[0])
            raise KeyboardInterrupt

        signal.signal(signal.SIGINT, handler)

        def f(x):
            calls[0] += 1
            time.sleep(0.01)
            return float(np.sum((x - 0.3) ** 2))

        for method in ("auto", "hrla"):
            calls[0] = 0
            del seen[:]
            timer = threading.Timer(0.2, signal.raise_signal, (signal.SIGINT,))
            timer.start()
            try:
                hrla.minimize(f, [(-5.0, 5.0)] * 3, method=method, maxfun=10**12, rng=1)
            except KeyboardInterrupt:
                pass
            else:
                raise AssertionError("no KeyboardInterrupt")
            timer.join()
            assert len(seen) == 1 and calls[0] == seen[0], (calls, seen)
        print("ok")
    """)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout.strip() == "ok", p.stderr[-3000:]


def test_the_first_ctrl_c_ends_a_run_whose_worker_hangs(tmp_path):
    # workers=2: the first call of fun at a point with x_0 > 1 signals the
    # parent once (the file marks it done), then hangs for good. scipy
    # raises at the first Ctrl-C; so must hrla, without a second call of
    # the hanging fun. The limit only guards a hang.
    code = textwrap.dedent("""
        import os, signal, sys, time
        import numpy as np
        import hrla

        def f(x, mark):
            if x[0] > 1.0:
                try:
                    os.close(os.open(mark, os.O_CREAT | os.O_EXCL))
                except FileExistsError:
                    pass
                else:
                    os.kill(os.getppid(), signal.SIGINT)
                time.sleep(3600)
            return float(np.sum((x - 0.3) ** 2))

        if __name__ == "__main__":
            try:
                hrla.minimize(f, [(-5.0, 5.0)] * 2, args=(sys.argv[1],), workers=2, maxfun=10**9, rng=1,
                              converge=False)
            except KeyboardInterrupt:
                print("ok")
    """)
    p = subprocess.run([sys.executable, "-c", code, str(tmp_path / "signalled")], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 0 and p.stdout.strip() == "ok", p.stderr[-3000:]


def pyrastrigin(X):
    t = 2 * np.pi * X
    return X.shape[1] + np.sum(X * X - np.cos(t), axis=1), 2 * X + 2 * np.pi * np.sin(t)


def optimizer(potential):
    return hrla.Optimizer(potential, hrla.Hrla.paper(0.01), 4.0, hrla.Gaussian([3.0] * 4, 3.0), chains=20,
                          seed=4, stop=hrla.Stop().steps(10**12))


def state(opt):
    return (opt.iteration, opt.evaluations, bits(opt.x), bits(opt.y), bits(opt.gradient), bits(opt.best_x),
            bits(opt.best_value), opt.best_chain)


@pytest.mark.parametrize("k", [1, 7])
def test_an_optimizer_interrupted_between_steps_goes_on_with_the_same_bits(k):
    # Ctrl-C seen between two steps (here raised by the observer after
    # step k) leaves the optimiser after a whole step: going on gives the
    # bits of a run never interrupted.
    def observer(iteration, evaluations, best):
        if iteration == k:
            raise KeyboardInterrupt

    opt = optimizer(pyrastrigin)
    with pytest.raises(KeyboardInterrupt):
        opt.run(observer)
    assert opt.iteration == k
    opt.step(3)
    fresh = optimizer(pyrastrigin)
    fresh.step(k + 3)
    assert state(opt) == state(fresh)


def test_an_optimizer_interrupted_inside_its_potential_goes_on_with_the_same_bits():
    # Ctrl-C inside the potential (its k-th call) ends the run there, with
    # no call after it. The call it was in is undone (its points were
    # moved but never evaluated): the optimiser is as before `run`, and
    # going on gives the bits of a run never interrupted.
    calls = [0]

    def potential(X):
        calls[0] += 1
        if calls[0] == 5:
            raise KeyboardInterrupt
        return pyrastrigin(X)

    opt = optimizer(potential)
    before = state(opt)
    with pytest.raises(KeyboardInterrupt):
        opt.run()
    assert calls[0] == 5
    assert opt.iteration == 0
    assert state(opt) == before
    opt.step(3)
    fresh = optimizer(pyrastrigin)
    fresh.step(3)
    assert state(opt) == state(fresh)


# --- fun gets a copy of the point ----------------------------------------


def writing(name, write):
    """The arguments of ``form`` ``name`` whose calls write into their
    ``x`` after computing the value when ``write``."""
    def scrub(x):
        if write:
            x[...] = 0.3
    if name == "scalar":
        return dict(fun=lambda x: (sphere_value(x), scrub(x))[0])
    if name == "jac":
        return dict(fun=lambda x: ((sphere_value(x), 2 * (x - 0.3)), scrub(x))[0], jac=True)
    if name == "jac-callable":
        return dict(fun=lambda x: (sphere_value(x), scrub(x))[0], jac=lambda x: (2 * (x - 0.3), scrub(x))[0])
    if name == "vectorized":
        return dict(fun=lambda x: (np.sum((x - 0.3) ** 2, axis=0), scrub(x))[0], vectorized=True)
    if name == "map":
        return dict(fun=lambda x: (sphere_value(x), scrub(x))[0], workers=lambda f, xs: [f(x) for x in xs])
    raise AssertionError(name)


@pytest.mark.parametrize("method", ["auto", "hrla"])
@pytest.mark.parametrize("name", ["scalar", "jac", "jac-callable", "vectorized", "map"])
def test_fun_writing_into_its_argument_changes_nothing(method, name):
    # scipy passes fun a copy of the point; so does hrla, in every path:
    # a fun that writes into x changes neither the run nor the result.
    clean = hrla.minimize(bounds=BOX, method=method, maxfun=3_000, rng=2, **writing(name, False))
    dirty = hrla.minimize(bounds=BOX, method=method, maxfun=3_000, rng=2, **writing(name, True))
    same(clean, dirty)
    assert bits(clean.jac) == bits(dirty.jac)


@pytest.mark.parametrize("method", ["auto", "hrla"])
def test_a_callback_writing_into_its_point_changes_nothing(method):
    def scribble(xk):
        xk[...] = 0.3

    def scribble_result(intermediate_result):
        intermediate_result.x[...] = 0.3

    clean = hrla.minimize(sphere_value, BOX, method=method, maxfun=3_000, rng=2, callback=lambda xk: None)
    for cb in (scribble, scribble_result):
        same(clean, hrla.minimize(sphere_value, BOX, method=method, maxfun=3_000, rng=2, callback=cb))


# --- a callback stops the run with any true answer ------------------------


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("answer", [True, np.True_, 1, np.int64(2), "stop"])
def test_a_true_answer_of_the_callback_stops_the_run(method, answer):
    res = hrla.minimize(sphere_value, BOX, method=method, maxfun=20_000, rng=1, callback=lambda xk: answer)
    assert res.termination == "Callback" and not res.success


@pytest.mark.parametrize("answer", [False, np.False_, 0, None, ""])
def test_a_false_answer_of_the_callback_goes_on(answer):
    res = hrla.minimize(sphere_value, BOX, maxfun=3_000, rng=1, callback=lambda xk: answer)
    assert res.termination in ("Evaluations", "Converged"), res


# --- counts as integral floats ------------------------------------------


@pytest.mark.parametrize("method", ["auto", "hrla"])
def test_counts_may_be_integral_floats_or_numpy_integers(method):
    plain = hrla.minimize(sphere_value, BOX, method=method, maxfun=3_000, maxiter=40, rng=1)
    for maxfun, maxiter in ((3e3, 40.0), (np.int64(3_000), np.uint8(40)), (np.float32(3_000), np.float64(40))):
        same(plain, hrla.minimize(sphere_value, BOX, method=method, maxfun=maxfun, maxiter=maxiter, rng=1))


@pytest.mark.parametrize("kw, error, text", [
    ({"maxfun": 1e5 + 0.5}, ValueError, "maxfun must be a whole number, got 100000.5"),
    ({"maxfun": float("inf")}, ValueError, "maxfun must be finite, got inf"),
    ({"maxfun": float("nan")}, ValueError, "maxfun must be finite, got nan"),
    ({"maxiter": 2.5}, ValueError, "maxiter must be a whole number"),
    ({"maxfun": "1e5"}, TypeError, "maxfun must be an int"),
    ({"maxfun": True}, TypeError, "maxfun must be an int"),
])
def test_a_count_that_is_not_whole_is_named(kw, error, text):
    with pytest.raises(error, match=text):
        hrla.minimize(sphere_value, BOX, **kw)


# --- a workers map's answers are counted ----------------------------------


@pytest.mark.parametrize("jac", [None, True, "callable"])
@pytest.mark.parametrize("wrong", [lambda xs: xs[:3], lambda xs: xs + xs[:1], lambda xs: []])
def test_a_workers_map_with_the_wrong_number_of_results_is_named(jac, wrong):
    # A map that drops or adds results would misalign values and points
    # (or fail deep in numpy): the one path through the workers counts.
    def mapper(f, xs):
        return wrong([f(x) for x in xs])

    kw = {None: {}, True: {"jac": True}, "callable": {"jac": lambda x: 2 * (x - 0.3)}}[jac]
    fun = (lambda x: (sphere_value(x), 2 * (x - 0.3))) if jac is True else sphere_value
    with pytest.raises(ValueError, match=r"the workers map returned \d+ results for \d+ points"):
        hrla.minimize(fun, BOX, method="hrla", workers=mapper, maxfun=3_000, rng=1, **kw)


# --- the result prints as scipy's ------------------------------------------


@pytest.mark.parametrize("method", ["auto", "hrla"])
@pytest.mark.parametrize("dim", [3, 20])
def test_the_result_prints_one_field_a_line_as_scipys(method, dim):
    so = pytest.importorskip("scipy.optimize")
    res = hrla.minimize(sphere_value, [(-2.0, 2.0)] * dim, method=method, maxfun=3_000 * dim, rng=1)
    text = repr(res)
    assert str(res) == text and text.count("\n") == len(res) - 1
    assert text.splitlines()[0].strip().startswith("message: ")
    # scipy's own printer, given the same order of keys, prints the same.
    peer = so.OptimizeResult(**res, _order_keys=list(hrla.OptimizeResult._order_keys))
    assert repr(peer) == text
    assert repr(hrla.OptimizeResult()) == "OptimizeResult()"


# --- one reading of the limits in every method -----------------------------


INF = float("inf")


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("kw, termination, nit", [
    ({"maxiter": 0}, "Steps", 0),            # the starts only
    ({"target": INF}, "Target", 0),          # any finite value reaches it: the first look stops
    ({"stall": (1, INF)}, "Stalled", 1),     # no fall exceeds inf: stalled after the window
    ({"stall": (3, INF)}, "Stalled", 3),
])
def test_every_method_reads_the_limits_alike(method, kw, termination, nit):
    res = hrla.minimize(sphere_value, BOX, method=method, maxfun=20_000, rng=1, **kw)
    # "auto" succeeds only when it converged or met its target: a run that
    # maxiter cut short did not converge.
    success = method != "auto" or termination != "Steps"
    assert (res.termination, res.nit, res.success) == (termination, nit, success), res


@pytest.mark.parametrize("method", METHODS)
def test_a_target_of_minus_inf_is_no_target(method):
    # Never reached: the run is the one without a target.
    same(hrla.minimize(sphere_value, BOX, method=method, maxfun=5_000, rng=1),
         hrla.minimize(sphere_value, BOX, method=method, maxfun=5_000, rng=1, target=-INF))


# --- scipy's callback forms ---------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_a_callback_of_dual_annealings_form_gets_x_f_and_where(method):
    seen = []

    def callback(x, f, context):
        seen.append((x.copy(), f, context))

    res = hrla.minimize(sphere_value, BOX, method=method, maxfun=5_000, rng=1, callback=callback)
    assert seen and {c for _, _, c in seen} <= {0, 1} and seen[0][2] == 0
    # The last call saw the result; a call of context 1 only for the
    # polish's lower best, and only last.
    assert bits(seen[-1][0]) == bits(res.x) and seen[-1][1] == res.fun
    assert all(c == 0 for _, _, c in seen[:-1])
    if seen[-1][2] == 1:
        assert seen[-1][1] < seen[-2][1]
    for x, f, _ in seen:
        assert f == sphere_value(x)


def test_the_samplers_report_their_polish_as_a_local_search():
    seen = []
    hrla.minimize(sphere_value, BOX, method="hrla", maxiter=5, maxfun=5_000, rng=1,
                  callback=lambda x, f, context: seen.append(context))
    assert seen == [0] * 5 + [1]


@pytest.mark.parametrize("method", METHODS)
def test_a_callback_of_two_or_three_arguments_stops_the_run(method):
    for callback in (lambda x, f, context: True, lambda x, f, accept=None: True, lambda x, f: True):
        res = hrla.minimize(sphere_value, BOX, method=method, maxfun=20_000, rng=1, callback=callback)
        assert res.termination == "Callback"


def test_one_callback_serves_dual_annealing_and_hrla():
    so = pytest.importorskip("scipy.optimize")
    calls = []

    def callback(x, f, context):
        calls.append(context)

    so.dual_annealing(sphere_value, BOX, maxiter=5, rng=1, callback=callback)
    hrla.minimize(sphere_value, BOX, maxfun=3_000, rng=1, callback=callback)
    assert calls


# --- what a spent budget left -------------------------------------------------


def left_of(message):
    """The calls left and their shares, from a message's budget note."""
    used, total = message.split(" calls of fun used")[0].rsplit("; ", 1)[1].split(" of maxfun=")
    shares = message.split(" left: ", 1)[1].split("; ") if " left: " in message else []
    return int(used.replace(",", "")), int(total.replace(",", "")), shares


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("kw", [{"maxfun": 10_007}, {"jac": "3-point", "maxfun": 12_345},
                                {"chains": 16, "maxfun": 30_000}])
def test_a_budget_spent_says_what_it_left_and_why(method, kw):
    if method == "auto":
        # A run maxfun ends, not one that converged; Auto alone, whose
        # gradients leave shares of maxfun (the default without a gradient
        # hands them to the ensemble: the next test).
        kw = {**kw, "converge": False}
        method = hrla.Auto()
    res = hrla.minimize(sphere_value, BOX, method=method, rng=1, **kw)
    maxfun = kw["maxfun"]
    assert res.nfev < maxfun and res.termination in ("Evaluations", "Steps"), res
    used, total, shares = left_of(res.message)
    assert (used, total) == (res.nfev, maxfun), res.message
    # Each share names its calls; together they are what is left.
    assert sum(int(share.split(" ", 1)[0].replace(",", "")) for share in shares) == maxfun - res.nfev, res.message
    assert all(" " in share for share in shares)


@pytest.mark.parametrize("kw", [{"maxfun": 10_007}, {"jac": "3-point", "maxfun": 12_345}])
def test_without_a_gradient_auto_spends_maxfun_but_the_results_gradient(kw):
    # Auto's share, then the ensemble's values to the last call but the
    # gradient kept back for the result's jac (D + 1 or 2 D + 1 calls,
    # spent unless the best point's gradient was already known).
    res = hrla.minimize(sphere_value, BOX, rng=1, converge=False, **kw)
    cost = 1 + (2 if kw.get("jac") == "3-point" else 1) * len(BOX)
    assert res.termination == "Evaluations" and kw["maxfun"] - cost <= res.nfev <= kw["maxfun"], res
    assert "ensemble" in res.message and res.success is False, res.message


def test_a_budget_spent_whole_adds_no_note():
    res = hrla.minimize(hrla.Rastrigin(), BOX, maxfun=10_000, rng=1, converge=False)
    assert res.nfev == 10_000 and "maxfun=" not in res.message, res.message


def test_a_run_maxiter_ended_adds_no_note():
    res = hrla.minimize(sphere_value, BOX, method="hrla", maxiter=5, rng=1)
    assert res.termination == "Steps" and "maxfun=" not in res.message, res.message


# --- the README's table of scipy's keywords ---------------------------------


def test_the_readme_tables_every_keyword_of_scipys_global_optimisers():
    so = pytest.importorskip("scipy.optimize")
    import inspect
    import re
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    section = readme.split("Every keyword of scipy's global optimisers", 1)[1].split("\n\n", 2)[1]
    tabled = {name for row in section.splitlines() if row.startswith("| `")
              for name in re.findall(r"`(\w+)`", row.split(" | ")[0])}
    for f in (so.dual_annealing, so.differential_evolution, so.basinhopping):
        missing = set(inspect.signature(f).parameters) - tabled
        assert not missing, (f.__name__, missing)

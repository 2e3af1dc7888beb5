"""Ctrl-C during a run, in a process of its own (`test_hostile.py` runs it
with a time limit, so that a run that ignores the signal fails the test
instead of hanging it).

    python interrupts.py CASE

Each case starts a run that cannot end (a budget of 10^10 evaluations or
10^12 steps), sends SIGINT to this process from a timer thread, expects
`KeyboardInterrupt`, then checks that the optimiser was left after a whole
step: going on from there gives the bits of a run never interrupted, step
for step. The verdict never depends on when the signal came (it may even
come before the run starts: the interrupted optimiser has then done 0
steps, and the comparison still holds). Prints "ok" when every check
passed.
"""

import signal
import sys
import threading

import numpy as np

import hrla

# A process started with SIGINT ignored (a background job of a
# non-interactive shell inherits it so) would never see the signal: Python
# installs its handler only where SIGINT is not ignored at start-up.
signal.signal(signal.SIGINT, signal.default_int_handler)

DELAY = 0.3  # seconds before the SIGINT; any value gives the same verdict


def interrupted(call):
    """Calls `call()` with a SIGINT sent after DELAY seconds; it must
    raise KeyboardInterrupt."""
    timer = threading.Timer(DELAY, signal.raise_signal, (signal.SIGINT,))
    try:
        timer.start()
        call()
    except KeyboardInterrupt:
        return
    finally:
        timer.cancel()
    raise AssertionError("the call ended without KeyboardInterrupt")


def bits(a):
    return np.asarray(a, dtype=np.float64).tobytes()


def same_state(a, b):
    assert a.iteration == b.iteration, (a.iteration, b.iteration)
    assert a.evaluations == b.evaluations
    for field in ("x", "y", "gradient", "best_x", "best_value"):
        assert bits(getattr(a, field)) == bits(getattr(b, field)), field
    assert a.best_chain == b.best_chain


def optimizer(stop):
    # 1000 chains in 10-D: 10^4 coordinate-steps a step, so that 10^7
    # steps take far longer than the test's time limit.
    return hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Gaussian([3.0] * 10, 3.0),
                          chains=1000, seed=9, stop=stop)


def case_run():
    opt = optimizer(hrla.Stop().steps(10**12))
    interrupted(opt.run)
    first = opt.iteration
    # run() again goes on from there; interrupted a second time.
    interrupted(opt.run)
    assert opt.iteration >= first
    opt.step(3)
    fresh = optimizer(hrla.Stop().steps(10**12))
    fresh.step(opt.iteration)
    same_state(opt, fresh)


def case_step():
    opt = optimizer(None)
    interrupted(lambda: opt.step(10**7))
    opt.step(2)
    fresh = optimizer(None)
    fresh.step(opt.iteration)
    same_state(opt, fresh)


def case_minimize():
    interrupted(lambda: hrla.minimize(hrla.Rastrigin(), [(-5, 5)] * 10, method="hrla", chains=1000,
                                      maxfun=10**10))
    # The package is still usable.
    res = hrla.minimize(hrla.Rastrigin(), [(-5, 5)] * 2, method="hrla", maxfun=5_000)
    assert res.success


def case_auto():
    interrupted(lambda: hrla.minimize(hrla.Rastrigin(), [(-5, 5)] * 10, maxfun=10**10, converge=False))
    res = hrla.minimize(hrla.Rastrigin(), [(-5, 5)] * 2, maxfun=20_000)
    assert res.success and res.termination == "Converged", res


def case_scalar():
    """minimize with a scipy user's fun(x) and finite differences, in
    each method; the callback and time limit watch the run too."""
    for method in ("auto", "hrla"):
        interrupted(lambda: hrla.minimize(lambda x: float(x @ x), [(-5, 5)] * 3, method=method, maxfun=10**12,
                                          maxtime=10**6, callback=lambda intermediate_result: None,
                                          **({"converge": False} if method == "auto" else {})))
    res = hrla.minimize(lambda x: float(x @ x), [(-5, 5)] * 3, maxfun=50_000)
    assert res.success and res.termination == "Converged", res


def case_python_potential():
    """A Python potential's run: SIGINT seen between two steps leaves a
    whole step; SIGINT while the potential runs raises inside it and puts
    the optimiser back as it was before the call. Either way it goes on
    with the bits of a run never interrupted."""
    def rastrigin(X):
        t = 2 * np.pi * X
        return X.shape[1] + np.sum(X * X - np.cos(t), axis=1), 2 * X + 2 * np.pi * np.sin(t)

    def make():
        return hrla.Optimizer(rastrigin, hrla.Hrla.paper(0.01), 4.0, hrla.Gaussian([3.0] * 4, 3.0),
                              chains=50, seed=4, stop=hrla.Stop().steps(10**12))

    opt = make()
    interrupted(opt.run)
    opt.step(2)
    fresh = make()
    fresh.step(opt.iteration)
    same_state(opt, fresh)


if __name__ == "__main__":
    globals()["case_" + sys.argv[1]]()
    print("ok")

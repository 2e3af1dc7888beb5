"""``hrla.minimize``: the front door, in ``scipy.optimize``'s shape."""

from __future__ import annotations

import math
import sys
import time
import warnings
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _objective
from ._hrla import (Auto, DivergedError, Hrla, Interval, Ola, Optimizer, PolishSettings, Potential, Stop, Ula,
                    auto_share, ensemble_minimize, split_budget)

#: The clock of ``maxtime`` and of the progress line's rate (seconds); a
#: test may replace it with a fake one.
_clock: Callable[[], float] = time.monotonic

#: Why a run ended, indexed by :class:`OptimizeResult`'s ``status``: the
#: kernel's ``Termination`` names (``"Steps"``: the step budget, or
#: ``maxiter``; ``"Evaluations"``: ``maxfun``; ``"Target"``; ``"Stalled"``;
#: ``"Observer"``: an observer of :meth:`Optimizer.run` or
#: :meth:`Auto.minimize`), then ``"Time"`` (``maxtime``) and
#: ``"Callback"`` (the callback asked to stop), then ``"Converged"``
#: (``"auto"``'s convergence rule).
TERMINATIONS = ("Steps", "Evaluations", "Target", "Stalled", "Observer", "Time", "Callback", "Converged")

#: The sentence of each reason :func:`minimize` itself stops a run for.
_REASONS = {
    "Steps": "the step budget is spent (maxiter, or the steps maxfun leaves before the polish)",
    "Target": "the target value is reached",
    "Stalled": "the best value stalled",
    "Time": "the time limit (maxtime) is reached",
    "Callback": "the callback asked to stop",
    "Converged": "converged (the best did not fall over the convergence window)",
}

_SAMPLERS: Dict[str, Any] = {"hrla": Hrla, "ula": Ula, "ola": Ola}
#: The arguments only the samplers use.
_SAMPLER_ONLY = ("h", "schedule", "start", "polish")

#: The default of ``maxfun``.
MAXFUN = 125_000

#: The ``context`` of a three-argument ``callback(x, f, context)``, as
#: ``scipy.optimize.dual_annealing`` passes it: where the best ``f`` was
#: last seen. ``SAMPLING`` (0, dual_annealing's "the annealing"): during
#: the run, once per step (samplers) or round (``"auto"``, each of whose
#: rounds ends its moves with quenches); ``LOCAL_SEARCH`` (1, its "the
#: local search"): after the end's L-BFGS polish, once, when that lowered
#: the best. (dual_annealing's 2 has no counterpart.)
SAMPLING = 0
LOCAL_SEARCH = 1


class OptimizeResult(Dict[str, Any]):
    """The outcome of :func:`minimize`, as ``scipy.optimize.OptimizeResult``:
    a dict whose keys are also attributes.

    - ``x``: the best point; ``fun``: ``f(x)``; ``jac``: the gradient there
      (finite differences when ``jac`` was not given);
    - ``nfev``: the calls of ``fun`` on a point, all counted (the
      finite-difference probes, the starts, the polish); ``njev``: the
      gradients computed; ``nit``: the steps (samplers) or rounds
      (``"auto"``);
    - ``success``: ``True`` only when ``fun`` is finite, some chain is still
      alive and a stopping rule other than the callback ended the run;
      with ``"auto"``, only when the run converged (its convergence rule
      or ``stall``) or reached ``target``: a run that ``maxfun``,
      ``maxiter`` or ``maxtime`` cut short did not converge;
      ``termination``: why it ended; ``status``: its index in
      :data:`TERMINATIONS`. scipy's ``status`` is 0 for success and a
      solver's own code otherwise; hrla's names only why the run ended,
      and ``success`` says whether it succeeded (for the samplers, whose
      runs have a length, a spent budget is a normal end, as ``maxiter``
      is for ``dual_annealing``):

      ======  ===============  =======  ==================================
      status  termination      success  the run ended when
      ======  ===============  =======  ==================================
      0       ``Steps``        yes      ``maxiter`` steps or rounds ran
      1       ``Evaluations``  yes      ``maxfun`` left no whole step
      2       ``Target``       yes      the best reached ``target``
      3       ``Stalled``      yes      ``stall``'s window saw no gain
      4       ``Observer``     no       an observer of the run-time
                                        objects asked to stop
      5       ``Time``         yes      ``maxtime`` seconds passed
      6       ``Callback``     no       the callback asked to stop
      7       ``Converged``    yes      ``"auto"``'s convergence rule held
      ======  ===============  =======  ==================================

      (``success`` is also ``False`` when ``fun`` is not finite or every
      chain diverged.)

    - ``all_diverged``, ``diverged_chains``, ``chains``, ``method``,
      ``seed`` (the seed the run used: the same call with ``rng=seed``
      gives the same bits);
    - ``message``: why the run ended and what it found, written last; when
      its budget ended it short of ``maxfun``, the calls used and what the
      rest was left for (less than one step of the chains, the polish's
      share it did not need, the gradient kept back for ``jac``, less than
      one gradient).
    """

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError as e:
            raise AttributeError(name) from e

    __setattr__ = dict.__setitem__
    __delattr__ = dict.__delitem__

    #: The keys printed first, in this order (scipy's order, with
    #: ``termination`` beside ``status``); the others follow as stored.
    _order_keys = ("message", "success", "status", "termination", "fun", "x", "nit", "jac", "nfev", "njev")

    def __repr__(self) -> str:
        """One field a line, keys right-aligned, as scipy's
        ``OptimizeResult`` prints (and arrays as scipy prints them)."""
        if not self:
            return type(self).__name__ + "()"

        def rank(item: Tuple[str, Any]) -> float:
            return self._order_keys.index(item[0]) if item[0] in self._order_keys else math.inf

        return _formatted(dict(sorted(self.items(), key=rank)))


def _formatted(d: Any, indent: int = 0) -> str:
    """scipy's ``_dict_formatter``: a dict one key a line, each key
    right-aligned to the longest plus one and its value's later lines
    indented under the value; a value as ``str`` with numpy's print options
    of scipy's results (floats in ten characters, arrays of more than 12
    entries cut to their first and last two)."""
    if isinstance(d, dict):
        width = max(map(len, d)) + 1
        return "\n".join(k.rjust(width) + ": " + _formatted(v, width + indent + 2).replace("\n", "\n" + " " * (width + 2))
                         for k, v in d.items())
    with np.printoptions(linewidth=76 - indent, edgeitems=2, threshold=12, formatter={"float_kind": _float10}):
        return str(d)


def _float10(x: Any) -> str:
    """A float in exactly ten characters, as scipy prints a result's."""
    if np.isnan(x):
        return "       nan"
    if np.isinf(x):
        return "       inf" if x > 0 else "      -inf"
    return np.format_float_scientific(x, precision=3, pad_left=2, unique=False)


Box = Union[None, Interval, List[Tuple[float, float]]]


def box_of(bounds: Any, dim: Optional[int] = None) -> Box:
    """``bounds`` as a box for the run-time layer: ``(lo, hi)`` in every
    coordinate (an :class:`Interval`), a sequence of ``D`` pairs
    ``(lo_i, hi_i)`` (their number fixes ``D``), or a
    ``scipy.optimize.Bounds`` (anything with ``lb`` and ``ub``; scalars
    are the same side in every coordinate)."""
    if bounds is None:
        return None
    if isinstance(bounds, Interval):
        return bounds
    if hasattr(bounds, "lb") and hasattr(bounds, "ub"):
        lb, ub = _real_array(bounds.lb, "bounds.lb"), _real_array(bounds.ub, "bounds.ub")
        if lb.size == 1 and ub.size == 1:
            # scipy keeps scalar sides as arrays of one.
            return Interval(float(lb.reshape(())), float(ub.reshape(())))
        if lb.ndim > 1 or ub.ndim > 1:
            raise ValueError(f"bounds.lb and bounds.ub must be scalars or 1-D, got shapes {lb.shape} and {ub.shape}")
        try:
            lb, ub = np.broadcast_arrays(lb, ub)
        except ValueError:
            raise ValueError(f"bounds.lb and bounds.ub differ in length: {lb.shape} and {ub.shape}") from None
        return [(float(lo), float(hi)) for lo, hi in zip(lb, ub)]
    b = _real_array(bounds, "bounds")
    if b.shape == (2,):
        return Interval(float(b[0]), float(b[1]))
    if b.ndim == 2 and b.shape[1] == 2 and b.shape[0] >= 1:
        return [(float(lo), float(hi)) for lo, hi in b]
    raise ValueError(f"bounds must be (lo, hi), a sequence of D (lo, hi) pairs or scipy.optimize.Bounds, "
                     f"got {bounds!r}")


def _real_array(v: Any, name: str) -> np.ndarray:
    b = np.asarray(v)
    if b.dtype.kind not in "fiu":
        raise TypeError(f"{name} must be real numbers (floats or ints), got {v!r} (dtype {b.dtype})")
    return b.astype(np.float64)


def _sides(box: Box, d: Optional[int]) -> Tuple[Any, Any]:
    """The box's lower and upper sides, for the finite differences."""
    if box is None:
        return -np.inf, np.inf
    if isinstance(box, Interval):
        return box.lo, box.hi
    return np.array([lo for lo, _ in box]), np.array([hi for _, hi in box])


def _count(v: Any, name: str, minimum: int = 0) -> int:
    """A count argument: an int (Python's or numpy's) or a float with a
    whole value (``maxfun=1e5``, as scipy's own defaults are written), in
    ``[minimum, 2**64)``; else an error naming it."""
    if isinstance(v, bool) or not isinstance(v, (int, np.integer, float, np.floating)):
        raise TypeError(f"{name} must be an int (or a float with a whole value, such as 1e5), got {v!r}")
    if isinstance(v, (float, np.floating)):
        if not math.isfinite(v):
            raise ValueError(f"{name} must be finite, got {float(v)!r}")
        if not float(v).is_integer():
            raise ValueError(f"{name} must be a whole number, got {float(v)!r}")
    count = int(v)
    if count < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {count}")
    if count >= 2 ** 64:
        raise ValueError(f"{name} must be < 2**64, got {count}")
    return count


def _number(v: Any, name: str) -> float:
    """A real argument that is not NaN."""
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {v!r}")
    if math.isnan(v):
        raise ValueError(f"{name} must be a number, got NaN")
    return float(v)


def seed_of(rng: Any, name: str = "rng") -> int:
    """The run's 64-bit seed from scipy's ``rng``: ``None`` (fresh entropy
    from the operating system), an int (the seed itself, as
    :class:`Optimizer`'s ``seed``), or a ``numpy.random.Generator`` (the
    seed drawn from it)."""
    if rng is None:
        entropy: Any = np.random.SeedSequence().entropy  # an int of 128 bits
        return int(entropy) % 2 ** 64
    if isinstance(rng, np.random.Generator):
        return int(rng.integers(0, 2 ** 64, dtype=np.uint64))
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool):
        return _count(rng, name)
    raise TypeError(f"{name} must be None, an int or a numpy.random.Generator, got {rng!r}")


class _Watch:
    """What only Python checks as a run goes: the time limit, the callback
    and the progress line (the kernel's own rules hold the target, stall
    and round limits). Called as the observer of :meth:`Optimizer.run` or
    :meth:`Auto.minimize` (with ``with_x=True`` where the callback needs
    the best point); returns ``True`` to stop, and keeps why in
    ``reason``."""

    def __init__(self, method: str, *, maxtime: Optional[float], callback: Optional[Callable[..., Any]],
                 disp: bool, nfev: Callable[[int], int]) -> None:
        self.method = method
        self.maxtime = maxtime
        self.callback = callback
        self.form = "x" if callback is None else _objective.callback_form(callback)
        self.seen: Optional[float] = None
        self.disp = disp
        self.nfev = nfev
        self.reason: Optional[str] = None
        self.start = _clock()
        self.shown: Optional[float] = None
        self.called_at: Optional[int] = None

    def __call__(self, iteration: int, evaluations: int, value: float, x: Optional[np.ndarray] = None) -> bool:
        now = _clock()
        if self.disp and (self.shown is None or now - self.shown >= 1.0):
            self.shown = now
            self.show(iteration, evaluations, value, now)
        if self.maxtime is not None and now - self.start >= self.maxtime:
            return self.stop("Time")
        if self.callback is not None and iteration != self.called_at:
            self.called_at = iteration
            self.seen = value
            try:
                if self.form == "intermediate_result":
                    answer = self.callback(OptimizeResult(x=x, fun=value, nfev=self.nfev(evaluations), nit=iteration))
                elif self.form == "x, f, context":
                    answer = self.callback(x, value, SAMPLING)
                elif self.form == "x, f":
                    answer = self.callback(x, value)
                else:
                    answer = self.callback(x)
            except StopIteration:
                return self.stop("Callback")
            # Any true answer stops, as scipy's callbacks do (np.True_, 1).
            if answer:
                return self.stop("Callback")
        return False

    def stop(self, reason: str) -> bool:
        self.reason = reason
        return True

    def polished(self, x: np.ndarray, value: float, termination: str) -> None:
        """``callback(x, f, LOCAL_SEARCH)`` once for the end's polish, when
        it lowered the best the callback last saw (``dual_annealing``'s
        call for a local search's minimum); its answer is moot, the run
        being over. Only the three-argument form can tell the two apart."""
        if (self.form == "x, f, context" and self.callback is not None and termination != "Callback"
                and self.seen is not None and value < self.seen):
            self.seen = value
            try:
                self.callback(np.array(x, dtype=np.float64), value, LOCAL_SEARCH)
            except StopIteration:
                pass

    def show(self, iteration: int, evaluations: int, value: float, now: float) -> None:
        nfev = self.nfev(evaluations)
        elapsed = now - self.start
        rate = f", {nfev / elapsed:.3g} evaluations/s" if elapsed > 0 else ""
        word = "round" if self.method == "auto" else "step"
        print(f"hrla {self.method}: {word} {iteration}, {nfev} evaluations, best {value:.10g}{rate}",
              file=sys.stdout, flush=True)


def minimize(
    fun: Any,
    bounds: Any = None,
    args: Sequence[Any] = (),
    *,
    jac: Any = None,
    x0: Any = None,
    method: Any = "auto",
    maxfun: Optional[float] = None,
    maxiter: Optional[float] = None,
    maxtime: Optional[float] = None,
    target: Optional[float] = None,
    stall: Optional[Tuple[int, float]] = None,
    converge: Any = None,
    rng: Any = None,
    seed: Any = None,
    callback: Optional[Callable[..., Any]] = None,
    vectorized: bool = False,
    workers: Any = 1,
    disp: bool = False,
    dim: Optional[int] = None,
    chains: Optional[int] = None,
    h: Optional[float] = None,
    schedule: Any = None,
    start: Any = None,
    polish: Optional[int] = None,
    budget: Optional[int] = None,
    steps: Optional[int] = None,
) -> OptimizeResult:
    """Minimises ``fun`` globally over a box by Langevin sampling, with
    ``scipy.optimize``'s conventions.

    The function:

    - ``fun(x, *args) -> float`` at one point ``x`` of shape ``(D,)``, as
      scipy calls it; or a built-in potential (``hrla.Rastrigin()``, ...),
      which runs in Rust. Every call of ``fun`` (and ``jac``, and the
      callback) gets an array of its own, a copy as scipy passes: writing
      into it changes nothing of the run;
    - ``jac``: ``None`` or ``"2-point"`` (forward differences, ``D``
      calls of ``fun`` per gradient), ``"3-point"`` (central differences,
      ``2 D`` calls), both with the steps of
      ``scipy.optimize.approx_derivative`` in the box's units (its
      ``max(1, |x|)`` with the side over 10.24 for the 1, so that the
      steps scale with the box) and turned inward at the box's faces so
      that no call leaves the box; ``True`` (``fun`` returns
      ``(f, g)``); or a callable ``jac(x, *args)`` returning ``g``;
    - ``vectorized=True``: ``fun`` is called once per batch with ``x`` of
      shape ``(D, S)``, a column per point, and returns ``S`` values
      (``differential_evolution``'s convention; with ``jac=True``, ``(f,
      g)`` with ``g`` of shape ``(D, S)``); the finite differences' probes
      go in the same call;
    - ``workers``: an int (a process pool of that many, ``-1`` one per
      CPU; ``fun`` must then pickle) or a map-like callable
      (``pool.map``) that evaluates a batch's points in parallel.

    The problem: ``bounds`` is ``D`` pairs ``(lo_i, hi_i)``, a
    ``scipy.optimize.Bounds`` or ``(lo, hi)`` with ``dim``; ``x0`` (shape
    ``(D,)``, inside the box) is chain 0's initial point (the other chains
    draw theirs); a point where ``fun`` is not finite raises
    :class:`HrlaError` with ``"auto"`` (the samplers mark that chain
    diverged).

    The run: ``method`` is ``"auto"`` (the default: :class:`Auto`, no
    setting to tune; ``chains`` defaults to ``Auto.chains_for``), an
    :class:`Auto` with constants of the caller's (``method=hrla.Auto(
    steps=3)``: ``"auto"`` with those), or
    ``"hrla"``, ``"ula"``, ``"ola"`` (Algorithm 1 of the paper with that
    sampler in its paper setting at step ``h`` (default 0.01), the
    ``schedule`` (default ``a = 4``), ``chains`` chains (default 10) from
    ``start`` (default: uniform in the box), then, unless the target, the
    time limit or the callback stopped the run, an L-BFGS polish of the
    best point within ``polish`` calls of ``fun``). Every method stops at
    the first of: ``maxfun`` calls of ``fun`` (default 125 000, every call
    counted), ``maxiter`` steps or rounds, the ``target`` value, ``stall =
    (window, tolerance)`` (the best has not fallen by more than
    ``tolerance`` over ``window`` steps or rounds), ``maxtime`` seconds,
    the callback, Ctrl-C (``KeyboardInterrupt``). Every method reads the
    limits alike: ``maxiter=0`` evaluates the starts only (the samplers then
    polish, as ``differential_evolution`` does); ``target=inf`` is reached
    by any finite value, so the run stops at its first look, and
    ``target=-inf`` is never reached (no target); a ``stall`` tolerance of
    ``inf`` stalls the run after its window.

    ``"auto"`` also ends by itself when it has converged, so that
    ``maxfun`` is a cap, not a target: when its best has not fallen beyond
    rounding (``1e-12`` of the spread of ``f`` at the initial points, a
    tolerance in the problem's own units) over ``Auto().converged_window``
    rounds (60: two stalls of ``Auto().stall`` rounds), or over a sixth of them while every chain's basin was the
    best's (a unimodal problem), it polishes the best and ends with
    ``termination == "Converged"``. ``converge=`` a window of rounds sets another;
    ``converge=False`` switches the rule off (the run then spends
    ``maxfun``).

    Without a gradient (``jac`` by finite differences) and with ``D <=
    ENSEMBLE_MAX_DIM`` (20), ``"auto"`` is two phases: :class:`Auto` with
    the first ``max(100, 15 D) D`` calls of ``fun`` (at least two gradients
    a chain; from ``D = 7`` on, about ``15 D`` gradients, enough for a
    quench to end), where its quenched starts lead on the bbob benchmark, then the layer's
    gradient-free ensemble with the rest: Langevin particles in their own
    whitened frame, driven by the gradient of a quadratic model fitted to
    their values (no finite differences), restarted with twice the
    particles when they agree or stall, but with as many after the first
    agreement, which the next restart may confirm, and from the third
    restart on alternating with small local restarts that spend as many
    calls, half of them around the best point so far (the crate
    ``hrla-dyn``'s ``Ensemble`` gives the method). Its generations are ``nit``'s
    iterations after Auto's rounds, each one batch of ``fun`` through
    ``workers`` or ``vectorized``; the run has converged when a large
    restart agreed on the best value at Auto's best point, two at one point,
    or three at different points (``converge=False``: never); ``target``,
    ``maxiter``, ``maxtime``, the callback and Ctrl-C end it as they end
    Auto. ``method=hrla.Auto()`` runs Auto alone.

    ``rng`` (or ``seed``) is ``None`` (fresh entropy), an int or a
    ``numpy.random.Generator``; the result's ``seed`` repeats the run.
    ``callback(intermediate_result)`` gets an :class:`OptimizeResult`
    (``x``, ``fun``: the best so far; ``nfev``, ``nit``) once per step or
    round; a callback with another parameter name gets the best point,
    by the number of its positional parameters without a default:
    ``callback(x)`` (scipy's older convention), ``callback(x, f)``, or
    ``callback(x, f, context)`` as ``dual_annealing`` calls it (and
    ``basinhopping``'s ``callback(x, f, accept)``), ``context`` saying
    where the best was seen: 0 during the run (the sampling: steps, or
    rounds of moves and quenches), 1 in one more call after the end's
    L-BFGS polish when that lowered the best (the local search; as
    ``dual_annealing``'s 0 and 1, which has a 2 with no counterpart here). It stops the run by raising ``StopIteration`` or
    returning a true value (``True``, ``np.True_``, ``1``: any answer whose
    ``bool`` is true, as scipy tests it). ``disp=True`` prints a progress line (steps or
    rounds, evaluations, best value, rate) at most once a second.

    ``budget`` and ``steps`` are the older names of ``maxfun`` and
    ``maxiter`` (deprecated). Counts (``maxfun``, ``maxiter``, ``chains``,
    ``dim``, ``polish``, ``stall``'s window) are ints, numpy integers or
    floats with a whole value (``maxfun=1e5``, as scipy writes its
    defaults); another float raises ``ValueError`` naming the argument. An argument the method does not use raises
    ``ValueError`` naming it.

    Returns an :class:`OptimizeResult`. Bad input raises ``TypeError`` or
    ``ValueError`` naming the argument; failed runs raise
    :class:`HrlaError` (with the kernel's message) or a subclass.
    """
    settings: Optional[Auto] = None
    if isinstance(method, Auto):
        settings, method = method, "auto"
    if not isinstance(method, str):
        raise TypeError(f"method must be a str (auto hrla ula ola) or an hrla.Auto, got {type(method).__name__}")
    method = method.lower()
    if method != "auto" and method not in _SAMPLERS:
        raise ValueError(f"unknown method {method!r}; expected one of: auto hrla ula ola")
    maxfun = _renamed(maxfun, budget, "maxfun", "budget")
    maxiter = _renamed(maxiter, steps, "maxiter", "steps")
    if converge is not None and method != "auto":
        raise ValueError("converge is used by method='auto' only (the samplers' runs have a length)")
    if converge is None or converge is True:
        converge = (settings or Auto()).converged_window if method == "auto" else None
    elif converge is False:
        converge = None
    else:
        converge = _count(converge, "converge", 1)
    if method == "auto":
        given = {"h": h, "schedule": schedule, "start": start, "polish": polish}
        for name in _SAMPLER_ONLY:
            if given[name] is not None:
                raise ValueError(f"{name} is not used by method='auto' (it sets the samplers "
                                 f"'hrla', 'ula' and 'ola')")
    maxfun = MAXFUN if maxfun is None else _count(maxfun, "maxfun", 1)
    maxiter = None if maxiter is None else _count(maxiter, "maxiter")
    chains = None if chains is None else _count(chains, "chains", 1)
    dim = None if dim is None else _count(dim, "dim", 1)
    polish = None if polish is None else _count(polish, "polish")
    maxtime = None if maxtime is None else _number(maxtime, "maxtime")
    if maxtime is not None and maxtime < 0:
        raise ValueError(f"maxtime must be >= 0 seconds, got {maxtime}")
    target = None if target is None else _number(target, "target")
    if target == -math.inf:
        target = None  # never reached: no target
    if stall is not None:
        try:
            window, tolerance = stall
        except (TypeError, ValueError):
            raise TypeError(f"stall must be a pair (window, tolerance), got {stall!r}") from None
        stall = (_count(window, "stall's window", 1), _number(tolerance, "stall's tolerance"))
        if stall[1] < 0:
            raise ValueError(f"stall's tolerance must be >= 0, got {stall[1]}")
    if callback is not None and not callable(callback):
        raise TypeError(f"callback must be callable, got {callback!r}")
    if rng is not None and seed is not None:
        raise TypeError("give rng or seed (its older name), not both")
    run_seed = seed_of(seed, "seed") if seed is not None else seed_of(rng, "rng")
    if not isinstance(args, tuple):
        args = (args,) if not isinstance(args, list) else tuple(args)
    box = box_of(bounds)
    if x0 is not None:
        x0 = _real_array(x0, "x0")
        if x0.ndim != 1:
            raise ValueError(f"x0 must have shape (D,), got {x0.shape}")
    d = dim
    for name, size in (("bounds", len(box) if isinstance(box, list) else None),
                       ("x0", None if x0 is None else len(x0))):
        if size is not None:
            if d is not None and d != size:
                raise ValueError(f"{name} has dimension {size} but "
                                 f"{'dim' if dim is not None else 'bounds'} has {d}")
            d = size
    lb, ub = _sides(box, d)
    if x0 is not None and (np.any(x0 < lb) or np.any(x0 > ub)):
        raise ValueError(f"x0 must lie in the box, got {x0}")

    builtin = isinstance(fun, Potential)
    mapper: Optional[_objective.Mapper] = None
    objective: Optional[_objective.Objective] = None
    try:
        if builtin:
            for name, value, default in (("args", args, ()), ("jac", jac, None), ("vectorized", vectorized, False),
                                         ("workers", workers, 1)):
                if callable(value) or value != default:
                    raise ValueError(f"{name} is not used with a built-in potential (it runs in Rust, "
                                     f"with its own gradient)")
            potential: Any = fun
            cost = 1
        elif callable(fun):
            if vectorized and (callable(workers) or workers != 1):
                raise ValueError("workers is not used with vectorized=True: fun evaluates each batch in one call")
            mapper = _objective.Mapper(workers)
            objective = _objective.Objective(fun, args, jac, bool(vectorized), mapper, lb, ub)
            potential = objective
            if objective.scheme is None:
                cost = 1
            elif d is None:
                raise ValueError("the dimension is unknown: give bounds as D pairs, x0, or dim=")
            else:
                cost = objective.cost(d)
        else:
            raise TypeError(f"fun must be callable or a built-in potential (hrla.Rastrigin(), ...), "
                            f"got {type(fun).__name__}")
        # One gradient is kept back for the result's jac, if the run did
        # not compute it at x.
        spare = 1 if objective is not None and not builtin else 0
        budget_k = maxfun // cost - spare
        if budget_k < 1:
            raise ValueError(f"maxfun={maxfun} leaves no evaluation: each gradient costs {cost} calls of fun")
        if method == "auto":
            n = chains if chains is not None else Auto.chains_for(budget_k)
            if budget_k < 2 * n:
                raise ValueError(f"maxfun={maxfun} is too small for method='auto' with {n} chains: it needs "
                                 f"{2 * n} gradients of {cost} calls of fun each"
                                 f"{' and one more for the result' if spare else ''}, "
                                 f"maxfun >= {(2 * n + spare) * cost}")

        def nfev(evaluations: int) -> int:
            return objective.nfev if objective is not None else evaluations

        spend = _Budget(maxfun, cost, spare)
        if method == "auto":
            return _auto(potential, box, budget_k, run_seed, chains, dim, d, x0, objective, builtin, fun, nfev, spend,
                         settings=settings, target=target, stall=stall, converge=converge, maxiter=maxiter,
                         maxtime=maxtime, callback=callback, disp=disp)
        return _sampler(method, potential, box, budget_k, run_seed, chains, dim, objective, builtin, fun, nfev,
                        spend, h=h, schedule=schedule, start=start, polish=polish, x0=x0, target=target,
                        stall=stall, maxiter=maxiter, maxtime=maxtime, callback=callback, disp=disp)
    finally:
        if mapper is not None:
            mapper.close()


class _Budget(NamedTuple):
    """How ``maxfun`` is spent: the kernel's budget is ``maxfun // cost -
    spare`` gradients of ``cost`` calls of ``fun`` each, ``spare`` of them
    kept back for the result's ``jac``."""

    maxfun: int
    cost: int
    spare: int

    def note(self, nfev: int, njev: int, evaluations: int, unspent: List[Tuple[int, str]]) -> str:
        """What a run that ended for its budget left of ``maxfun``, and
        why: the calls used, then each share left over (``unspent``: the
        kernel's own, in gradients, each with its reason; then the spare
        gradient not needed and the calls fewer than one gradient), when
        they add up to what is left; ``""`` when nothing is left."""
        left = self.maxfun - nfev
        if left <= 0:
            return ""
        shares = [(k * self.cost, why) for k, why in unspent]
        # The gradient kept back for jac and not needed: the run had it.
        shares.append((self.cost * (self.spare - (njev - evaluations)),
                       "kept back for the result's jac, which the run had computed at x"))
        shares.append((self.maxfun % self.cost, f"fewer than one gradient ({self.cost} calls of fun)"))
        shares = [(calls, why) for calls, why in shares if calls > 0]
        text = f"; {nfev:,} of maxfun={self.maxfun:,} calls of fun used"
        if sum(calls for calls, _ in shares) == left:
            text += f"; the {left:,} left: " + "; ".join(f"{calls:,} {why}" for calls, why in shares)
        return text


def _renamed(new: Any, old: Any, name: str, old_name: str) -> Any:
    """``new``, or ``old`` (with a deprecation warning) where only that is given."""
    if old is None:
        return new
    if new is not None:
        raise TypeError(f"give {name} or its older name {old_name}, not both")
    warnings.warn(f"{old_name}= is deprecated: it is {name}= (the same count)", DeprecationWarning, stacklevel=3)
    return old


def _auto(potential: Any, box: Box, budget: int, seed: int, chains: Optional[int], dim: Optional[int],
          size: Optional[int],
          x0: Optional[np.ndarray], objective: Optional[_objective.Objective], builtin: bool, fun: Any,
          nfev: Callable[[int], int], spend: _Budget, *, settings: Optional[Auto], target: Optional[float],
          stall: Optional[Tuple[int, float]], converge: Optional[int], maxiter: Optional[int],
          maxtime: Optional[float],
          callback: Optional[Callable[..., Any]], disp: bool) -> OptimizeResult:
    if box is None:
        raise ValueError('method="auto" needs bounds: D (lo, hi) pairs, scipy.optimize.Bounds, or (lo, hi) with dim=')

    w = _Watch("auto", maxtime=maxtime, callback=callback, disp=disp, nfev=nfev)
    observed = maxtime is not None or callback is not None or disp
    # Without a gradient, Auto runs first with its share and the ensemble,
    # which needs values only, with the rest (the layer's rule,
    # hrla_dyn::budget::auto_share). hrla.Auto(...) as the method runs
    # Auto alone.
    # The share is Auto's soft budget: the quench of its best start may
    # finish past it.
    soft = None
    if settings is None and objective is not None and objective.scheme is not None and size is not None:
        soft = auto_share(budget, size, spend.cost, spend.spare, chains)
    ensemble = soft is not None
    whole = budget
    # The limits as the run's own rules, which take only finite numbers:
    # the largest float stands for inf (target=inf: any finite value
    # reaches it; stall's tolerance inf: the run stalls after its window).
    s = (settings or Auto()).minimize(potential, box, budget, seed, chains=chains, dim=dim,
                        x0=None if x0 is None else [float(v) for v in x0], observer=w if observed else None,
                        with_x=callback is not None,
                        target=None if target is None else min(target, sys.float_info.max),
                        stall=None if stall is None else (stall[0], min(stall[1], sys.float_info.max)),
                        rounds=maxiter, converge=converge, soft_budget=soft)
    termination = w.reason if s.termination == "Observer" and w.reason else s.termination
    x, value, nit = np.asarray(s.x), s.value, s.rounds
    left = spend.maxfun - nfev(s.evaluations) - spend.cost * spend.spare
    # The caller's rules that ended Auto end the run: the ensemble takes
    # over only from Auto's own ends (its share spent, or converged).
    phases = None
    planned = budget if soft is None else soft
    if (ensemble and termination in ("Evaluations", "Converged") and left > 0 and planned < whole
            and (maxiter is None or nit < maxiter)):
        assert objective is not None and size is not None
        x, value, nit, termination = _ensemble(objective, box, size, left, seed, w, x, value, nit, target=target,
                                               stall=stall, maxiter=maxiter, converge=converge is not None,
                                               with_x=callback is not None)
        phases = (s.rounds, nit - s.rounds)
    w.polished(x, value, termination)
    jac = _gradient(x, objective, builtin, fun)
    if disp:
        w.show(nit, s.evaluations, value, _clock())
    njev = objective.njev if objective is not None else s.evaluations
    note = ""
    if termination == "Evaluations" and planned == whole:
        # Auto's rounds stop when what is left would not fit one more, and
        # its final polish gets the rest.
        note = spend.note(nfev(s.evaluations), njev, s.evaluations,
                          [(budget - s.evaluations, "not needed by the final polish (it converged first)")])
    return _result(
        x=x, fun=value, jac=jac, nfev=nfev(s.evaluations), budget_note=note,
        njev=njev, nit=nit, termination=termination,
        diverged_chains=s.diverged_chains, chains=s.chains, method="auto", seed=seed, step=s.step,
        inverse_temperature=s.inverse_temperature,
        # Auto's chains always hold a feasible basin: an infeasible last
        # proposal is rejected, not a failure.
        holds_basins=True, kernel_message=s.message, ensemble=phases,
    )


#: The ensemble's ends as ``hrla.minimize`` names them.
_ENSEMBLE_ENDS = {"Budget": "Evaluations", "Converged": "Converged", "Target": "Target", "Stalled": "Stalled",
                  "Iterations": "Steps"}


def _ensemble(objective: _objective.Objective, box: Box, dim: int, calls: int, seed: int, w: _Watch, x: np.ndarray,
              value: float, nit: int, *, target: Optional[float], stall: Optional[Tuple[int, float]],
              maxiter: Optional[int], converge: bool, with_x: bool) -> Tuple[np.ndarray, float, int, str]:
    """The layer's gradient-free ensemble on ``fun``'s values with
    ``calls`` calls, after Auto found ``value`` at ``x`` in ``nit`` rounds:
    the better point, the iterations (Auto's rounds, then the ensemble's
    generations) and why the run ended. The watch sees the best of both;
    the layer's rules end it as they end Auto (``target``, ``stall`` and
    ``maxiter`` over the run's iterations, a stall window reaching back
    into Auto's rounds measuring the fall from Auto's best); ``converge``
    switches the ensemble's own rule (a large restart agrees at Auto's
    ``x`` or at another's point, or three agree anywhere) on or off."""
    lb, ub = (np.broadcast_to(np.asarray(side, dtype=np.float64), dim) for side in _sides(box, dim))

    def watch(generation: int, evaluations: int, best: float, at: Optional[np.ndarray] = None) -> bool:
        lower = best < value
        return w(nit + generation, evaluations, min(best, value), (at if lower else x) if with_x else None)

    try:
        ex, ev, _, generations, _, _, end = ensemble_minimize(
            objective.values, lb.tolist(), ub.tolist(), calls, seed, observer=watch, with_x=with_x,
            target=target, stall=stall, iterations=maxiter, elapsed=nit, known=value, known_at=x.tolist(),
            converge=converge)
    except DivergedError:
        # No finite value in the ensemble's share: Auto's answer stands.
        return x, value, nit, "Evaluations"
    termination = _ENSEMBLE_ENDS.get(end) or w.reason or "Observer"
    if ev < value:
        x, value = np.asarray(ex), ev
    return x, value, nit + generations, termination


def _sampler(method: str, potential: Any, box: Box, budget: int, seed: int, chains: Optional[int],
             dim: Optional[int], objective: Optional[_objective.Objective], builtin: bool, fun: Any,
             nfev: Callable[[int], int], spend: _Budget, *, h: Optional[float], schedule: Any, start: Any,
             polish: Optional[int], x0: Optional[np.ndarray], target: Optional[float],
             stall: Optional[Tuple[int, float]], maxiter: Optional[int], maxtime: Optional[float],
             callback: Optional[Callable[..., Any]], disp: bool) -> OptimizeResult:
    if start is None:
        if box is None:
            raise ValueError("give bounds or a start (hrla.Gaussian, hrla.Point, hrla.Interval)")
        start = box
    n = 10 if chains is None else chains
    cost = spend.cost
    # The sampling leaves the polish its share of the budget (the layer's
    # rule, which every front end shares).
    split = split_budget(budget, n, None if polish is None else polish // cost, x0 is not None)
    if split is None:
        asked = min(1000, budget // 4) if polish is None else polish // cost
        raise ValueError(f"maxfun leaves no step to {n} chains before a polish of {asked} gradients "
                         f"({cost} calls of fun each): raise maxfun, or lower polish or chains")
    sampling, polish_k = split
    stop = Stop().evaluations(budget)
    steps = maxiter
    if sampling is not None:
        steps = sampling if steps is None else min(steps, sampling)
    # The limits as the kernel's rules, which take only finite numbers and
    # a step budget of one or more; every method reads them the same way
    # (maxiter=0: the starts only; target=inf: any finite value reaches
    # it, so the run stops at its first look; stall's tolerance inf: the
    # run stalls after its window), so the largest float stands for inf,
    # and no step budget for maxiter=0, whose run is not started.
    if steps:
        stop = stop.steps(steps)
    if target is not None:
        stop = stop.target(min(target, sys.float_info.max))
    if stall is not None:
        stop = stop.stall(stall[0], min(stall[1], sys.float_info.max))
    opt = Optimizer(potential, _SAMPLERS[method].paper(0.01 if h is None else h),
                    4.0 if schedule is None else schedule, start, chains=n, seed=seed, stop=stop, domain=box, dim=dim)
    if x0 is not None:
        opt.restart(0, [float(v) for v in x0])

    w = _Watch(method, maxtime=maxtime, callback=callback, disp=disp, nfev=nfev)
    observed = maxtime is not None or callback is not None or disp
    report: Any = None
    termination = "Steps"
    if steps != 0:
        report = opt.run(w if observed else None, with_x=callback is not None)
        termination = report.termination
    if termination == "Observer" and w.reason:
        # A kernel rule that holds too comes first.
        termination = opt.termination() or w.reason
    # A run stopped by its target, time limit or callback stops there: the
    # polish would spend evaluations the user asked not to spend.
    sampled = opt.evaluations
    polished = polish_k > 0 and termination not in ("Target", "Time", "Callback")
    if polished:
        opt.polish(opt.best_chain, PolishSettings(polish_k))
        # The report of the polished state: its rule still holds (the
        # polish only adds evaluations and lowers the best), unless a
        # target is now reached, which comes first.
        report = opt.report() or report
        if report is not None and report.termination != "Observer":
            termination = report.termination
    x, value, _ = opt.best
    w.polished(x, value, termination)
    jac = _gradient(x, objective, builtin, fun)
    if disp:
        w.show(opt.iteration, opt.evaluations, value, _clock())
    njev = objective.njev if objective is not None else opt.evaluations
    note = ""
    # The step budget maxfun leaves, or maxfun itself, ended the run.
    if termination == "Evaluations" or (termination == "Steps" and steps != maxiter):
        polish_left = polish_k - (opt.evaluations - sampled) if polished else 0
        k = opt.diverged_chains
        left_by_steps = (f"fewer than one step of its {n} chains ({n * cost:,} calls)" if not k
                         else f"left by the steps of its {n} chains, {k} of which diverged")
        note = spend.note(nfev(opt.evaluations), njev, opt.evaluations, [
            (budget - opt.evaluations - polish_left, left_by_steps),
            (polish_left, f"of the polish's share of {polish_k * cost:,} calls, which converged after "
                          f"{(polish_k - polish_left) * cost:,}"),
        ])
    return _result(
        x=x, fun=value, jac=jac, nfev=nfev(opt.evaluations), budget_note=note,
        njev=njev, nit=opt.iteration,
        termination=termination, diverged_chains=opt.diverged_chains, chains=len(opt), method=method,
        seed=seed, kernel_message="" if report is None else report.message,
    )


def _gradient(x: np.ndarray, objective: Optional[_objective.Objective], builtin: bool, fun: Any) -> np.ndarray:
    """The gradient at the result's ``x``: the one computed there in the
    run, else computed now (one gradient, counted)."""
    if builtin:
        return np.asarray(fun.value_and_gradient(np.asarray(x, dtype=np.float64)[None, :])[1][0])
    assert objective is not None
    if objective.best is not None and np.array_equal(objective.best[0], x):
        return objective.best[2].copy()
    _, g = objective(np.asarray(x, dtype=np.float64)[None, :])
    return np.asarray(g[0])


def _message(kernel: str, termination: str, r: OptimizeResult, budget_note: str,
             ensemble: Optional[Tuple[int, int]] = None) -> str:
    """Why the run ended and what it found, in the user's units: calls of
    ``fun`` (the kernel counts gradients, each of which may be several
    calls), and ``f`` to its last digit; for a run its budget ended, what
    it left of ``maxfun`` and why (``budget_note``)."""
    reason = _REASONS.get(termination) or kernel.split(": ", 1)[0]
    unit = "rounds" if r["method"] == "auto" else "steps"
    spent = f"{r['nit']} {unit}"
    if ensemble is not None:
        # Auto's rounds (with their gradients), then the ensemble's
        # generations, which need none.
        rounds, generations = ensemble
        spent = f"{rounds} rounds, then {generations} generations of the ensemble"
        if termination == "Converged":
            reason = "converged (restarts of the ensemble agreed on the best value)"
    text = (f"{reason}: best f = {float(r['fun'])!r} after {r['nfev']} calls of fun "
            f"({r['njev']} gradients) in {spent}")
    k, n = r["diverged_chains"], r["chains"]
    if r["method"] == "auto" and r["nit"] == 0 and termination in ("Evaluations", "Time"):
        text += ("; the run ended before its first round of sampling (the starts' quenches took the budget): "
                 "raise maxfun, or give jac")
    if k and r["method"] == "auto":
        text += f"; the last proposal of {k} of {n} chains met a point where f is not finite (rejected)"
    elif k:
        text += f"; {k} of {n} chains diverged"
    return text + budget_note


def _result(*, fun: float, termination: str, diverged_chains: int, chains: int, kernel_message: str,
            holds_basins: bool = False, budget_note: str = "", ensemble: Optional[Tuple[int, int]] = None,
            **rest: Any) -> OptimizeResult:
    """An :class:`OptimizeResult` whose ``success`` and ``status`` follow
    from the termination and the value (and, for the samplers, from whether
    any chain is still alive); ``message`` last."""
    alive = holds_basins or diverged_chains < chains
    r = OptimizeResult(fun=fun, **rest)
    ended = (termination in ("Target", "Stalled", "Converged") if rest.get("method") == "auto"
             else termination not in ("Observer", "Callback"))
    r.update(
        success=ended and alive and bool(np.isfinite(fun)),
        status=TERMINATIONS.index(termination), termination=termination,
        all_diverged=diverged_chains == chains, diverged_chains=diverged_chains, chains=chains,
    )
    r["message"] = _message(kernel_message, termination, r, budget_note, ensemble)
    return r

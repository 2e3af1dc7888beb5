"""Global optimisation by high-resolution Langevin sampling (HRLA).

To minimise a smooth nonconvex ``U: R^D -> R``, run ``N`` independent chains
that sample the Gibbs law ``exp(-a U)`` and keep the best point visited
(Algorithm 1 of Cortild, Delplancke, Oudjane and Peypouquet, *Global
Optimization Algorithm through High-Resolution Sampling*, TMLR 2025). The
sampler, HRLA, discretises the high-resolution Langevin dynamics::

    dX = (-beta ∇U(X) + Y) dt + sqrt(2 beta / a) dB^x
    dY = (-(a/b) ∇U(X) - alpha Y) dt + sqrt(2 alpha / b) dB^y

whose invariant law is ``exp(-a U(x) - b |y|^2 / 2)``. Over each step of
length ``h`` the gradient ``g`` is frozen and the linear SDE left is solved
exactly: every coordinate moves to a Gaussian with, for ``u = alpha h``,
``e = exp(-u)``, ``phi1 = (1 - e)/u``, ``phi2 = (e - 1 + u)/u^2``,
``gamma = a/b``, ``sx2 = beta/a``, ``sy2 = alpha/b``::

    mean_x = x + h phi1 y - (beta h + gamma h^2 phi2) g
    mean_y = e y - gamma h phi1 g
    Sxx = (sy2/alpha^3)(2u - e^2 + 4e - 3) + 2 sx2 h
    Syy = sy2 (1 - e^2)/alpha,   Sxy = sy2 (1 - e)^2/alpha^2

Every number is computed by the Rust kernel ``hrla`` (this package binds it
with PyO3): the same names as its Rust API and, for a seed, the same bits.
Each chain ``c`` draws from its own ``Xoshiro256PlusPlus`` seeded with
``chain_seed(seed, c)``. Floats are ``float64``. Every method of
``minimize``, ``Optimizer`` and the built-ins' ``global_minimum`` run any
dimension ``D >= 1``.

Two kinds of potential:

- the kernel's built-ins (``Rastrigin()``, ``Quadratic(k, m)``,
  ``DoubleWell()``, ``StyblinskiTang()``, ``Levy()``, ``Ackley()``), run in
  Rust with the GIL released;
- a Python function ``fun(X) -> (U, G)`` on a batch: ``X`` of shape
  ``(N, D)``, ``U`` of shape ``(N,)`` and ``G = ∇U(X)`` of shape ``(N, D)``,
  called once per step for all live chains (and with one row at a time by
  the polish, quenches, restarts and ``Auto``). ``U`` and ``G`` must be
  real numbers (a numpy float or integer array, or sequences of Python
  floats and ints): bool, complex, string and object arrays raise
  ``TypeError``. Where ``U`` is NaN or ``+inf`` is infeasible: a start
  there is drawn again; a chain that steps there diverges.

Errors form one hierarchy under :class:`HrlaError` (a ``ValueError``):
``DivergedError``, ``UnboundedBelowError``,
``BusyError`` and ``InternalError`` (both also ``RuntimeError``). Storage
that cannot be allocated raises ``MemoryError``; Ctrl-C stops a run after
a whole step with ``KeyboardInterrupt``, and the run can go on.

Entry points: :func:`minimize` (scipy.optimize-like, returns an
:class:`OptimizeResult`), :class:`Optimizer` (step by step, chains as numpy
views), :class:`Builder` (the Rust builder's chain of settings), and
:class:`Auto` (the default solver).
"""

from __future__ import annotations

from typing import Any, Callable, List, Optional, Tuple, Union

import numpy as np

from ._hrla import (
    BUILTINS,
    Ackley,
    Auto,
    BusyError,
    Constant,
    DivergedError,
    DoubleWell,
    Gaussian,
    Geometric,
    HrlaError,
    Hrla,
    InternalError,
    Interval,
    Levy,
    Linear,
    Ola,
    Optimizer,
    Point,
    Polished,
    PolishSettings,
    Potential,
    Quadratic,
    Rastrigin,
    Report,
    Solution,
    Stop,
    StyblinskiTang,
    Ula,
    UnboundedBelowError,
)

__all__ = [
    "BUILTINS", "TERMINATIONS", "Ackley", "Auto", "Builder", "BusyError", "Constant",
    "DivergedError", "DoubleWell", "Gaussian", "Geometric", "Hrla",
    "HrlaError", "InternalError", "Interval", "Levy", "Linear", "Ola", "OptimizeResult",
    "Optimizer", "Point", "Polished", "PolishSettings", "Potential", "Quadratic", "Rastrigin",
    "Report", "Solution", "Stop", "StyblinskiTang", "Ula", "UnboundedBelowError", "minimize",
]

#: Why a run ended, indexed by :class:`OptimizeResult`'s ``status``: the
#: kernel's ``Termination`` names.
TERMINATIONS = ("Steps", "Evaluations", "Target", "Stalled", "Observer")

Fun = Union[Potential, Callable[[np.ndarray], Tuple[Any, Any]]]


class OptimizeResult(dict):
    """The outcome of :func:`minimize`, as ``scipy.optimize.OptimizeResult``:
    a dict whose keys are also attributes.

    ``x`` the best point, ``fun`` ``U(x)``, ``nfev`` the evaluations of
    ``U`` (all counted: initial points, steps, polish), ``njev`` the same
    (every evaluation computes ``U`` and ``∇U`` together), ``nit`` the
    steps (``"auto"``: rounds), ``success``, ``termination`` (why it ended:
    the kernel's ``Termination`` name, ``"Steps"``, ``"Evaluations"``,
    ``"Target"`` or ``"Stalled"``), ``status`` (its index in
    :data:`TERMINATIONS`), ``all_diverged`` (whether every chain had
    diverged at the end: ``x`` is then the last feasible best found
    before), ``diverged_chains``, ``chains``, ``message`` (the kernel's
    report of the final state, after the polish), ``method``, ``seed``.
    ``success`` is ``True`` only when ``fun`` is finite, some chain is
    still alive and a stopping rule ended the run.
    """

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError as e:
            raise AttributeError(name) from e

    __setattr__ = dict.__setitem__  # type: ignore[assignment]
    __delattr__ = dict.__delitem__  # type: ignore[assignment]

    def __repr__(self) -> str:
        keys = ("fun", "x", "nfev", "nit", "success", "status", "termination", "message")
        return "OptimizeResult(" + ", ".join(f"{k}={self[k]!r}" for k in keys if k in self) + ")"


def _box(bounds: Any) -> Union[None, Interval, List[Tuple[float, float]]]:
    """``bounds`` as a box: ``(lo, hi)`` in every coordinate, or a sequence
    of ``D`` pairs ``(lo_i, hi_i)`` as ``scipy.optimize.dual_annealing``
    takes (their number fixes ``D``; the run-time layer checks them)."""
    if bounds is None:
        return None
    if isinstance(bounds, Interval):
        return bounds
    b = np.asarray(bounds)
    if b.dtype.kind not in "fiu":
        raise TypeError(f"bounds must be real numbers (floats or ints), got {bounds!r} (dtype {b.dtype})")
    b = b.astype(np.float64)
    if b.shape == (2,):
        return Interval(float(b[0]), float(b[1]))
    if b.ndim == 2 and b.shape[1] == 2 and b.shape[0] >= 1:
        return [(float(lo), float(hi)) for lo, hi in b]
    raise ValueError(f"bounds must be (lo, hi) or a sequence of D (lo, hi) pairs, got {bounds!r}")


_SAMPLERS = {"hrla": Hrla, "ula": Ula, "ola": Ola}


def minimize(
    fun: Fun,
    bounds: Any = None,
    *,
    dim: Optional[int] = None,
    method: str = "auto",
    budget: int = 125_000,
    seed: int = 0,
    chains: Optional[int] = None,
    h: float = 0.01,
    schedule: Any = 4.0,
    start: Any = None,
    steps: Optional[int] = None,
    target: Optional[float] = None,
    stall: Optional[Tuple[int, float]] = None,
    polish: int = 1000,
) -> OptimizeResult:
    """Minimises ``fun`` globally by Langevin sampling.

    ``fun`` is a built-in potential (``hrla.Rastrigin()``, ...) or a Python
    function ``fun(X) -> (U, G)`` evaluating ``U`` and ``∇U`` on the rows of
    ``X`` (shape ``(N, D)``; ``U`` of shape ``(N,)``, ``G`` of shape
    ``(N, D)``). ``bounds`` is ``(lo, hi)`` (then give ``dim``) or ``D``
    pairs ``(lo_i, hi_i)``, each coordinate with its own sides; the chains
    stay in the box by reflection.

    ``method="auto"`` (the default; needs ``bounds``) is the kernel's
    :class:`Auto` solver: no setting to tune, ``budget`` evaluations in
    all, ``chains`` defaulting to ``Auto.chains_for(budget)``; it calls a
    Python ``fun`` with one row at a time.

    ``method="hrla"``, ``"ula"`` or ``"ola"`` runs Algorithm 1 of the paper
    with that sampler in its paper setting at step ``h``, the schedule
    ``schedule`` (a float ``a``, or ``Linear``/``Geometric`` annealing),
    ``chains`` chains (default 10) from ``start`` (default: uniform in the
    box), until ``budget`` evaluations, ``steps`` steps, the ``target``
    value or the ``stall = (window, tolerance)`` rule; then an L-BFGS
    polish of the best point with at most ``polish`` evaluations (0: none),
    kept out of the sampling's share of the budget. A Python ``fun`` is called once per step for all
    chains.

    Returns an :class:`OptimizeResult`. Bad input and failed runs raise
    :class:`HrlaError` (with the kernel's message) or a subclass.
    """
    if not isinstance(method, str):
        raise TypeError(f"method must be a str (auto hrla ula ola), got {type(method).__name__}")
    box = _box(bounds)
    method = method.lower()
    if polish < 0:
        raise ValueError(f"polish must be >= 0 evaluations, got {polish}")
    if method == "auto":
        if box is None:
            raise ValueError('method="auto" needs bounds: (lo, hi) with dim=, or D (lo, hi) pairs')
        s = Auto().minimize(fun, box, budget, seed, chains=chains, dim=dim)
        return _result(
            x=np.asarray(s.x), fun=s.value, nfev=s.evaluations, nit=s.rounds, termination=s.termination,
            diverged_chains=s.diverged_chains, chains=s.chains, message=s.message,
            method="auto", seed=seed, step=s.step, inverse_temperature=s.inverse_temperature,
            # Auto's chains always hold a feasible basin: an infeasible
            # last proposal is rejected, not a failure.
            holds_basins=True,
        )
    if method not in _SAMPLERS:
        raise ValueError(f"unknown method {method!r}; expected one of: auto hrla ula ola")
    if start is None:
        if box is None:
            raise ValueError("give bounds or a start (hrla.Gaussian, hrla.Point, hrla.Interval)")
        start = box
    n = 10 if chains is None else chains
    stop = Stop().evaluations(budget)
    if polish > 0:
        # The sampling leaves `polish` evaluations of the budget to the polish.
        sampling = (budget - polish - n) // max(n, 1)
        if sampling < 1:
            raise ValueError(f"a budget of {budget} leaves no step to {n} chains before a polish of {polish}")
        steps = sampling if steps is None else min(steps, sampling)
    if steps is not None:
        stop = stop.steps(steps)
    if target is not None:
        stop = stop.target(target)
    if stall is not None:
        stop = stop.stall(*stall)
    opt = Optimizer(fun, _SAMPLERS[method].paper(h), schedule, start,
                    chains=n, seed=seed, stop=stop,
                    domain=box, dim=dim)
    report = opt.run()
    if polish > 0:
        opt.polish(opt.best_chain, PolishSettings(polish))
        # The report of the polished state: its rule still holds (the
        # polish only adds evaluations and lowers the best), unless a
        # target is now reached, which comes first.
        report = opt.report() or report
    x, value, _ = opt.best
    return _result(
        x=x, fun=value, nfev=opt.evaluations, nit=report.iterations, termination=report.termination,
        diverged_chains=report.diverged_chains, chains=report.chains, message=report.message,
        method=method, seed=seed,
    )


def _result(*, fun: float, nfev: int, termination: str, diverged_chains: int, chains: int,
            holds_basins: bool = False, **rest: Any) -> OptimizeResult:
    """An :class:`OptimizeResult` whose ``success`` and ``status`` follow
    from the termination and the value (and, for the samplers, from whether
    any chain is still alive)."""
    alive = holds_basins or diverged_chains < chains
    return OptimizeResult(
        fun=fun, nfev=nfev, njev=nfev,
        success=termination != "Observer" and alive and bool(np.isfinite(fun)),
        status=TERMINATIONS.index(termination), termination=termination,
        all_diverged=diverged_chains == chains, diverged_chains=diverged_chains, chains=chains,
        **rest,
    )


class Builder:
    """The settings of a run, chained as in Rust's ``hrla::Builder``::

        opt = (Builder(Rastrigin(), Hrla.paper(0.01), 4.0, Gaussian([3.0] * 10, 10 ** 0.5))
               .seed(1).stop(Stop().steps(14_000)).build(chains=10))

    ``build`` makes the :class:`Optimizer` (``dim`` only when neither the
    potential nor the start fixes it).
    """

    def __init__(self, potential: Fun, sampler: Any, schedule: Any, start: Any) -> None:
        self._args = (potential, sampler, schedule, start)
        self._kw: dict = {}

    def _with(self, **kw: Any) -> "Builder":
        b = Builder(*self._args)
        b._kw = {**self._kw, **kw}
        return b

    def domain(self, domain: Any) -> "Builder":
        """Confines the chains to a box by reflection: an :class:`Interval`
        or ``D`` pairs ``(lo_i, hi_i)``."""
        return self._with(domain=domain)

    def seed(self, seed: int) -> "Builder":
        """The run's seed (chain ``c`` uses ``chain_seed(seed, c)``)."""
        return self._with(seed=seed)

    def stride(self, stride: int) -> "Builder":
        """Records the running best at iterates that are multiples of ``stride``."""
        return self._with(stride=stride)

    def stop(self, stop: Stop) -> "Builder":
        """The stopping rules."""
        return self._with(stop=stop)

    def build(self, chains: int = 10, dim: Optional[int] = None) -> Optimizer:
        """Draws the initial points of ``chains`` chains and checks everything."""
        return Optimizer(*self._args, chains=chains, dim=dim, **self._kw)

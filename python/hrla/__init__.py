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

:func:`minimize` takes a function as ``scipy.optimize`` does:
``fun(x, *args) -> float`` on one point (or, ``vectorized=True``, on the
columns of ``x (D, S)``), its gradient from finite differences (scipy's
``"2-point"`` or ``"3-point"`` steps, kept inside the box), ``jac=True`` or
a ``jac`` callable, evaluated through ``workers`` where given; it turns
that into the batch below. The run-time objects take two kinds of
potential:

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
that cannot be allocated raises ``MemoryError``. Ctrl-C raises
``KeyboardInterrupt`` at the next call of a Python function, or between
two steps of a built-in's run; a Python function is never called again
after it raised. An :class:`Optimizer` interrupted between two steps goes
on with the bits of a run never interrupted; one whose Python potential
raised in the middle of a call is put back as it was before that call,
and goes on with the same bits too.

Entry points: :func:`minimize` (scipy.optimize's conventions, returns an
:class:`OptimizeResult`), :class:`Optimizer` (step by step, chains as numpy
views), :class:`Builder` (the Rust builder's chain of settings), and
:class:`Auto` (the default solver).
"""

from __future__ import annotations

from typing import Any, Callable, Dict, Optional, Tuple, Union

import numpy as np

from ._hrla import (
    __version__,
    BUILTINS,
    ENSEMBLE_MAX_DIM,
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
from ._minimize import TERMINATIONS, OptimizeResult, minimize

__all__ = [
    "__version__", "BUILTINS", "ENSEMBLE_MAX_DIM", "TERMINATIONS", "Ackley", "Auto", "Builder", "BusyError", "Constant",
    "DivergedError", "DoubleWell", "Gaussian", "Geometric", "Hrla",
    "HrlaError", "InternalError", "Interval", "Levy", "Linear", "Ola", "OptimizeResult",
    "Optimizer", "Point", "Polished", "PolishSettings", "Potential", "Quadratic", "Rastrigin",
    "Report", "Solution", "Stop", "StyblinskiTang", "Ula", "UnboundedBelowError", "minimize",
]

Fun = Union[Potential, Callable[[np.ndarray], Tuple[Any, Any]]]


class Builder:
    """The settings of a run, chained as in Rust's ``hrla::Builder``::

        opt = (Builder(Rastrigin(), Hrla.paper(0.01), 4.0, Gaussian([3.0] * 10, 10 ** 0.5))
               .seed(1).stop(Stop().steps(14_000)).build(chains=10))

    ``build`` makes the :class:`Optimizer` (``dim`` only when neither the
    potential nor the start fixes it).
    """

    def __init__(self, potential: Fun, sampler: Any, schedule: Any, start: Any) -> None:
        self._args = (potential, sampler, schedule, start)
        self._kw: Dict[str, Any] = {}

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

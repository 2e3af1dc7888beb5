"""Type stubs of the extension module ``hrla._hrla`` (see ``hrla/__init__.py``)."""

from typing import Callable, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
BatchedFunction = Callable[[F64], Tuple[npt.ArrayLike, npt.ArrayLike]]
#: ``observer(iteration, evaluations, best_value)``; a true answer ends the run.
Observer = Callable[[int, int, float], Optional[bool]]
#: ``observer(iteration, evaluations, best_value, best_x)`` (``with_x=True``).
ObserverX = Callable[[int, int, float, F64], Optional[bool]]

__version__: str

#: The built-in potentials' class names, in the run-time layer's order.
BUILTINS: List[str]

class HrlaError(ValueError):
    """The kernel refused its input or the run failed; the message is the kernel's."""
class DivergedError(HrlaError):
    """Every chain diverged (non-finite position, potential or gradient)."""
class UnboundedBelowError(HrlaError):
    """The potential fell below -sqrt(MAX): it looks unbounded below."""
class BusyError(HrlaError, RuntimeError):
    """The optimiser is running (a call from its potential or another thread); nothing was done."""
class InternalError(HrlaError, RuntimeError):
    """A bug in hrla (a caught panic); the optimiser it interrupted refuses later calls."""

class Hrla:
    """The exact step of ``dX = (-beta ∇U + Y) dt + sqrt(2 beta/a) dB``,
    ``dY = (-(a/b) ∇U - alpha Y) dt + sqrt(2 alpha/b) dB'`` with ∇U frozen."""
    def __init__(self, h: float, *, b: float = 10.0, alpha: float = 1.0, beta: float = 1.0) -> None: ...
    @staticmethod
    def paper(h: float) -> Hrla: ...

class Ula:
    """HRLA with ``beta = 0``: ``dX = Y dt``, ``dY = (-(a/b) ∇U - alpha Y) dt + sqrt(2 alpha/b) dB``."""
    def __init__(self, h: float, *, b: float = 10.0, alpha: float = 1.0) -> None: ...
    @staticmethod
    def paper(h: float) -> Ula: ...

class Ola:
    """``x' = x - alpha h ∇U(x) + sqrt(2 alpha h / a) xi``, ``xi ~ N(0, I)``."""
    def __init__(self, h: float, *, alpha: float = 1.0) -> None: ...
    @staticmethod
    def paper(h: float) -> Ola: ...

Sampler = Union[Hrla, Ula, Ola]

class Constant:
    """``a_k = a``."""
    def __init__(self, a: float) -> None: ...

class Linear:
    """``a_k = a_low + (a_high - a_low) k / K`` for ``k < K``, then ``a_high``."""
    def __init__(self, a_low: float, a_high: float, steps: int) -> None: ...

class Geometric:
    """``a_k = a_low (a_high / a_low)^(k / K)`` for ``k < K``, then ``a_high``."""
    def __init__(self, a_low: float, a_high: float, steps: int) -> None: ...

ScheduleLike = Union[float, Constant, Linear, Geometric]

class Interval:
    """The box ``[lo, hi]^D``: a domain (reflection) and a start (uniform)."""
    def __init__(self, lo: float, hi: float) -> None: ...
    @property
    def lo(self) -> float: ...
    @property
    def hi(self) -> float: ...

class Gaussian:
    """``x_0 ~ N(mean, std_dev^2 I)``; ``D = len(mean)``."""
    def __init__(self, mean: Sequence[float], std_dev: float) -> None: ...

class Point:
    """Every chain starts at ``x``; ``D = len(x)``."""
    def __init__(self, x: Sequence[float]) -> None: ...

#: A box: the same interval in every coordinate, or one ``(lo_i, hi_i)`` per coordinate.
BoxLike = Union[Interval, Sequence[Tuple[float, float]]]
StartLike = Union[Gaussian, Point, Interval, Sequence[Tuple[float, float]]]

class Stop:
    """Stopping rules, chained: ``Stop().evaluations(125_000).target(1e-6)``."""
    def __init__(self) -> None: ...
    def steps(self, k: int) -> Stop: ...
    def evaluations(self, n: int) -> Stop: ...
    def target(self, target: float) -> Stop: ...
    def stall(self, window: int, tolerance: float) -> Stop: ...
    def is_empty(self) -> bool: ...

class PolishSettings:
    """L-BFGS limits: ``evaluations``; converged when ``max |∂U| <= gradient_tolerance``
    or a step lowers ``U`` by at most ``value_tolerance * max(1, |U|)``."""
    def __init__(self, evaluations: int, *, gradient_tolerance: Optional[float] = None,
                 value_tolerance: Optional[float] = None) -> None: ...
    @property
    def evaluations(self) -> int: ...
    @property
    def gradient_tolerance(self) -> float: ...
    @property
    def value_tolerance(self) -> float: ...

class Report:
    value: float
    chain: int
    found_at: int
    iterations: int
    evaluations: int
    diverged_chains: int
    chains: int
    termination: str
    message: str

class Polished:
    value: float
    evaluations: int
    iterations: int
    end: str

class Potential:
    """A built-in potential, evaluated in Rust."""
    def value_and_gradient(self, x: F64) -> Tuple[F64, F64]: ...
    def global_minimum(self, dim: int) -> float: ...
    def global_minimiser(self, dim: int) -> F64: ...

class Rastrigin(Potential):
    """``U(x) = D + |x|^2 - Σ cos(2π x_i)``, ``∇U = 2x + 2π sin(2π x)``."""
    def __init__(self) -> None: ...

class Quadratic(Potential):
    """``U(x) = (k/2) |x - m|^2``."""
    def __init__(self, stiffness: float, centre: Sequence[float]) -> None: ...

class DoubleWell(Potential):
    """``U(x) = Σ (x_i^2 - 1)^2``."""
    def __init__(self) -> None: ...

class StyblinskiTang(Potential):
    """``U(x) = (1/2) Σ (x_i^4 - 16 x_i^2 + 5 x_i)``."""
    def __init__(self) -> None: ...

class Levy(Potential):
    """Levy's function; ``U* = 0`` at ``x* = 1``."""
    def __init__(self) -> None: ...

class Ackley(Potential):
    """Ackley's function with ``(20, 0.2, 2π)``; ``U* = 0`` at ``x* = 0``."""
    def __init__(self) -> None: ...

PotentialLike = Union[Potential, BatchedFunction]

class Optimizer:
    """Algorithm 1, step by step; chains readable as numpy views (no copy)."""
    def __init__(self, potential: PotentialLike, sampler: Sampler, schedule: ScheduleLike,
                 start: StartLike, *, chains: Optional[int] = 10, seed: Optional[int] = 0,
                 stride: Optional[int] = 1, stop: Optional[Stop] = None, domain: Optional[BoxLike] = None,
                 dim: Optional[int] = None) -> None: ...
    def step(self, steps: Optional[int] = 1) -> None: ...
    def run(self, observer: Union[None, Observer, ObserverX] = None, *, with_x: bool = False) -> Report: ...
    def termination(self) -> Optional[str]: ...
    def report(self) -> Optional[Report]: ...
    def polish(self, chain: int, settings: Optional[PolishSettings] = None) -> Polished: ...
    def quench(self, chain: int, settings: Optional[PolishSettings] = None) -> Polished: ...
    def restart(self, chain: int, x: Sequence[float]) -> bool: ...
    def current_best(self) -> Optional[Tuple[int, float]]: ...
    @property
    def x(self) -> F64: ...
    @property
    def y(self) -> F64: ...
    @property
    def gradient(self) -> F64: ...
    @property
    def best_x(self) -> F64: ...
    @property
    def best_value(self) -> F64: ...
    @property
    def value(self) -> F64: ...
    @property
    def diverged(self) -> npt.NDArray[np.bool_]: ...
    @property
    def best(self) -> Tuple[F64, float, int]: ...
    @property
    def best_chain(self) -> int: ...
    @property
    def iteration(self) -> int: ...
    @property
    def evaluations(self) -> int: ...
    @property
    def diverged_chains(self) -> int: ...
    @property
    def inverse_temperature(self) -> float: ...
    @property
    def dim(self) -> int: ...
    def __len__(self) -> int: ...

class Solution:
    x: F64
    value: float
    evaluations: int
    rounds: int
    step: float
    inverse_temperature: float
    chains: int
    termination: str
    diverged_chains: int
    all_diverged: bool
    message: str

class Auto:
    """The default solver (Langevin basin hopping on a ladder of temperatures)."""
    steps: int
    step_scale: float
    ladder: float
    quench: int
    first_quench: int
    stall: int
    converged_window: int
    accept: float
    def __init__(self, *, steps: Optional[int] = None, step_scale: Optional[float] = None,
                 ladder: Optional[float] = None, quench: Optional[int] = None,
                 first_quench: Optional[int] = None,
                 stall: Optional[int] = None, accept: Optional[float] = None) -> None: ...
    @staticmethod
    def chains_for(budget: int) -> int: ...
    def minimize(self, potential: PotentialLike, domain: BoxLike, budget: int, seed: Optional[int] = 0, *,
                 chains: Optional[int] = None, dim: Optional[int] = None,
                 x0: Optional[Sequence[float]] = None, observer: Union[None, Observer, ObserverX] = None,
                 with_x: bool = False, target: Optional[float] = None,
                 stall: Optional[Tuple[int, float]] = None, rounds: Optional[int] = None,
                 converge: Optional[int] = None, soft_budget: Optional[int] = None) -> Solution: ...

#: The largest dimension the gradient-free ensemble takes.
ENSEMBLE_MAX_DIM: int

def ensemble_minimize(values: Callable[[npt.NDArray[np.float64]], npt.ArrayLike], lo: Sequence[float], hi: Sequence[float],
                      budget: int, seed: int, observer: Optional[Callable[..., object]] = None, with_x: bool = False,
                      target: Optional[float] = None, stall: Optional[Tuple[int, float]] = None,
                      iterations: Optional[int] = None, elapsed: int = 0, known: float = ...,
                      known_at: Optional[Sequence[float]] = None, spread: float = 6.0, population: float = 2.0,
                      cool: float = 1.5, cool_every: int = 10,
                      converge: bool = True) -> Tuple[npt.NDArray[np.float64], float, int, int, int, int, str]:
    """The layer's gradient-free ensemble solver on ``values(X (n, d)) ->
    U (n,)`` in the box ``[lo, hi]``: ``(x, value, evaluations,
    generations, restarts, population, end)``, ``end`` one of
    ``"Budget"``, ``"Converged"``, ``"Observer"``, ``"Target"``,
    ``"Stalled"``, ``"Iterations"``; the rules count ``elapsed``
    iterations of an earlier phase that reached ``known`` at ``known_at``,
    and one large restart that agrees at ``known_at`` converges the run."""

def split_budget(budget: int, chains: int, polish: Optional[int] = None,
                 x0: bool = False) -> Optional[Tuple[Optional[int], int]]: ...
def auto_share(budget: int, dim: int, cost: int, spare: int, chains: Optional[int] = None) -> Optional[int]: ...

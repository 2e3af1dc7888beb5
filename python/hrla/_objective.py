"""A user's function, as scipy takes it, turned into the batch the kernel
calls: ``X (N, D) -> (U (N,), G (N, D))``.

scipy's conventions, each mapped here once:

- ``fun(x, *args) -> float`` on one point, or with ``vectorized=True``
  on ``S`` points at once: ``x`` of shape ``(D, S)`` (a column per point,
  as ``scipy.optimize.differential_evolution`` passes it) returning ``S``
  values;
- the gradient: ``jac=True`` (``fun`` returns ``(f, g)``, ``g`` of shape
  ``(D,)``, or ``(D, S)`` when vectorized), a callable ``jac(x, *args)``
  of the same shapes, or finite differences (``None``, ``"2-point"``,
  ``"3-point"``) with the steps of ``scipy.optimize.approx_derivative``
  in the box's units of length (:func:`steps`);
- ``workers``: an int (a ``multiprocessing.Pool`` of that many processes,
  ``-1`` for every CPU) or a map-like callable, which evaluates the points
  of a batch in parallel, then their finite-difference probes (those of
  points where ``fun`` is finite: elsewhere the point is infeasible, its
  gradient unused).

Every call of ``fun`` on a point counts in ``nfev``; every gradient (one
per point of the batch) in ``njev``. The lowest point seen is kept with
its gradient, the result's ``jac`` when the run ends there.
"""

from __future__ import annotations

import inspect
import multiprocessing
import os
from typing import Any, Callable, Iterable, List, Optional, Tuple

import numpy as np

EPS = float(np.finfo(np.float64).eps)

#: The finite-difference schemes, as ``scipy.optimize.approx_derivative``
#: names them: evaluations of ``fun`` per coordinate beyond the point.
SCHEMES = {"2-point": 1, "3-point": 2}


#: The width of a side of the box that is one unit of length to the
#: finite differences, as to ``Auto``: the paper's box ``[-5.12, 5.12]``.
WIDTH = 10.24


def units(lb: np.ndarray, ub: np.ndarray) -> np.ndarray:
    """Each coordinate's unit of length: its side of the box over
    :data:`WIDTH` (1 on the paper's box), or 1 where a side is not finite
    (no box to measure)."""
    width = np.asarray(ub, dtype=np.float64) - np.asarray(lb, dtype=np.float64)
    unit: np.ndarray = np.where(np.isfinite(width), width / WIDTH, 1.0)
    return unit


def steps(x: np.ndarray, lb: np.ndarray, ub: np.ndarray, scheme: str) -> Tuple[np.ndarray, np.ndarray]:
    """The finite-difference steps at the rows of ``x`` and whether each is
    one-sided: ``scipy.optimize.approx_derivative``'s rule, row by row, in
    the box's units of length.

    The step is ``r sign(x) max(l, |x|)`` with ``r = sqrt(eps)``
    (``"2-point"``) or ``eps^(1/3)`` (``"3-point"``), ``sign(0) = 1``, and
    ``l`` the coordinate's unit (:func:`units`): scipy's ``max(1, |x|)``
    with the box's unit for its 1, so that the steps, and the gradients,
    scale with the box (in ``s`` times the box, ``s`` times the steps).
    At a face of the box ``[lb, ub]`` it is turned inward (``"2-point"``:
    the backward difference; ``"3-point"``: the one-sided three-point
    formula), and shortened where the box is narrower than it, so that no
    probe leaves the box.
    """
    rstep = EPS ** 0.5 if scheme == "2-point" else EPS ** (1 / 3)
    sign = (x >= 0).astype(np.float64) * 2 - 1
    h = rstep * sign * np.maximum(np.broadcast_to(units(lb, ub), x.shape), np.abs(x))
    lb = np.broadcast_to(lb, x.shape)
    ub = np.broadcast_to(ub, x.shape)
    if scheme == "2-point":
        one_sided = np.ones_like(h, dtype=bool)
    else:
        h = np.abs(h)
        one_sided = np.zeros_like(h, dtype=bool)
    if np.all((lb == -np.inf) & (ub == np.inf)):
        return h, one_sided
    adjusted = h.copy()
    lower = x - lb
    upper = ub - x
    if scheme == "2-point":
        probe = x + h
        violated = (probe < lb) | (probe > ub)
        fitting = np.abs(h) <= np.maximum(lower, upper)
        adjusted[violated & fitting] *= -1
        forward = (upper >= lower) & ~fitting
        adjusted[forward] = upper[forward]
        backward = (upper < lower) & ~fitting
        adjusted[backward] = -lower[backward]
    else:
        central = (lower >= h) & (upper >= h)
        forward = (upper >= lower) & ~central
        adjusted[forward] = np.minimum(h[forward], 0.5 * upper[forward])
        one_sided[forward] = True
        backward = (upper < lower) & ~central
        adjusted[backward] = -np.minimum(h[backward], 0.5 * lower[backward])
        one_sided[backward] = True
        least = np.minimum(upper, lower)
        recentred = ~central & (np.abs(adjusted) <= least)
        adjusted[recentred] = least[recentred]
        one_sided[recentred] = False
    return adjusted, one_sided


def probes(x: np.ndarray, h: np.ndarray, one_sided: np.ndarray, scheme: str) -> np.ndarray:
    """The probe points of the rows of ``x`` (``N x D``): shape
    ``(N, k, D, D)``, ``k`` of :data:`SCHEMES`, probe ``[n, i, j]`` being
    row ``n`` with coordinate ``j`` moved (``"2-point"``: ``x + h``;
    ``"3-point"``: ``x - h, x + h``, or ``x + h, x + 2h`` where one-sided)."""
    n, d = x.shape
    k = SCHEMES[scheme]
    p = np.repeat(np.repeat(x[:, None, None, :], k, axis=1), d, axis=2)
    j = np.arange(d)
    if scheme == "2-point":
        p[:, 0, j, j] = x + h
    else:
        p[:, 0, j, j] = np.where(one_sided, x + h, x - h)
        p[:, 1, j, j] = np.where(one_sided, x + 2 * h, x + h)
    return p


def difference(f0: np.ndarray, x: np.ndarray, p: np.ndarray, fp: np.ndarray, one_sided: np.ndarray,
               scheme: str) -> np.ndarray:
    """The gradients at the rows of ``x`` from the values ``f0`` there and
    ``fp`` (shape ``(N, k, D)``) at the probes ``p``, as
    ``approx_derivative`` forms them (the step taken as the probes'
    difference, so that its rounding cancels)."""
    j = np.arange(x.shape[1])
    if scheme == "2-point":
        forward: np.ndarray = (fp[:, 0] - f0[:, None]) / (p[:, 0, j, j] - x)
        return forward
    f1, f2 = fp[:, 0], fp[:, 1]
    x1, x2 = p[:, 0, j, j], p[:, 1, j, j]
    with np.errstate(invalid="ignore"):
        side = (-3.0 * f0[:, None] + 4 * f1 - f2) / (x2 - x)
        centre = (f2 - f1) / (x2 - x1)
    both: np.ndarray = np.where(one_sided, side, centre)
    return both


def real(v: Any, what: str) -> np.ndarray:
    """``v`` as a float64 array, refusing what numpy would turn into a
    wrong number silently: booleans, complex numbers, strings, objects."""
    try:
        a = np.asarray(v)
    except ValueError:  # ragged sequences
        raise TypeError(f"{what} must be real numbers (floats or ints), got {_show(v)}") from None
    if a.dtype.kind not in "fiu":
        raise TypeError(f"{what} must be real numbers (floats or ints), got {_show(v)} (dtype {a.dtype})")
    return a.astype(np.float64, copy=False)


def _show(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 80 else text[:77] + "..."


class Call:
    """``fun(x, *args)`` on a copy of ``x``: a picklable callable, for a
    process pool. Every call of the user's ``fun`` or ``jac`` goes through
    it, so that each gets an array of its own, as scipy passes a copy: a
    ``fun`` that writes into its argument changes neither the run's points
    nor its result. (A read-only view would cost no copy but break a
    ``fun`` written for scipy that works in place on its ``x``; the copy
    costs far less than the call.) The copy keeps the memory order, so
    that ``fun`` computes the same bits as on the original."""

    def __init__(self, fun: Callable[..., Any], args: Tuple[Any, ...]) -> None:
        self.fun = fun
        self.args = args

    def __call__(self, x: np.ndarray) -> Any:
        return self.fun(np.array(x, order="K"), *self.args)


class Mapper:
    """``workers`` as a map: the builtin ``map`` for 1, a process pool for
    an int above 1 (``-1``: one process per CPU), or the user's map-like
    callable. :meth:`close` ends a pool this made."""

    def __init__(self, workers: Any) -> None:
        self.pool: Any = None
        self.map: Callable[[Callable[[Any], Any], Iterable[Any]], Iterable[Any]]
        if callable(workers):
            self.map = workers
            return
        if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)):
            raise TypeError(f"workers must be an int or a map-like callable, got {_show(workers)}")
        workers = int(workers)
        if workers == 1:
            self.map = map
        elif workers == -1 or workers > 1:
            self.pool = multiprocessing.Pool(os.cpu_count() if workers == -1 else workers)
            self.map = self._pool_map
        else:
            raise ValueError(f"workers must be >= 1, -1 (every CPU) or a map-like callable, got {workers}")

    def _pool_map(self, function: Callable[[Any], Any], points: Iterable[Any]) -> List[Any]:
        """The pool's map, waking the main thread every 50 ms: the operating
        system may deliver Ctrl-C's SIGINT to one of the pool's threads,
        and a main thread blocked without a timeout would then never run
        Python's handler (with a worker that hangs, the run would hang)."""
        pending = self.pool.map_async(function, points)
        while True:
            try:
                answers: List[Any] = pending.get(0.05)
            except multiprocessing.TimeoutError:
                continue
            return answers

    def close(self) -> None:
        if self.pool is not None:
            self.pool.terminate()
            self.pool.join()
            self.pool = None


def callback_form(callback: Callable[..., Any]) -> str:
    """How ``callback`` is called, from its signature: ``"intermediate_result"``
    (scipy's test: its one parameter has that name) gets an
    ``OptimizeResult``; else by the positional parameters without a
    default: three or more, ``"x, f, context"`` (``dual_annealing``'s form,
    and ``basinhopping``'s ``(x, f, accept)``, whose third is then the
    context); two, ``"x, f"``; fewer (or no signature), ``"x"``, scipy's
    older ``callback(xk)``."""
    try:
        parameters = inspect.signature(callback).parameters
    except (TypeError, ValueError):
        return "x"
    if set(parameters) == {"intermediate_result"}:
        return "intermediate_result"
    positional = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    required = sum(p.kind in positional and p.default is inspect.Parameter.empty for p in parameters.values())
    return "x, f, context" if required >= 3 else "x, f" if required == 2 else "x"


class Objective:
    """A user's ``fun`` (with ``args``, ``jac``, ``vectorized``,
    ``workers``) as the kernel's batch ``X (N, D) -> (U (N,), G (N, D))``.

    ``lb`` and ``ub`` bound the finite differences' probes (``-inf`` and
    ``inf`` without a box). ``nfev`` counts the calls of ``fun`` on a point,
    ``njev`` the gradients; ``best`` is ``(x, f, g)`` of the lowest point of
    any batch so far (``None`` before the first).
    """

    def __init__(self, fun: Callable[..., Any], args: Tuple[Any, ...], jac: Any, vectorized: bool,
                 mapper: Mapper, lb: np.ndarray, ub: np.ndarray) -> None:
        self.fun = fun
        self.args = args
        self.jac = jac
        self.vectorized = vectorized
        self.mapper = mapper
        self.lb = lb
        self.ub = ub
        self.scheme: Optional[str] = None
        if jac is None or jac is False:
            self.scheme = "2-point"
        elif isinstance(jac, str):
            if jac not in SCHEMES:
                raise ValueError(f"jac must be None, True, a callable, '2-point' or '3-point', got {jac!r}")
            self.scheme = jac
        elif jac is not True and not callable(jac):
            raise TypeError(f"jac must be None, True, a callable, '2-point' or '3-point', got {_show(jac)}")
        self.nfev = 0
        self.njev = 0
        self.best: Optional[Tuple[np.ndarray, float, np.ndarray]] = None

    def cost(self, d: int) -> int:
        """Calls of ``fun`` per gradient in dimension ``d``."""
        return 1 + (SCHEMES[self.scheme] * d if self.scheme else 0)

    def __call__(self, x: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        x = np.asarray(x, dtype=np.float64)
        n, d = x.shape
        if self.scheme is not None:
            k = SCHEMES[self.scheme]
            h, one_sided = steps(x, self.lb, self.ub, self.scheme)
            p = probes(x, h, one_sided, self.scheme)
            if self.vectorized:
                # One call for the points and their probes.
                everything = self.values(np.concatenate([x, p.reshape(-1, d)]))
                u, fp = everything[:n], everything[n:].reshape(n, k, d)
            else:
                # The probes of feasible points only: where fun is NaN or
                # infinite the point is refused whatever its gradient, and
                # each probe may cost as much as a failed solve.
                u = self.values(x)
                feasible = np.isfinite(u)
                fp = np.full((n, k, d), np.nan)
                if feasible.any():
                    fp[feasible] = self.values(p[feasible].reshape(-1, d)).reshape(-1, k, d)
            g = difference(u, x, p, fp, one_sided, self.scheme)
        elif self.jac is True:
            u, g = self.values_and_gradients(x)
        else:
            u = self.values(x)
            g = self.gradients(x)
        self.njev += n
        self.keep(x, u, g)
        return u, g

    def keep(self, x: np.ndarray, u: np.ndarray, g: np.ndarray) -> None:
        finite = np.where(np.isfinite(u))[0]
        if finite.size == 0:
            return
        i = finite[np.argmin(u[finite])]
        if self.best is None or u[i] < self.best[1]:
            self.best = (x[i].copy(), float(u[i]), np.array(g[i], dtype=np.float64))

    def values(self, x: np.ndarray) -> np.ndarray:
        """``fun`` at the rows of ``x``: one call on the columns of ``x.T``
        when vectorized, else one call a row through the workers."""
        n = len(x)
        self.nfev += n
        if self.vectorized:
            u = real(Call(self.fun, self.args)(x.T), "fun's values")
            if u.shape != (n,):
                raise ValueError(f"a vectorized fun must return shape ({n},) for x of shape "
                                 f"{(x.shape[1], n)}, got {u.shape}")
            return u
        return np.array([scalar(v) for v in self.each(self.fun, x)], dtype=np.float64)

    def gradients(self, x: np.ndarray) -> np.ndarray:
        """``jac`` at the rows of ``x``."""
        n, d = x.shape
        if self.vectorized:
            return self.column_gradients(Call(self.jac, self.args)(x.T), n, d, "jac")
        rows = [vector(g, d, "jac") for g in self.each(self.jac, x)]
        return np.array(rows, dtype=np.float64).reshape(n, d)

    def values_and_gradients(self, x: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """``fun`` returning ``(f, g)`` at the rows of ``x``."""
        n, d = x.shape
        self.nfev += n
        if self.vectorized:
            u, g = pair(Call(self.fun, self.args)(x.T))
            u = real(u, "fun's values")
            if u.shape != (n,):
                raise ValueError(f"a vectorized fun must return f of shape ({n},), got {u.shape}")
            return u, self.column_gradients(g, n, d, "fun's gradient")
        answers = [pair(a) for a in self.each(self.fun, x)]
        u = np.array([scalar(f) for f, _ in answers], dtype=np.float64)
        g = np.array([vector(g, d, "fun's gradient") for _, g in answers], dtype=np.float64)
        return u, g.reshape(n, d)

    def each(self, function: Callable[..., Any], x: np.ndarray) -> List[Any]:
        """``function`` at each row of ``x``, through the workers: one
        answer a row, or ``ValueError`` naming the map."""
        answers = list(self.mapper.map(Call(function, self.args), list(x)))
        if len(answers) != len(x):
            raise ValueError(f"the workers map returned {len(answers)} results for {len(x)} points: a map-like "
                             f"workers must return one result per point, in order, as the builtin map")
        return answers

    @staticmethod
    def column_gradients(g: Any, n: int, d: int, what: str) -> np.ndarray:
        g = real(g, what)
        if g.shape != (d, n):
            raise ValueError(f"{what} must have shape {(d, n)} (a column per point), got {g.shape}")
        rows: np.ndarray = g.T
        return rows


def pair(answer: Any) -> Tuple[Any, Any]:
    """``(f, g)`` from ``fun`` when ``jac=True``."""
    try:
        f, g = answer
    except (TypeError, ValueError):
        raise TypeError(f"with jac=True, fun must return a pair (f, g), got {_show(answer)}") from None
    return f, g


def scalar(v: Any) -> float:
    """``fun``'s value at one point: a real number (or an array of one)."""
    try:
        a = np.asarray(v)
    except ValueError:  # ragged sequences
        a = np.asarray(None)
    if a.dtype.kind not in "fiu" or a.size != 1:
        hint = " (with its gradient, pass jac=True)" if isinstance(v, tuple) else ""
        raise TypeError(f"fun must return a real number{hint}, got {_show(v)}")
    return float(a.reshape(()))


def vector(g: Any, d: int, what: str) -> np.ndarray:
    """A gradient at one point: ``d`` real numbers."""
    a = real(g, what)
    if a.size != d:
        raise ValueError(f"{what} must have {d} entries (shape ({d},)), got shape {a.shape}")
    return a.reshape(d)


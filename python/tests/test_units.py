"""``hrla.minimize`` does not depend on the units of the problem: ``c
f(x / s)`` over ``s`` times the box (``c`` in ``[1e-14, 1e14]``, ``s`` in
``[1e-10, 1e10]``) is run as ``f`` over the box, its result ``s`` times the
point and ``c`` times the value, up to rounding (the Rust side:
``tests/tests/units.rs``)."""

import numpy as np
import pytest

import hrla

C = [1e-14, 1e-7, 1.0, 1e7, 1e14]
S = [1e-10, 1e-5, 1.0, 1e5, 1e10]


def bowl(c, s, jac):
    """``c sum (x_i / s - 0.3)^2`` and, with ``jac``, its gradient."""
    def fun(x):
        z = x / s - 0.3
        value = c * float(np.sum(z * z))
        return (value, 2 * c * z / s) if jac else value
    return fun


def run(c, s, jac, seed):
    fun = bowl(c, s, jac)
    maxfun = 2_000 if jac else 6_000
    return hrla.minimize(fun, [(0.0, s), (0.0, s)], jac=True if jac else None, maxfun=maxfun, rng=seed)


@pytest.mark.parametrize("seed", [0, 1])
def test_the_gradients_bowl_is_run_alike_in_any_units(seed):
    """With its gradient, the same decisions (rounds, why it ended,
    the calls up to the final polish's last few), and the point, value, step and inverse temperature within
    `1e-10` of the unscaled run's (relative to the box, to 1, and to
    themselves): the arithmetic of the same decisions on inputs that
    differ in their last bits, the settings' difference of gradients
    `1e-4` of the box apart losing about four digits of sixteen."""
    want = run(1.0, 1.0, True, seed)
    assert want.success and np.all(np.abs(want.x - 0.3) < 1e-8) and want.fun < 1e-16, want
    for c in C:
        for s in S:
            got = run(c, s, True, seed)
            case = f"c = {c:e}, s = {s:e}: {got} against {want}"
            # The same rounds and end; the final polish, which runs to the
            # float type's precision, ends where rounding decides, within a
            # few calls of the unscaled run's end.
            assert (got.nit, got.termination) == (want.nit, want.termination), case
            assert abs(got.nfev - want.nfev) <= 4, case
            np.testing.assert_allclose(got.x / s, want.x, rtol=0, atol=1e-10, err_msg=case)
            assert abs(got.fun / c - want.fun) <= 1e-10, case
            assert got.step * c / s ** 2 == pytest.approx(want.step, rel=1e-10), case
            assert got.inverse_temperature * c == pytest.approx(want.inverse_temperature, rel=1e-10), case


@pytest.mark.parametrize("seed", [0, 1])
def test_the_finite_differences_bowl_is_solved_alike_in_any_units(seed):
    """With finite differences (their steps in the box's units), every
    scaled run ends at the minimum as the unscaled one does, to the
    differences' precision: within `1e-8` of the box (the forward
    difference's bias, half its step, `sqrt(eps)` of the box over 2 *
    10.24, is `7e-10` of it), its value below `1e-16` of `c`. (The calls
    and rounds may differ: each quench ends where the decrease its
    gradient predicts falls to `64 eps` of the problem's energy, and a
    forward difference is only `sqrt(eps)` accurate, so that the rounding
    of its values decides that end.)"""
    want = run(1.0, 1.0, False, seed)
    assert want.success, want
    for c in C:
        for s in S:
            got = run(c, s, False, seed)
            case = f"c = {c:e}, s = {s:e}: {got} against {want}"
            assert got.success and got.termination == want.termination, case
            assert np.all(np.abs(got.x / s - 0.3) < 1e-8), case
            assert 0 <= got.fun / c < 1e-16, case

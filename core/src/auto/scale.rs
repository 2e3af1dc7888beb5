//! The box's own units: the coordinates in which [`Auto`](super::Auto)'s
//! dynamics and quenches run.
//!
//! One step size `h` serves every coordinate, so a box whose sides differ
//! by orders of magnitude would leave the wide coordinates frozen while
//! the narrow ones move. The run therefore works in `u_i = x_i / w_i`,
//! `w_i = (hi_i - lo_i) / max_j (hi_j - lo_j)`: every side becomes as
//! long as the widest. The map is linear with a constant Jacobian, so
//! `exp(-a U)` is the same law in `u`; the gradient in `u` is `w_i ∂U/∂x_i`.
//! In a box whose sides are all equal every `w_i` is exactly 1, and the
//! run is bit for bit the one in `x`.

use core::cell::RefCell;

use crate::domain::{Domain, Sides, confine_each, feasible_each, project_each};
use crate::float::Float;
use crate::potential::SlicePotential;

/// The box `domain` in its unit coordinates (itself a box: `[lo_i / w_i,
/// hi_i / w_i]`).
pub(super) struct Unit<'a, F, B: ?Sized> {
    domain: &'a B,
    widest: F,
    /// Whether every side is the widest: every `w_i` is 1, and the maps
    /// are skipped (they would multiply and divide by 1).
    equal: bool,
}

impl<F, B: ?Sized> Clone for Unit<'_, F, B>
where
    F: Copy,
{
    fn clone(&self) -> Self {
        *self
    }
}

impl<F: Copy, B: ?Sized> Copy for Unit<'_, F, B> {}

impl<'a, F: Float, B: Sides<F> + ?Sized> Unit<'a, F, B> {
    /// The unit coordinates of `domain` in dimension `d`.
    pub(super) fn new(domain: &'a B, d: usize) -> Self {
        let mut widest = F::ZERO;
        let mut narrowest = F::INFINITY;
        for i in 0..d {
            let (lo, hi) = domain.side(i);
            if hi - lo > widest {
                widest = hi - lo;
            }
            if hi - lo < narrowest {
                narrowest = hi - lo;
            }
        }
        Self {
            domain,
            widest,
            equal: narrowest == widest,
        }
    }

    /// Whether every side is the widest: the unit coordinates are the
    /// box's own, and a caller may skip the maps.
    #[inline(always)]
    pub(super) fn is_identity(&self) -> bool {
        self.equal
    }

    /// The widest side: every side's length in unit coordinates.
    pub(super) fn widest(&self) -> F {
        self.widest
    }

    /// `w_i`: coordinate `i`'s side over the widest.
    #[inline(always)]
    pub(super) fn w(&self, i: usize) -> F {
        if self.equal {
            return F::ONE;
        }
        let (lo, hi) = self.domain.side(i);
        (hi - lo) / self.widest
    }

    /// `x` to unit coordinates, in place.
    #[inline]
    pub(super) fn scale_in(&self, x: &mut [F]) {
        if self.equal {
            return;
        }
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = *xi / self.w(i);
        }
    }

    /// The point `x` of the box at unit coordinates `u` (rounding kept
    /// inside the box).
    #[inline]
    pub(super) fn point_of(&self, u: &[F], x: &mut [F]) {
        if self.equal {
            x.copy_from_slice(u);
            return;
        }
        for (i, (xi, &ui)) in x.iter_mut().zip(u).enumerate() {
            *xi = ui * self.w(i);
        }
        self.domain.project(x);
    }

    /// [`point_of`](Unit::point_of) in place.
    #[inline]
    pub(super) fn scale_out(&self, x: &mut [F]) {
        if self.equal {
            return;
        }
        for (i, xi) in x.iter_mut().enumerate() {
            *xi *= self.w(i);
        }
        self.domain.project(x);
    }

    /// [`gradient`](Unit::gradient) in place.
    #[inline]
    pub(super) fn gradient_in_place(&self, g: &mut [F]) {
        if self.equal {
            return;
        }
        for (i, gi) in g.iter_mut().enumerate() {
            *gi *= self.w(i);
        }
    }

    /// The gradient in the box's coordinates of the gradient `g` in unit
    /// coordinates, in place.
    pub(super) fn gradient_out_in_place(&self, g: &mut [F]) {
        if self.equal {
            return;
        }
        for (i, gi) in g.iter_mut().enumerate() {
            *gi = *gi / self.w(i);
        }
    }

    /// The gradient in unit coordinates of the gradient `g` in `x`.
    #[inline]
    pub(super) fn gradient(&self, g: &[F], out: &mut [F]) {
        if self.equal {
            out.copy_from_slice(g);
            return;
        }
        for (i, (oi, &gi)) in out.iter_mut().zip(g).enumerate() {
            *oi = gi * self.w(i);
        }
    }
}

impl<F: Float, B: Sides<F> + ?Sized> Domain<F> for Unit<'_, F, B> {
    #[inline]
    fn confine(&self, x: &mut [F], y: &mut [F]) {
        if self.equal {
            return self.domain.confine(x, y);
        }
        confine_each(x, y, |i| self.side(i).0, |i| self.side(i).1);
    }

    #[inline]
    fn project(&self, x: &mut [F]) {
        if self.equal {
            return self.domain.project(x);
        }
        project_each(x, |i| self.side(i).0, |i| self.side(i).1);
    }

    fn feasible_direction(&self, x: &[F], d: &mut [F]) {
        if self.equal {
            return self.domain.feasible_direction(x, d);
        }
        feasible_each(x, d, |i| self.side(i).0, |i| self.side(i).1);
    }
}

impl<F: Float, B: Sides<F> + ?Sized> Sides<F> for Unit<'_, F, B> {
    #[inline(always)]
    fn side(&self, i: usize) -> (F, F) {
        let (lo, hi) = self.domain.side(i);
        if self.equal {
            return (lo, hi);
        }
        let w = self.w(i);
        (lo / w, hi / w)
    }
}

/// `U` in unit coordinates: evaluated at the box's point, its gradient
/// scaled, with `x` a point's worth of scratch.
pub(super) struct Scaled<'a, F, P: ?Sized, B: ?Sized> {
    pub(super) potential: &'a P,
    pub(super) unit: Unit<'a, F, B>,
    pub(super) x: RefCell<&'a mut [F]>,
}

impl<F, P, B> SlicePotential<F> for Scaled<'_, F, P, B>
where
    F: Float,
    P: SlicePotential<F> + ?Sized,
    B: Sides<F> + ?Sized,
{
    #[inline]
    fn value_and_gradient(&self, u: &[F], grad: &mut [F]) -> F {
        let mut x = self.x.borrow_mut();
        self.unit.point_of(u, &mut x);
        let value = self.potential.value_and_gradient(&x, grad);
        if self.unit.equal {
            return value;
        }
        for (i, gi) in grad.iter_mut().enumerate() {
            *gi *= self.unit.w(i);
        }
        value
    }
}

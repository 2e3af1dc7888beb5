//! What a potential is: the [`Potential`] trait, and [`KnownMinimum`] for
//! potentials whose global minimum is known.

use core::cell::Cell;
use core::ops::ControlFlow;

use crate::float::Float;

/// A smooth potential `U` on `R^D` with its gradient.
///
/// Implement [`Potential::value_and_gradient`], the one method the
/// optimiser calls (once per chain and step); [`Potential::value`] and
/// [`Potential::gradient`] follow from it. A non-finite value or gradient
/// is allowed: the optimiser marks the chain as diverged.
///
/// ```
/// use hrla::Potential;
///
/// /// `U(x) = cosh(x_1) + x_2^2`.
/// struct Valley;
///
/// impl Potential<f64, 2> for Valley {
///     fn value_and_gradient(&self, x: &[f64; 2], grad: &mut [f64; 2]) -> f64 {
///         *grad = [libm::sinh(x[0]), 2.0 * x[1]];
///         libm::cosh(x[0]) + x[1] * x[1]
///     }
/// }
///
/// assert_eq!(Valley.value(&[0.0, 1.0]), 2.0);
/// ```
pub trait Potential<F: Float, const D: usize> {
    /// Writes `∇U(x)` into `grad` and returns `U(x)`.
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F;

    /// `U(x)`.
    #[inline]
    fn value(&self, x: &[F; D]) -> F {
        let mut grad = [F::ZERO; D];
        self.value_and_gradient(x, &mut grad)
    }

    /// Writes `∇U(x)` into `grad`.
    #[inline]
    fn gradient(&self, x: &[F; D], grad: &mut [F; D]) {
        self.value_and_gradient(x, grad);
    }
}

/// A reference to a potential is the same potential: one potential can
/// serve many optimisers without being cloned.
impl<F: Float, const D: usize, P: Potential<F, D> + ?Sized> Potential<F, D> for &P {
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        (**self).value_and_gradient(x, grad)
    }
}

/// A potential whose global minimum is known: for tests and benchmarks.
pub trait KnownMinimum<F: Float, const D: usize>: Potential<F, D> {
    /// The global minimum `U*`.
    fn global_minimum(&self) -> F;
    /// A global minimiser `x*` (one of them, when there are several).
    fn global_minimiser(&self) -> [F; D];
}

impl<F: Float, const D: usize, P: KnownMinimum<F, D> + ?Sized> KnownMinimum<F, D> for &P {
    fn global_minimum(&self) -> F {
        (**self).global_minimum()
    }
    fn global_minimiser(&self) -> [F; D] {
        (**self).global_minimiser()
    }
}

/// A smooth potential `U` on `R^d` whose dimension is the length of the
/// slices: the run-time-dimension twin of [`Potential`]. A built-in
/// potential gives the same bits through both.
pub trait SlicePotential<F: Float> {
    /// Writes `∇U(x)` into `grad` (`grad.len() == x.len()`) and returns
    /// `U(x)`.
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F;

    /// The dimension the potential was made for, if it has one (a centre,
    /// a table of coefficients); a run of another dimension is refused.
    fn dimension(&self) -> Option<usize> {
        None
    }
}

impl<F: Float, P: SlicePotential<F> + ?Sized> SlicePotential<F> for &P {
    #[inline]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        (**self).value_and_gradient(x, grad)
    }
    fn dimension(&self) -> Option<usize> {
        (**self).dimension()
    }
}

/// The batch seam: one call evaluates the new points of a group of chains
/// (a GPU kernel, a SIMD routine, a Python function of an `(n, d)` array).
///
/// The group's points are chain-major: chain `i`'s point is
/// `x[i * d..(i + 1) * d]`, its gradient goes to `grad[i * d..(i + 1) * d]`
/// and its value to `value[i]`. A chain with `skip[i]` set has diverged:
/// leave its gradient and value alone (they are not read). A non-finite
/// value or gradient is allowed: the optimiser marks the chain diverged.
///
/// A potential that cannot answer (a user's function raised, a device was
/// lost) answers [`ControlFlow::Break`]: the run ends with
/// [`Error::Stopped`](crate::Error::Stopped), the group's values unread,
/// and the caller that gave the potential keeps the cause.
///
/// Every [`SlicePotential`] is one, evaluating the points one by one;
/// implement this trait directly (and not [`SlicePotential`]) for a
/// potential that is cheaper per batch.
pub trait BatchPotential<F: Float> {
    /// Writes the values and gradients of the group's points, or stops
    /// the run.
    fn values_and_gradients(
        &self,
        d: usize,
        x: &[F],
        grad: &mut [F],
        value: &mut [F],
        skip: &[bool],
    ) -> ControlFlow<()>;

    /// The dimension the potential was made for, if it has one.
    fn batch_dimension(&self) -> Option<usize> {
        None
    }

    /// How many chains a call should carry at most: `None` (the default),
    /// all of a step's. A potential that gains nothing from large batches
    /// asks for few, so that a group's state is still in cache when it is
    /// evaluated right after its step (the blanket implementation asks for
    /// [`LANES`](crate::LANES), one group of chains stepped in lockstep).
    /// Any answer gives the same bits.
    fn chains_per_call(&self) -> Option<usize> {
        None
    }
}

impl<F: Float, P: SlicePotential<F> + ?Sized> BatchPotential<F> for P {
    #[inline(always)]
    fn values_and_gradients(
        &self,
        d: usize,
        x: &[F],
        grad: &mut [F],
        value: &mut [F],
        skip: &[bool],
    ) -> ControlFlow<()> {
        let points = x.chunks_exact(d).zip(grad.chunks_exact_mut(d));
        for (((x, grad), value), &skip) in points.zip(value.iter_mut()).zip(skip) {
            if !skip {
                *value = self.value_and_gradient(x, grad);
            }
        }
        ControlFlow::Continue(())
    }

    fn batch_dimension(&self) -> Option<usize> {
        self.dimension()
    }

    fn chains_per_call(&self) -> Option<usize> {
        Some(crate::lockstep::LANES)
    }
}

/// `U(x)` and `∇U(x)` through the batch seam, as a batch of one, for the
/// callers that take one point at a time (a search, `Auto`). A stop is
/// kept in `stopped` and reads as `-inf`, which ends the caller's work at
/// once (as a potential unbounded below would) before it reports
/// [`Error::Stopped`](crate::Error::Stopped).
#[inline]
pub(crate) fn one_point<F: Float, P: BatchPotential<F> + ?Sized>(
    potential: &P,
    x: &[F],
    grad: &mut [F],
    stopped: &Cell<bool>,
) -> F {
    let mut value = [F::INFINITY];
    if potential
        .values_and_gradients(x.len(), x, grad, &mut value, &[false])
        .is_break()
    {
        stopped.set(true);
        return -F::INFINITY;
    }
    value[0]
}

//! What a potential is: the [`Potential`] trait, and [`KnownMinimum`] for
//! potentials whose global minimum is known.

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

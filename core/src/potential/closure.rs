//! A potential from a closure.

use super::traits::{Potential, SlicePotential};
use crate::float::Float;

/// A potential from one closure that writes `∇U(x)` and returns `U(x)`, as
/// users write it.
///
/// ```
/// use hrla::{FnPotential, Potential};
///
/// // Himmelblau's function.
/// let himmelblau = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| {
///     let (p, q) = (x[0] * x[0] + x[1] - 11.0, x[0] + x[1] * x[1] - 7.0);
///     *g = [4.0 * x[0] * p + 2.0 * q, 2.0 * p + 4.0 * x[1] * q];
///     p * p + q * q
/// });
/// assert_eq!(himmelblau.value(&[3.0, 2.0]), 0.0);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct FnPotential<G>(G);

impl<G> FnPotential<G> {
    /// Wraps `value_and_gradient`. (Through this function rather than the
    /// struct, the closure's argument types are inferred for every
    /// lifetime of its references.)
    pub fn new<F: Float, const D: usize>(value_and_gradient: G) -> Self
    where
        G: Fn(&[F; D], &mut [F; D]) -> F,
    {
        Self(value_and_gradient)
    }
}

impl<F: Float, const D: usize, G> Potential<F, D> for FnPotential<G>
where
    G: Fn(&[F; D], &mut [F; D]) -> F,
{
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        (self.0)(x, grad)
    }
}

impl<G> FnPotential<G> {
    /// A closure over slices, for a dimension known at run time: it writes
    /// `∇U(x)` into its second argument (as long as `x`) and returns `U(x)`.
    pub fn slices<F: Float>(value_and_gradient: G) -> Self
    where
        G: Fn(&[F], &mut [F]) -> F,
    {
        Self(value_and_gradient)
    }
}

impl<F: Float, G> SlicePotential<F> for FnPotential<G>
where
    G: Fn(&[F], &mut [F]) -> F,
{
    #[inline]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        (self.0)(x, grad)
    }
}

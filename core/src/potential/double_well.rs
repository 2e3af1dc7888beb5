//! The separable double well: a two-humped Gibbs law, the test case for
//! the invariant law.

use super::traits::{KnownMinimum, Potential, SlicePotential};
use crate::float::Float;

/// The separable double well `U(x) = sum_i (x_i^2 - 1)^2`,
/// `∇U(x) = 4 x (x^2 - 1)`.
///
/// `U* = 0` at the `2^D` points with every `x_i = ±1`; a saddle of height 1
/// per coordinate at `x_i = 0`. In one dimension its Gibbs law is a
/// two-humped density, the test case for the invariant-law test.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DoubleWell;

impl<F: Float, const D: usize> Potential<F, D> for DoubleWell {
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        SlicePotential::value_and_gradient(self, x, grad)
    }
}

impl<F: Float> SlicePotential<F> for DoubleWell {
    // Always inlined, so that the fixed-size impl's loops know their length.
    #[inline(always)]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        let mut u = F::ZERO;
        for (&xi, gi) in x.iter().zip(grad.iter_mut()) {
            let w = xi * xi - F::ONE;
            *gi = F::from_f64(4.0) * xi * w;
            u += w * w;
        }
        u
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for DoubleWell {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    /// `(1, ..., 1)`, one of the `2^D` minimisers.
    fn global_minimiser(&self) -> [F; D] {
        [F::ONE; D]
    }
}

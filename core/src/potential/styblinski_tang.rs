//! Styblinski–Tang: one global minimum among `2^D` local ones.

use super::traits::{KnownMinimum, Potential, SlicePotential};
use crate::float::Float;

/// The root of `4x^3 - 32x + 5 = 0` in `(-3, -2.5)`: the Styblinski–Tang
/// minimiser of one coordinate (computed to 40 digits offline).
const STYBLINSKI_TANG_X: f64 = -2.903_534_027_771_177;
/// `(x^4 - 16x^2 + 5x) / 2` at that root.
const STYBLINSKI_TANG_U: f64 = -39.166_165_703_771_41;

/// Styblinski–Tang, `U(x) = (1/2) sum_i (x_i^4 - 16 x_i^2 + 5 x_i)`.
///
/// Global minimum `U* = -39.166165703771415 D` at
/// `x* = (-2.9035340277711771, ...)`; `2^D - 1` other local minima with a
/// coordinate near `+2.7468`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StyblinskiTang;

impl<F: Float, const D: usize> Potential<F, D> for StyblinskiTang {
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        SlicePotential::value_and_gradient(self, x, grad)
    }
}

impl<F: Float> SlicePotential<F> for StyblinskiTang {
    // Always inlined, so that the fixed-size impl's loops know their length.
    #[inline(always)]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        let (c16, c5) = (F::from_f64(16.0), F::from_f64(5.0));
        let mut u = F::ZERO;
        for (&xi, gi) in x.iter().zip(grad.iter_mut()) {
            let x2 = xi * xi;
            *gi = F::TWO * xi * x2 - c16 * xi + F::from_f64(2.5);
            u += (x2 * x2 - c16 * x2 + c5 * xi) * F::HALF;
        }
        u
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for StyblinskiTang {
    fn global_minimum(&self) -> F {
        F::from_f64(STYBLINSKI_TANG_U * D as f64)
    }
    fn global_minimiser(&self) -> [F; D] {
        [F::from_f64(STYBLINSKI_TANG_X); D]
    }
}

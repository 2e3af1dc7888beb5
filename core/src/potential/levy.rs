//! Levy's function: many local minima, the global one at `(1, ..., 1)`.

use super::traits::{KnownMinimum, Potential, SlicePotential};
use crate::float::Float;

/// Levy's function, with `w_i = 1 + (x_i - 1)/4`:
///
/// ```text
/// U(x) = sin^2(π w_1)
///      + sum_{i<D} (w_i - 1)^2 (1 + 10 sin^2(π w_i + 1))
///      + (w_D - 1)^2 (1 + sin^2(2π w_D))
/// ```
///
/// Global minimum `U* = 0` at `x* = (1, ..., 1)`; many local minima.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Levy;

impl<F: Float, const D: usize> Potential<F, D> for Levy {
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        SlicePotential::value_and_gradient(self, x, grad)
    }
}

impl<F: Float> SlicePotential<F> for Levy {
    // Always inlined, so that the fixed-size impl's loops know their length.
    #[inline(always)]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        let n = x.len().min(grad.len());
        if n == 0 {
            return F::ZERO;
        }
        let quarter = F::from_f64(0.25);
        let ten = F::from_f64(10.0);
        let pi = F::PI;
        let w = |xi: F| F::ONE + (xi - F::ONE) * quarter;
        // dU/dx_i = dU/dw_i / 4.
        let (s1, c1) = (pi * w(x[0])).fast_sin_cos();
        let mut u = s1 * s1;
        grad.fill(F::ZERO);
        grad[0] = F::TWO * pi * s1 * c1 * quarter;
        for i in 0..n {
            let wi = w(x[i]);
            let d = wi - F::ONE;
            let (term, dterm) = if i + 1 < n {
                let (s, c) = (pi * wi + F::ONE).fast_sin_cos();
                let bracket = F::ONE + ten * s * s;
                (
                    d * d * bracket,
                    F::TWO * d * bracket + d * d * ten * F::TWO * s * c * pi,
                )
            } else {
                let (s, c) = (F::TWO * pi * wi).fast_sin_cos();
                let bracket = F::ONE + s * s;
                (
                    d * d * bracket,
                    F::TWO * d * bracket + d * d * F::TWO * s * c * F::TWO * pi,
                )
            };
            u += term;
            grad[i] += dterm * quarter;
        }
        u
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for Levy {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    fn global_minimiser(&self) -> [F; D] {
        [F::ONE; D]
    }
}

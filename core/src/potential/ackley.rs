//! Ackley's function: a nearly flat outer region riddled with local minima
//! around one deep funnel.

use super::traits::{KnownMinimum, Potential, SlicePotential};
use crate::float::Float;

/// Ackley's function with the usual constants `(20, 0.2, 2π)`:
///
/// ```text
/// U(x) = 20 (1 - exp(-0.2 r)) + e (1 - exp(-q)),
/// r = |x| / sqrt(D),   q = (1/D) sum_i (1 - cos(2π x_i))
/// ```
///
/// which is the textbook `-20 exp(-0.2 r) - exp((1/D) sum cos(2π x_i)) + 20 + e`
/// written without cancellation (`1 - cos(2π x) = 2 sin^2(π x)`, and
/// `expm1`), so it is accurate near the minimum. Global minimum `U* = 0` at
/// `x* = 0`, where `U` has a cone-shaped kink: the gradient returned there
/// is 0 (the subgradient of least norm).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ackley;

impl<F: Float, const D: usize> Potential<F, D> for Ackley {
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        SlicePotential::value_and_gradient(self, x, grad)
    }
}

impl<F: Float> SlicePotential<F> for Ackley {
    // Always inlined, so that the fixed-size impl's loops know their length.
    #[inline(always)]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        let (twenty, fifth) = (F::from_f64(20.0), F::from_f64(0.2));
        let e = F::from_f64(core::f64::consts::E);
        let d = F::from_u64(x.len() as u64);
        let (mut norm2, mut omc) = (F::ZERO, F::ZERO);
        for (&xi, gi) in x.iter().zip(grad.iter_mut()) {
            let (s, c) = (F::PI * xi).fast_sin_cos();
            norm2 += xi * xi;
            omc += F::TWO * s * s;
            // sin(2π x_i), scaled below.
            *gi = F::TWO * s * c;
        }
        let r = (norm2 / d).sqrt();
        let q = omc / d;
        let outer = (-fifth * r).exp();
        let inner = (-q).exp();
        // d/dx_i: 4 exp(-0.2 r) x_i / (D r) + 2π e exp(-q) sin(2π x_i) / D.
        let radial = if r > F::ZERO {
            F::from_f64(4.0) * outer / (d * r)
        } else {
            F::ZERO
        };
        let wave = F::TWO * F::PI * e * inner / d;
        for (&xi, gi) in x.iter().zip(grad.iter_mut()) {
            *gi = radial * xi + wave * *gi;
        }
        twenty * -(-fifth * r).expm1() + e * -(-q).expm1()
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for Ackley {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    fn global_minimiser(&self) -> [F; D] {
        [F::ZERO; D]
    }
}

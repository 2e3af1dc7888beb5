//! The isotropic quadratic: its Gibbs law is Gaussian, the exact case for
//! the moment tests.

use super::traits::{KnownMinimum, Potential, SlicePotential};
use crate::error::{Error, finite, positive};
use crate::float::Float;

/// The isotropic quadratic `U(x) = (k/2) |x - m|^2` with stiffness `k > 0`.
///
/// Its Gibbs law `exp(-a U)` is `N(m, I / (a k))`, and every sampler's step
/// is linear in the state, so the moments of long runs can be checked
/// exactly. Global minimum `U* = 0` at `x* = m`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadratic<F, const D: usize> {
    stiffness: F,
    centre: [F; D],
}

impl<F: Float, const D: usize> Quadratic<F, D> {
    /// `k` finite and > 0, `m` finite.
    pub fn new(stiffness: F, centre: [F; D]) -> Result<Self, Error> {
        let stiffness = positive("stiffness", stiffness)?;
        for &m in &centre {
            finite("centre", m)?;
        }
        Ok(Self { stiffness, centre })
    }

    /// The stiffness `k`.
    pub fn stiffness(&self) -> F {
        self.stiffness
    }
}

impl<F: Float, const D: usize> Potential<F, D> for Quadratic<F, D> {
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        SlicePotential::value_and_gradient(self, x, grad)
    }
}

/// Of dimension `D`: a run of another dimension is refused.
impl<F: Float, const D: usize> SlicePotential<F> for Quadratic<F, D> {
    // Always inlined, so that the fixed-size impl's loops know their length.
    #[inline(always)]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        // Sum (k r) r rather than k |r|^2: with a tiny k and a huge r the
        // latter is 0 * inf = NaN, the former the finite true value.
        let mut kr2 = F::ZERO;
        for ((gi, &xi), &mi) in grad.iter_mut().zip(x).zip(&self.centre) {
            let r = xi - mi;
            *gi = self.stiffness * r;
            kr2 += *gi * r;
        }
        F::HALF * kr2
    }

    fn dimension(&self) -> Option<usize> {
        Some(D)
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for Quadratic<F, D> {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    fn global_minimiser(&self) -> [F; D] {
        self.centre
    }
}

//! OLA, the paper's overdamped baseline: Euler–Maruyama on the overdamped
//! Langevin dynamics.

use rand_core::Rng;

use super::traits::{ChainState, Kernel, Sampler, StepMoments};
use crate::error::{Error, INVERSE_TEMPERATURE, in_range, positive};
use crate::float::Float;
use crate::lockstep::{LANES, Xoshiro256Lanes};

/// Parameters of [`Ola`]: rate `alpha` and step `h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OlaParams<F> {
    /// Rate `alpha > 0` (the paper's code uses 1).
    pub alpha: F,
    /// Step size `h > 0`.
    pub h: F,
}

impl<F: Float> OlaParams<F> {
    /// The paper's setting (`alpha = 1`) at step `h`.
    pub fn paper(h: F) -> Self {
        Self { alpha: F::ONE, h }
    }
}

/// Overdamped Langevin, Euler–Maruyama:
/// `x' = x - alpha h ∇U(x) + sqrt(2 alpha h / a) xi`, `xi ~ N(0, I)`.
/// One standard normal per coordinate; the velocity is not used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ola<F> {
    params: OlaParams<F>,
    drift: F,
}

impl<F: Float> Ola<F> {
    /// Validates the parameters (each finite and > 0).
    pub fn new(params: OlaParams<F>) -> Result<Self, Error> {
        let alpha = positive("alpha", params.alpha)?;
        let h = positive("h", params.h)?;
        let drift = alpha * h;
        if !drift.is_finite() {
            return Err(Error::DegenerateCoefficients);
        }
        Ok(Self { params, drift })
    }

    /// The paper's setting at step `h` ([`OlaParams::paper`]).
    pub fn paper(h: F) -> Result<Self, Error> {
        Self::new(OlaParams::paper(h))
    }

    /// The parameters.
    pub fn params(&self) -> OlaParams<F> {
        self.params
    }
}

impl<F: Float> Sampler<F> for Ola<F> {
    type Kernel = OlaKernel<F>;

    fn at(&self, a: F) -> Result<OlaKernel<F>, Error> {
        let a = positive("a", a)?;
        in_range("a", a, INVERSE_TEMPERATURE)?;
        let noise = (F::TWO * self.drift / a).sqrt();
        if !noise.is_finite() {
            return Err(Error::DegenerateCoefficients);
        }
        Ok(OlaKernel {
            a,
            drift: self.drift,
            noise,
        })
    }
}

/// The step of [`Ola`] at one inverse temperature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OlaKernel<F> {
    a: F,
    drift: F,
    noise: F,
}

impl<F: Float> Kernel<F> for OlaKernel<F> {
    #[inline]
    fn inverse_temperature(&self) -> F {
        self.a
    }

    /// `y` is carried unchanged.
    fn moments(&self, x: F, y: F, g: F) -> StepMoments<F> {
        StepMoments {
            mean_x: x - self.drift * g,
            mean_y: y,
            var_x: self.noise * self.noise,
            cov_xy: F::ZERO,
            var_y: F::ZERO,
        }
    }

    #[inline]
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [F; D],
        _y: &mut [F; D],
        grad: &[F; D],
        rng: &mut R,
    ) {
        for (xi, &gi) in x.iter_mut().zip(grad) {
            let z = F::standard_normal(rng);
            *xi = *xi - self.drift * gi + self.noise * z;
        }
    }

    /// Coordinate by coordinate, every chain's normal in lockstep.
    #[inline]
    fn step_lanes<const D: usize>(
        &self,
        mut chains: [ChainState<'_, [F; D]>; LANES],
        rng: &mut Xoshiro256Lanes,
    ) {
        // The arrays' fixed length spares the bounds checks of the slice
        // version: the same operations on the same values.
        for i in 0..D {
            let z = F::standard_normal_lanes(rng);
            for (chain, &zl) in chains.iter_mut().zip(&z) {
                chain.x[i] = chain.x[i] - self.drift * chain.grad[i] + self.noise * zl;
            }
        }
    }

    #[inline]
    fn step_slice<R: Rng + ?Sized>(&self, x: &mut [F], _y: &mut [F], grad: &[F], rng: &mut R) {
        for (xi, &gi) in x.iter_mut().zip(grad) {
            let z = F::standard_normal(rng);
            *xi = *xi - self.drift * gi + self.noise * z;
        }
    }

    /// [`step_lanes`](Kernel::step_lanes) on slices: the same draws and
    /// updates.
    #[inline]
    fn step_lanes_slice(&self, chains: [ChainState<'_, [F]>; LANES], rng: &mut Xoshiro256Lanes) {
        let d = chains[0].x.len();
        let mut parts = chains.map(|c| (c.x, c.grad));
        for i in 0..d {
            let z = F::standard_normal_lanes(rng);
            for ((x, grad), &zl) in parts.iter_mut().zip(&z) {
                if let (Some(xi), Some(&gi)) = (x.get_mut(i), grad.get(i)) {
                    *xi = *xi - self.drift * gi + self.noise * zl;
                }
            }
        }
    }
}

//! ULA, the paper's underdamped baseline: HRLA's exact step without the
//! position's own gradient term and noise.

use super::ou::OuKernel;
use super::traits::Sampler;
use crate::error::Error;
use crate::float::Float;

/// Parameters of [`Ula`]: `b`, `alpha`, `h` as for
/// [`HrlaParams`](crate::HrlaParams).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UlaParams<F> {
    /// Inverse temperature of the velocity, `b > 0`.
    pub b: F,
    /// Friction `alpha > 0`.
    pub alpha: F,
    /// Step size `h > 0`.
    pub h: F,
}

impl<F: Float> UlaParams<F> {
    /// The paper's setting (`alpha = 1`, `b = 10`) at step `h`.
    pub fn paper(h: F) -> Self {
        Self {
            b: F::from_f64(10.0),
            alpha: F::ONE,
            h,
        }
    }
}

/// Underdamped Langevin with the exact OU step and frozen gradient:
/// `dX = Y dt`, `dY = (-gamma ∇U - alpha Y) dt + sqrt(2 sy2) dB`, which is
/// HRLA with `beta = 0` and `sx2 = 0`. Two standard normals per coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ula<F> {
    params: UlaParams<F>,
    untempered: OuKernel<F>,
}

impl<F: Float> Ula<F> {
    /// Validates the parameters (each finite and > 0) and precomputes the
    /// step's coefficients that do not depend on `a`.
    pub fn new(params: UlaParams<F>) -> Result<Self, Error> {
        let untempered = OuKernel::untempered(params.b, params.alpha, F::ZERO, params.h)?;
        Ok(Self { params, untempered })
    }

    /// The paper's setting at step `h` ([`UlaParams::paper`]).
    pub fn paper(h: F) -> Result<Self, Error> {
        Self::new(UlaParams::paper(h))
    }

    /// The parameters.
    pub fn params(&self) -> UlaParams<F> {
        self.params
    }
}

impl<F: Float> Sampler<F> for Ula<F> {
    type Kernel = OuKernel<F>;

    #[inline]
    fn at(&self, a: F) -> Result<OuKernel<F>, Error> {
        self.untempered.at(a)
    }
}

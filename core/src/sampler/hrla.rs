//! HRLA, the paper's method: the exact step of the high-resolution
//! Langevin dynamics with the gradient frozen over each step.

use super::ou::OuKernel;
use super::traits::Sampler;
use crate::error::{Error, positive};
use crate::float::Float;

/// Parameters of [`Hrla`]: inverse temperature `b` of the velocity,
/// friction `alpha`, gradient weight `beta` and step `h`.
///
/// The remaining coefficients of the dynamics are derived, at each inverse
/// temperature `a`, so that `mu^{a,b}(x, y) ∝ exp(-a U(x) - b |y|^2 / 2)`
/// is invariant by construction: `gamma = a / b`, `sx2 = beta / a`,
/// `sy2 = alpha / b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HrlaParams<F> {
    /// Inverse temperature of the velocity, `b > 0`.
    pub b: F,
    /// Friction `alpha > 0`.
    pub alpha: F,
    /// Weight of the gradient in the position equation, `beta > 0`.
    pub beta: F,
    /// Step size `h > 0`.
    pub h: F,
}

impl<F: Float> HrlaParams<F> {
    /// The paper's experimental setting (`alpha = beta = 1`, `b = 10`) at
    /// step `h`.
    pub fn paper(h: F) -> Self {
        Self {
            b: F::from_f64(10.0),
            alpha: F::ONE,
            beta: F::ONE,
            h,
        }
    }
}

/// High-resolution Langevin: the exact Gaussian step of
///
/// ```text
/// dX = (-beta ∇U(X) + Y) dt + sqrt(2 sx2) dB^x
/// dY = (-gamma ∇U(X) - alpha Y) dt + sqrt(2 sy2) dB^y
/// ```
///
/// with the gradient frozen over each step (the crate docs give the mean and
/// covariance). Two standard normals per coordinate.
///
/// # Example
///
/// ```
/// use hrla::{Hrla, Kernel, Sampler};
///
/// let step = Hrla::paper(0.01_f64)?.at(4.0)?;
/// let m = step.moments(1.0, 0.0, 0.5);
/// assert!(m.mean_x < 1.0 && m.var_x > 0.0);
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hrla<F> {
    params: HrlaParams<F>,
    untempered: OuKernel<F>,
}

impl<F: Float> Hrla<F> {
    /// Validates the parameters (each finite and > 0) and precomputes the
    /// step's coefficients that do not depend on `a`.
    pub fn new(params: HrlaParams<F>) -> Result<Self, Error> {
        let beta = positive("beta", params.beta)?;
        let untempered = OuKernel::untempered(params.b, params.alpha, beta, params.h)?;
        Ok(Self { params, untempered })
    }

    /// The paper's setting at step `h` ([`HrlaParams::paper`]).
    pub fn paper(h: F) -> Result<Self, Error> {
        Self::new(HrlaParams::paper(h))
    }

    /// The parameters.
    pub fn params(&self) -> HrlaParams<F> {
        self.params
    }
}

impl<F: Float> Sampler<F> for Hrla<F> {
    type Kernel = OuKernel<F>;

    #[inline]
    fn at(&self, a: F) -> Result<OuKernel<F>, Error> {
        self.untempered.at(a)
    }
}

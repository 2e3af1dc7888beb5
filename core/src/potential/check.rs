//! A finite-difference check of a potential's gradient, for users' own
//! potentials.

use super::traits::Potential;
use crate::error::{Error, finite};
use crate::float::Float;

/// The worst coordinate of a gradient check: see [`check_gradient`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GradientCheck<F> {
    /// The coordinate with the largest error.
    pub coordinate: usize,
    /// The potential's own `dU/dx_j` there.
    pub analytic: F,
    /// The central difference `(U(x + t e_j) - U(x - t e_j)) / 2t`.
    pub numeric: F,
    /// `|analytic - numeric| / max(1, |analytic|, |numeric|)`: an absolute
    /// error for small derivatives, a relative one for large.
    pub error: F,
}

/// Compares `∇U(x)` with central differences of `U`, coordinate by
/// coordinate, and returns the worst. The step is `t = eps^(1/3)
/// max(1, |x_j|)`, which balances truncation and rounding: for a correct
/// gradient of a smooth `U` of moderate curvature the error is around
/// `eps^(2/3)` (1e-10 in f64, 1e-5 in f32); a wrong gradient shows errors
/// of order 1.
///
/// ```
/// use hrla::{FnPotential, check_gradient};
///
/// let right = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| {
///     *g = [2.0 * x[0], 3.0 * x[1] * x[1]];
///     x[0] * x[0] + x[1] * x[1] * x[1]
/// });
/// let wrong = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| {
///     *g = [2.0 * x[0], 2.0 * x[1]]; // should be 3 x_2^2
///     x[0] * x[0] + x[1] * x[1] * x[1]
/// });
/// assert!(check_gradient(&right, &[0.5, -1.5])?.error < 1e-8);
/// let bad = check_gradient(&wrong, &[0.5, -1.5])?;
/// assert_eq!(bad.coordinate, 1);
/// assert!(bad.error > 0.1);
/// # Ok::<(), hrla::Error>(())
/// ```
///
/// Errors: [`Error::NotFinite`] if `x`, `U`, the gradient or a difference
/// is not finite
/// (`D = 0` gives a check with no error).
pub fn check_gradient<F: Float, const D: usize, P: Potential<F, D> + ?Sized>(
    potential: &P,
    x: &[F; D],
) -> Result<GradientCheck<F>, Error> {
    for &v in x {
        finite("x", v)?;
    }
    let mut grad = [F::ZERO; D];
    finite("U(x)", potential.value_and_gradient(x, &mut grad))?;
    let cbrt_eps = F::from_f64(if F::MANTISSA_DIGITS > 24 {
        6.055_454_452_393_343e-6
    } else {
        4.921_566_601_151_848e-3
    });
    let mut worst = GradientCheck {
        coordinate: 0,
        analytic: F::ZERO,
        numeric: F::ZERO,
        error: F::ZERO,
    };
    let mut probe = *x;
    for j in 0..D {
        let scale = if x[j].abs() > F::ONE {
            x[j].abs()
        } else {
            F::ONE
        };
        let t = cbrt_eps * scale;
        probe[j] = x[j] + t;
        let up = potential.value(&probe);
        probe[j] = x[j] - t;
        let down = potential.value(&probe);
        probe[j] = x[j];
        // The step actually taken, exact in floating point.
        let width = (x[j] + t) - (x[j] - t);
        let numeric = finite("difference quotient", (up - down) / width)?;
        let analytic = finite("gradient", grad[j])?;
        let mut denominator = F::ONE;
        for v in [analytic.abs(), numeric.abs()] {
            if v > denominator {
                denominator = v;
            }
        }
        let error = (analytic - numeric).abs() / denominator;
        if error > worst.error || j == 0 {
            worst = GradientCheck {
                coordinate: j,
                analytic,
                numeric,
                error,
            };
        }
    }
    Ok(worst)
}

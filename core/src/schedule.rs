//! Inverse-temperature schedules `k -> a_k` (annealing).

use crate::error::{Error, positive};
use crate::float::Float;

/// The inverse temperature `a_k` used by the step from iterate `k` to `k + 1`.
///
/// The optimiser passes each value to
/// [`Sampler::set_inverse_temperature`](crate::Sampler::set_inverse_temperature),
/// which rejects a non-finite or non-positive one with an error; the built-in
/// schedules validate their parameters so that they never produce one.
pub trait Schedule<F: Float> {
    /// `a_k`.
    fn inverse_temperature(&self, k: u64) -> F;
}

fn count(name: &'static str, steps: u64) -> Result<u64, Error> {
    if steps == 0 {
        Err(Error::Count {
            name,
            value: 0,
            max: usize::MAX,
        })
    } else {
        Ok(steps)
    }
}

/// A constant inverse temperature: no annealing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Constant<F>(F);

impl<F: Float> Constant<F> {
    /// `a` finite and > 0.
    pub fn new(a: F) -> Result<Self, Error> {
        positive("a", a).map(Self)
    }
}

impl<F: Float> Schedule<F> for Constant<F> {
    #[inline]
    fn inverse_temperature(&self, _k: u64) -> F {
        self.0
    }
}

/// The paper's linear annealing (spec section 6, sign corrected):
/// `a_k = a_low + (a_high - a_low) k / K` for `k < K`, then `a_high`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linear<F> {
    a_low: F,
    a_high: F,
    steps: u64,
}

impl<F: Float> Linear<F> {
    /// `a_low`, `a_high` finite and > 0 (either order); `steps = K >= 1`.
    pub fn new(a_low: F, a_high: F, steps: u64) -> Result<Self, Error> {
        Ok(Self {
            a_low: positive("a_low", a_low)?,
            a_high: positive("a_high", a_high)?,
            steps: count("steps", steps)?,
        })
    }
}

impl<F: Float> Schedule<F> for Linear<F> {
    #[inline]
    fn inverse_temperature(&self, k: u64) -> F {
        if k >= self.steps {
            return self.a_high;
        }
        self.a_low + (self.a_high - self.a_low) * F::from_u64(k) / F::from_u64(self.steps)
    }
}

/// Geometric annealing: `a_k = a_low (a_high / a_low)^(k / K)` for `k < K`,
/// then `a_high`. Spends more steps at low `a` (exploration) than
/// [`Linear`] and raises `a` fastest at the end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometric<F> {
    a_low: F,
    a_high: F,
    log_ratio: F,
    steps: u64,
}

impl<F: Float> Geometric<F> {
    /// `a_low`, `a_high` finite and > 0 (either order); `steps = K >= 1`.
    pub fn new(a_low: F, a_high: F, steps: u64) -> Result<Self, Error> {
        let a_low = positive("a_low", a_low)?;
        let a_high = positive("a_high", a_high)?;
        Ok(Self {
            a_low,
            a_high,
            log_ratio: a_high.ln() - a_low.ln(),
            steps: count("steps", steps)?,
        })
    }
}

impl<F: Float> Schedule<F> for Geometric<F> {
    #[inline]
    fn inverse_temperature(&self, k: u64) -> F {
        if k >= self.steps {
            return self.a_high;
        }
        self.a_low * (self.log_ratio * F::from_u64(k) / F::from_u64(self.steps)).exp()
    }
}

/// Any function `k -> a_k` as a schedule.
///
/// ```
/// use hrla::{FnSchedule, Schedule};
///
/// // Logarithmic cooling, a_k = ln(e + k).
/// let s = FnSchedule(|k: u64| libm::log(core::f64::consts::E + k as f64));
/// assert_eq!(s.inverse_temperature(0), 1.0);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct FnSchedule<G>(pub G);

impl<F: Float, G: Fn(u64) -> F> Schedule<F> for FnSchedule<G> {
    #[inline]
    fn inverse_temperature(&self, k: u64) -> F {
        (self.0)(k)
    }
}

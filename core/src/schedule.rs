//! Inverse-temperature schedules `k -> a_k` (annealing).

use crate::error::{Error, positive};
use crate::float::Float;

/// The inverse temperature `a_k` used by the step from iterate `k` to `k + 1`.
///
/// The optimiser passes each value to
/// [`Sampler::at`](crate::Sampler::at), which rejects a non-finite or non-positive one with an error; the built-in
/// schedules validate their parameters so that they never produce one.
pub trait Schedule<F: Float> {
    /// `a_k`.
    fn inverse_temperature(&self, k: u64) -> F;

    /// The number of steps over which the schedule changes `a`, when it
    /// has one (`K` for [`Linear`] and [`Geometric`]): a run's step budget
    /// by default, and never less than it.
    fn length(&self) -> Option<u64> {
        None
    }
}

fn count(name: &'static str, steps: u64) -> Result<u64, Error> {
    if steps == 0 {
        Err(Error::Zero { name })
    } else {
        Ok(steps)
    }
}

/// `v` clamped to the interval spanned by `p` and `q` (either order): keeps
/// an interpolation's rounding from stepping past an end, where `inf` or a
/// non-positive value could lie.
#[inline]
fn between<F: Float>(v: F, p: F, q: F) -> F {
    let (lo, hi) = if p <= q { (p, q) } else { (q, p) };
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
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

/// A plain `f32` or `f64` is a constant schedule: `a_k = a` for every `k`
/// (the sampler refuses it when it is not finite and > 0).
impl<F: Float> Schedule<F> for F {
    #[inline]
    fn inverse_temperature(&self, _k: u64) -> F {
        *self
    }
}

/// The paper's linear annealing (`docs/SPEC.md` section 6, sign corrected):
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
    fn length(&self) -> Option<u64> {
        Some(self.steps)
    }

    #[inline]
    fn inverse_temperature(&self, k: u64) -> F {
        if k >= self.steps {
            return self.a_high;
        }
        // k/K first: (a_high - a_low) k could overflow for huge a_high.
        let frac = F::from_u64(k) / F::from_u64(self.steps);
        between(
            self.a_low + (self.a_high - self.a_low) * frac,
            self.a_low,
            self.a_high,
        )
    }
}

/// Geometric annealing: `a_k = a_low (a_high / a_low)^(k / K)` for `k < K`,
/// then `a_high` (computed as `exp` of the interpolated logarithms, exact at
/// both ends). Spends more steps at low `a` (exploration) than
/// [`Linear`] and raises `a` fastest at the end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometric<F> {
    a_low: F,
    a_high: F,
    ln_low: F,
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
            ln_low: a_low.ln(),
            log_ratio: a_high.ln() - a_low.ln(),
            steps: count("steps", steps)?,
        })
    }
}

impl<F: Float> Schedule<F> for Geometric<F> {
    fn length(&self) -> Option<u64> {
        Some(self.steps)
    }

    #[inline]
    fn inverse_temperature(&self, k: u64) -> F {
        if k >= self.steps {
            return self.a_high;
        }
        if k == 0 {
            return self.a_low;
        }
        // Interpolate the logarithms: a_low (a_high/a_low)^t could overflow
        // in the ratio even when both ends are representable.
        let frac = F::from_u64(k) / F::from_u64(self.steps);
        between(
            (self.ln_low + self.log_ratio * frac).exp(),
            self.a_low,
            self.a_high,
        )
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

/// One of the built-in schedules, chosen at run time (see
/// [`AnySampler`](crate::AnySampler)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnySchedule<F> {
    /// No annealing.
    Constant(Constant<F>),
    /// Linear annealing.
    Linear(Linear<F>),
    /// Geometric annealing.
    Geometric(Geometric<F>),
}

impl<F: Float> Schedule<F> for AnySchedule<F> {
    fn length(&self) -> Option<u64> {
        match self {
            Self::Constant(s) => s.length(),
            Self::Linear(s) => s.length(),
            Self::Geometric(s) => s.length(),
        }
    }

    #[inline]
    fn inverse_temperature(&self, k: u64) -> F {
        match self {
            Self::Constant(s) => s.inverse_temperature(k),
            Self::Linear(s) => s.inverse_temperature(k),
            Self::Geometric(s) => s.inverse_temperature(k),
        }
    }
}

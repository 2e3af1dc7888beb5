//! When a run ends: budgets, a target, a stall rule, and why it ended.

use core::fmt;

use crate::error::{Error, finite};
use crate::float::Float;

/// The stopping rules of a run, all optional and combinable: the run ends
/// at the first that holds. Built by chaining:
///
/// ```
/// use hrla::Stop;
///
/// let stop = Stop::new().evaluations(125_000).target(1e-6).stall(2_000, 1e-12);
/// # let _ = stop;
/// ```
///
/// Checked before every step: a run never starts a step that would exceed
/// its evaluation budget (one evaluation per live chain and step; the
/// initial points count too).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stop<F> {
    pub(crate) steps: Option<u64>,
    pub(crate) evaluations: Option<u64>,
    pub(crate) target: Option<F>,
    pub(crate) stall: Option<(u64, F)>,
}

impl<F: Float> Stop<F> {
    /// No rule: a run then needs a schedule with a length (which becomes
    /// its step budget) or an observer that stops it.
    pub fn new() -> Self {
        Self {
            steps: None,
            evaluations: None,
            target: None,
            stall: None,
        }
    }

    /// At most `k` steps.
    pub fn steps(mut self, k: u64) -> Self {
        self.steps = Some(k);
        self
    }

    /// At most `n` potential-and-gradient evaluations in all.
    pub fn evaluations(mut self, n: u64) -> Self {
        self.evaluations = Some(n);
        self
    }

    /// As soon as the best value is `<= target`.
    pub fn target(mut self, target: F) -> Self {
        self.target = Some(target);
        self
    }

    /// When the best value has not fallen by more than `tolerance` over the
    /// last `window` steps.
    pub fn stall(mut self, window: u64, tolerance: F) -> Self {
        self.stall = Some((window, tolerance));
        self
    }

    /// Whether any rule is set.
    pub fn is_empty(&self) -> bool {
        self.steps.is_none()
            && self.evaluations.is_none()
            && self.target.is_none()
            && self.stall.is_none()
    }

    /// Checks every rule's numbers.
    /// The first rule that holds for a run at `iteration` with
    /// `evaluations` spent, `live` chains, its best value `best` and its
    /// last improvement beyond the stall tolerance at `stall_since`.
    pub(crate) fn holds(
        &self,
        best: F,
        iteration: u64,
        evaluations: u64,
        live: u64,
        stall_since: u64,
    ) -> Option<Termination>
    where
        F: Float,
    {
        if self.target.is_some_and(|t| best <= t) {
            Some(Termination::Target)
        } else if self.steps.is_some_and(|k| iteration >= k) {
            Some(Termination::Steps)
        } else if self
            .evaluations
            .is_some_and(|b| evaluations.saturating_add(live) > b)
        {
            Some(Termination::Evaluations)
        } else if self
            .stall
            .is_some_and(|(window, _)| iteration - stall_since >= window)
        {
            Some(Termination::Stalled)
        } else {
            None
        }
    }

    pub(crate) fn validate(&self) -> Result<(), Error> {
        if self.steps == Some(0) {
            return Err(Error::Zero {
                name: "step budget",
            });
        }
        if self.evaluations == Some(0) {
            return Err(Error::Zero {
                name: "evaluation budget",
            });
        }
        if let Some(t) = self.target {
            finite("target", t)?;
        }
        if let Some((window, tolerance)) = self.stall {
            if window == 0 {
                return Err(Error::Zero {
                    name: "stall window",
                });
            }
            if !(tolerance.is_finite() && tolerance >= F::ZERO) {
                return Err(Error::Negative {
                    name: "stall tolerance",
                    value: tolerance.to_f64(),
                });
            }
        }
        Ok(())
    }
}

/// Why a run ended normally. (A run whose chains all diverged, or whose
/// potential is unbounded below, ends with an [`Error`] instead.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Termination {
    /// The step budget was spent.
    Steps,
    /// The next step would have exceeded the evaluation budget.
    Evaluations,
    /// The best value reached the target.
    Target,
    /// The best value did not improve by more than the tolerance over the
    /// stall window.
    Stalled,
    /// The observer asked to stop.
    Observer,
    /// [`Auto`](crate::Auto)'s convergence rule held: its best did not
    /// fall over the rule's window of rounds (see
    /// [`Problem::converge`](crate::Problem::converge)).
    Converged,
}

impl fmt::Display for Termination {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Termination::Steps => "step budget spent",
            Termination::Evaluations => "evaluation budget spent",
            Termination::Target => "target reached",
            Termination::Stalled => "stalled",
            Termination::Observer => "stopped by the observer",
            Termination::Converged => "converged",
        })
    }
}

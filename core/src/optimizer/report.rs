//! What a run tells its caller: progress while it runs, a report at the end.

use core::fmt;

use super::chain::Best;
use super::stop::Termination;
use crate::float::Float;

/// The outcome of a run that ended normally. The best point itself is
/// [`Optimizer::best`](crate::Optimizer::best).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report<F> {
    /// The best value found, `U` at [`Optimizer::best`](crate::Optimizer::best).
    pub value: F,
    /// The chain that found it.
    pub chain: usize,
    /// The iterate at which it was found.
    pub found_at: u64,
    /// Steps done.
    pub iterations: u64,
    /// Potential-and-gradient evaluations, the initial ones included.
    pub evaluations: u64,
    /// Chains that diverged (frozen, excluded from the best).
    pub diverged_chains: usize,
    /// Chains in the run.
    pub chains: usize,
    /// Why the run ended.
    pub termination: Termination,
}

impl<F: Float> fmt::Display for Report<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: best U = {} (chain {}, iteration {}) after {} steps and {} evaluations; \
             {} of {} chains diverged",
            self.termination,
            self.value,
            self.chain,
            self.found_at,
            self.iterations,
            self.evaluations,
            self.diverged_chains,
            self.chains,
        )
    }
}

/// What an observer sees (see
/// [`Optimizer::run_with`](crate::Optimizer::run_with)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress<'a, F, const D: usize> {
    /// Steps done.
    pub iteration: u64,
    /// Evaluations so far.
    pub evaluations: u64,
    /// The running best.
    pub best: &'a Best<F, D>,
    /// Whether the last step improved the running best.
    pub improved: bool,
    /// The inverse temperature of the last step.
    pub inverse_temperature: F,
    /// Chains diverged so far.
    pub diverged_chains: usize,
}

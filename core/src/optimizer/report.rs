//! What a run tells its caller: progress while it runs, a report at the end.

use core::fmt;

use super::stop::Termination;
use super::store::{Best, Store};
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

/// What a step did and where the run stands: what
/// [`Optimizer::step`](crate::Optimizer::step) returns and what an
/// observer of [`Optimizer::run_with`](crate::Optimizer::run_with) sees,
/// the chains included (an observer that draws them, tracks the best
/// chain now, or stops a run whose chains ran away reads them here).
#[derive(Clone, Copy)]
pub struct Progress<'a, F> {
    /// Steps done.
    pub iteration: u64,
    /// Evaluations so far.
    pub evaluations: u64,
    /// The running best.
    pub best: Best<'a, F>,
    /// Whether the last step improved the running best.
    pub improved: bool,
    /// The inverse temperature of the last step.
    pub inverse_temperature: F,
    /// Chains diverged so far.
    pub diverged_chains: usize,
    /// The chains.
    pub chains: &'a dyn Store<F>,
}

/// Every field but the chains, which are the run's own.
impl<F: fmt::Debug> fmt::Debug for Progress<'_, F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Progress")
            .field("iteration", &self.iteration)
            .field("evaluations", &self.evaluations)
            .field("best", &self.best)
            .field("improved", &self.improved)
            .field("inverse_temperature", &self.inverse_temperature)
            .field("diverged_chains", &self.diverged_chains)
            .finish_non_exhaustive()
    }
}

/// Equal when every field but the chains is: two runs at the same point.
impl<F: PartialEq> PartialEq for Progress<'_, F> {
    fn eq(&self, other: &Self) -> bool {
        (
            self.iteration,
            self.evaluations,
            self.improved,
            self.diverged_chains,
        ) == (
            other.iteration,
            other.evaluations,
            other.improved,
            other.diverged_chains,
        ) && self.best == other.best
            && self.inverse_temperature == other.inverse_temperature
    }
}

/// When the observer of [`Optimizer::run_with`](crate::Optimizer::run_with)
/// is called: a value, so that every front end's cadence is the loop's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Observe {
    /// Never (what [`Optimizer::run`](crate::Optimizer::run) does).
    Never,
    /// After every step.
    Always,
    /// After every step that improves the running best.
    NewBest,
    /// After every `n`-th step (never for `n = 0`).
    Every(u64),
    /// After every `n`-th step and every step that improves the running
    /// best.
    EveryAndNewBest(u64),
}

impl Observe {
    /// Whether the observer is called after step `k`, which `improved`
    /// the running best or not.
    pub fn wants(self, k: u64, improved: bool) -> bool {
        let every = |n: u64| n > 0 && k.is_multiple_of(n);
        match self {
            Observe::Never => false,
            Observe::Always => true,
            Observe::NewBest => improved,
            Observe::Every(n) => every(n),
            Observe::EveryAndNewBest(n) => improved || every(n),
        }
    }
}

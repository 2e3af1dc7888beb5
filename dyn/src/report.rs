//! Why a run ended, in the forms the front ends show, and what an observer
//! sees of a run in progress.

use hrla::Termination;

/// Every termination's name, in the order of [`termination_code`] (from
/// 1): what Python's `status` indexes.
pub const TERMINATIONS: [&str; 6] = [
    "Steps",
    "Evaluations",
    "Target",
    "Stalled",
    "Observer",
    "Converged",
];

/// The kernel's variant name of a termination: `"Steps"`, `"Target"`, ...
pub fn termination_name(t: Termination) -> &'static str {
    TERMINATIONS[index(t)]
}

fn index(t: Termination) -> usize {
    match t {
        Termination::Steps => 0,
        Termination::Evaluations => 1,
        Termination::Target => 2,
        Termination::Stalled => 3,
        Termination::Observer => 4,
        Termination::Converged => 5,
    }
}

/// The code of a stopping reason as a number (for a flat buffer): 0 while
/// the run goes on, then 1 step budget, 2 evaluation budget, 3 target, 4
/// stalled, 5 observer, 6 converged.
pub fn termination_code(t: Option<Termination>) -> f64 {
    t.map_or(0.0, |t| (index(t) + 1) as f64)
}

/// What an observer of a run sees, whatever the dimension: the best point
/// borrowed from the run's own storage (no copy per step).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress<'a> {
    /// Steps done ([`crate::auto::solve`]: rounds done).
    pub iteration: u64,
    /// Evaluations so far, all counted.
    pub evaluations: u64,
    /// The best value so far.
    pub value: f64,
    /// The best point so far (`U` there is `value`).
    pub x: &'a [f64],
    /// The run's dimension.
    pub dim: usize,
    /// The run's chains.
    pub chains: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_codes_follow_one_order() {
        let all = [
            Termination::Steps,
            Termination::Evaluations,
            Termination::Target,
            Termination::Stalled,
            Termination::Observer,
        ];
        for (i, t) in all.into_iter().enumerate() {
            assert_eq!(termination_name(t), format!("{t:?}"));
            assert_eq!(termination_code(Some(t)), (i + 1) as f64);
        }
        assert_eq!(termination_code(None), 0.0);
    }
}

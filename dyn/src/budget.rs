//! How a sampler's run shares an evaluation budget between the chains'
//! steps and the polish of the best point at its end: one rule for every
//! front end.

/// A sampler run's shares of its budget, in evaluations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Split {
    /// The step budget that leaves the polish its share (none: the
    /// evaluation budget alone ends the sampling, as without a polish).
    pub steps: Option<u64>,
    /// The evaluations of the polish: the caller's, or a quarter of the
    /// budget up to [`POLISH`].
    pub polish: u64,
}

/// The polish's default share, at most: L-BFGS converges within it on
/// every benchmark problem.
pub const POLISH: u64 = 1000;

/// The split of `budget` evaluations for `chains` chains (one evaluation
/// each per step, and one more for a caller's start when `x0`), with the
/// polish's `polish` evaluations or the default share; `None` when the
/// polish leaves no whole step.
pub fn split(budget: u64, chains: usize, polish: Option<u64>, x0: bool) -> Option<Split> {
    let polish = polish.unwrap_or(POLISH.min(budget / 4));
    if polish == 0 {
        return Some(Split {
            steps: None,
            polish,
        });
    }
    let n = chains.max(1) as u64;
    let steps = budget.checked_sub(polish + n + u64::from(x0))? / n;
    (steps >= 1).then_some(Split {
        steps: Some(steps),
        polish,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_polish_gets_its_share_and_the_steps_the_rest() {
        // A quarter of 2 000 is 500: (2 000 - 500 - 10) / 10 steps.
        assert_eq!(
            split(2_000, 10, None, false),
            Some(Split {
                steps: Some(149),
                polish: 500
            })
        );
        // The share is capped; a start of the caller's costs one more.
        assert_eq!(split(125_000, 10, None, true).unwrap().polish, POLISH);
        assert_eq!(
            split(125_000, 10, None, true).unwrap().steps,
            Some((125_000 - 1_000 - 11) / 10)
        );
        assert_eq!(
            split(100, 10, Some(0), false),
            Some(Split {
                steps: None,
                polish: 0
            })
        );
        assert_eq!(split(100, 10, Some(95), false), None);
        assert_eq!(split(20, 10, Some(5), false), None);
    }
}

//! How a run shares its budget, one rule for every front end: a sampler's
//! run between the chains' steps and the polish of the best point at its
//! end ([`split`]); a run without a gradient between `Auto`, on gradients
//! by finite differences, and the gradient-free ensemble after it
//! ([`auto_share`]).

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

/// `Auto`'s share of a run without a gradient, in calls of `U` per
/// coordinate, before the ensemble takes the rest: `ENSEMBLE_CALLS`, or
/// [`ENSEMBLE_GRADIENTS`] `d` where that is more (from `d = 7` on). On
/// bbob `Auto`'s quenches lead up to about `100 d` calls and the ensemble
/// from there (docs/QUALITY.md, "Black-box: COCO bbob").
pub const ENSEMBLE_CALLS: u64 = 100;
/// See [`ENSEMBLE_CALLS`]: in many dimensions, enough gradients for a
/// quench of `O(d)` iterations to end.
pub const ENSEMBLE_GRADIENTS: u64 = 15;

/// `Auto`'s budget, in gradients, in a run of `budget` gradients of `cost`
/// calls of `U` each (`1 + d` for forward differences), `spare` of them
/// kept back by the caller, whose ensemble takes the rest; `chains` is
/// `Auto`'s (none: [`hrla::Auto::chains_for`] its share). At least two
/// gradients a chain, and never more than `budget`. A soft budget
/// ([`hrla::Problem::soft_budget`]): the quench of `Auto`'s best start
/// may finish past it, since one cut short leaves the ensemble a basin
/// half searched (on bbob, 5.4 points of the share of targets at `200 d`
/// calls in d = 5; docs/QUALITY.md, "Black-box: COCO bbob"). `None` where the
/// ensemble takes no part: `d` beyond [`Ensemble::MAX_DIM`](crate::Ensemble::MAX_DIM).
pub fn auto_share(
    budget: u64,
    d: usize,
    cost: u64,
    spare: u64,
    chains: Option<usize>,
) -> Option<u64> {
    if d > crate::Ensemble::MAX_DIM {
        return None;
    }
    let d = d as u64;
    let calls = ENSEMBLE_CALLS.max(ENSEMBLE_GRADIENTS * d) * d;
    let share = (calls / cost.max(1)).saturating_sub(spare).max(1);
    let chains = chains.unwrap_or_else(|| hrla::Auto::<f64>::chains_for(share)) as u64;
    Some(budget.min(share.max(2 * chains)))
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

    #[test]
    fn auto_takes_its_share_of_a_run_without_a_gradient() {
        // d = 4, forward differences (5 calls a gradient), one kept back:
        // 100 d = 400 calls, 80 gradients, 79 with the spare out.
        assert_eq!(auto_share(25_000, 4, 5, 1, None), Some(79));
        // From d = 7 on, 15 d calls per coordinate: d = 10, 1 500 calls.
        assert_eq!(auto_share(1_000_000, 10, 11, 1, None), Some(1_500 / 11 - 1));
        // At least two gradients a chain, never beyond the budget.
        assert_eq!(auto_share(25_000, 1, 1_000, 1, Some(8)), Some(16));
        assert_eq!(auto_share(10, 4, 5, 1, None), Some(10));
        // Beyond the ensemble's dimensions, Auto runs alone.
        assert_eq!(auto_share(25_000, 21, 22, 1, None), None);
    }
}

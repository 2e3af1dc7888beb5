//! Curious simulated annealing (Guilmeau, Chouzenoux and Elvira 2021):
//! SMC-SA's population, reweighted and resampled along the logarithmic
//! schedule's Boltzmann laws, moved by FSA's kernel (acceptance
//! `1 / (1 + beta Δ+)` at the fast schedule's temperature), so that it
//! inherits FSA's convergence rate while resampling favours low members.

use hrla::SlicePotential;

use super::moves::{Acceptance, RandomWalk};
use super::population::{Peer, Population};
use super::schedule;

/// CSA with its random-walk proposal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Csa {
    /// The random-walk proposal.
    pub walk: RandomWalk,
}

impl Peer for Csa {
    fn iterate<P: SlicePotential<f64>>(&self, pop: &mut Population, potential: &P, k: u64) {
        pop.resample(schedule::logarithmic(k) - schedule::logarithmic(k - 1));
        pop.move_all(potential, self.walk, schedule::fast(k), Acceptance::Fast);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::peers::testing::{assert_iterates_as, full_walk};
    use hrla::Rastrigin;

    /// CSA's iteration k resamples along the logarithmic schedule
    /// (`dbeta = ln((k + 1) / k)`), then makes FSA's move at
    /// `beta = (k + 1) ln(k + 1)`; resampling never evaluates `U`.
    #[test]
    fn csa_is_logarithmic_resampling_then_fsa() {
        let walk = full_walk(0.2);
        assert_iterates_as(Csa { walk }, 20, |pop, k| {
            pop.resample(((k + 1) as f64 / k as f64).ln());
            let m = (k + 1) as f64;
            pop.move_all(&Rastrigin, walk, m * m.ln(), Acceptance::Fast);
        });
    }
}

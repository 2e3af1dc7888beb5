//! Sequential Monte Carlo simulated annealing (Zhou and Chen 2013): the
//! population tracks the Boltzmann laws `pi_k ∝ exp(-U / T_k)` of the
//! logarithmic schedule by reweighting with `pi_k / pi_{k-1}`, resampling,
//! and one SA move (which leaves `pi_k` invariant) per member.

use hrla::SlicePotential;

use super::moves::{Acceptance, RandomWalk};
use super::population::{Peer, Population};
use super::schedule;

/// SMC-SA with its random-walk proposal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmcSa {
    /// The random-walk proposal.
    pub walk: RandomWalk,
}

impl Peer for SmcSa {
    fn iterate<P: SlicePotential<f64>>(&self, pop: &mut Population, potential: &P, k: u64) {
        let beta = schedule::logarithmic(k);
        pop.resample(beta - schedule::logarithmic(k - 1));
        pop.move_all(potential, self.walk, beta, Acceptance::Metropolis);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::peers::Sa;
    use crate::peers::testing::{assert_iterates_as, full_walk};
    use hrla::{Point, Rastrigin};

    /// From one point every weight is equal, so whatever ancestors are
    /// drawn the first SMC-SA iteration is SA's, bit for bit (resampling
    /// draws from its own stream, never a member's). Every iteration is
    /// the reweighting by `ln((k + 1) / k)` followed by SA's move.
    #[test]
    fn smc_sa_is_resampling_then_sa() {
        let walk = full_walk(0.3);
        let mut start = Point::new([1.0; 10]).unwrap();
        let mut smc = Population::new(&Rastrigin, &mut start, 25, 10, 4);
        let mut sa = smc.clone();
        SmcSa { walk }.iterate(&mut smc, &Rastrigin, 1);
        Sa { walk }.iterate(&mut sa, &Rastrigin, 1);
        assert_eq!(smc.positions(), sa.positions());
        assert_iterates_as(SmcSa { walk }, 20, |pop, k| {
            pop.resample(((k + 1) as f64 / k as f64).ln());
            let beta = ((k + 1) as f64).ln();
            pop.move_all(&Rastrigin, walk, beta, Acceptance::Metropolis);
        });
    }
}

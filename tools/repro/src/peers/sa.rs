//! Simulated annealing (Haario and Saksman 1991): every member makes one
//! Metropolis random-walk move per iteration at the logarithmic schedule's
//! temperature. With a population, `N` independent SA chains.

use hrla::SlicePotential;

use super::moves::{Acceptance, RandomWalk};
use super::population::{Peer, Population};
use super::schedule;

/// SA with its random-walk proposal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sa {
    /// The random-walk proposal.
    pub walk: RandomWalk,
}

impl Peer for Sa {
    fn iterate<P: SlicePotential<f64>>(&self, pop: &mut Population, potential: &P, k: u64) {
        pop.move_all(
            potential,
            self.walk,
            schedule::logarithmic(k),
            Acceptance::Metropolis,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::peers::testing::{assert_iterates_as, full_walk};
    use hrla::{Gaussian, Rastrigin};

    /// SA's iteration k is the Metropolis random walk at `beta = ln(k + 1)`,
    /// and a member's chain does not depend on how many run beside it
    /// (independent chains, one stream each).
    #[test]
    fn sa_is_metropolis_on_the_logarithmic_schedule_and_members_are_independent() {
        let sa = Sa {
            walk: full_walk(0.25),
        };
        assert_iterates_as(sa, 30, |pop, k| {
            let beta = (k as f64 + 1.0).ln();
            pop.move_all(&Rastrigin, full_walk(0.25), beta, Acceptance::Metropolis);
        });
        let mut start = Gaussian::new([3.0; 10], 1.0).unwrap();
        let mut many = Population::new(&Rastrigin, &mut start, 40, 10, 5);
        let mut few = Population::new(&Rastrigin, &mut start, 7, 10, 5);
        for k in 1..=30 {
            sa.iterate(&mut many, &Rastrigin, k);
            sa.iterate(&mut few, &Rastrigin, k);
        }
        assert_eq!(&many.positions()[..7 * 10], few.positions());
    }
}

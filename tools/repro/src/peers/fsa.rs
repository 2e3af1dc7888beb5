//! Fast simulated annealing (Rubenthaler, Rydén and Wiktorsson 2009):
//! SA's random walk with the acceptance `1 / (1 + beta Δ+)` and the fast
//! schedule `T_k = 1 / ((k + 1) ln(k + 1))`. With a population, `N`
//! independent FSA chains.

use hrla::SlicePotential;

use super::moves::{Acceptance, RandomWalk};
use super::population::{Peer, Population};
use super::schedule;

/// FSA with its random-walk proposal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fsa {
    /// The random-walk proposal.
    pub walk: RandomWalk,
}

impl Peer for Fsa {
    fn iterate<P: SlicePotential<f64>>(&self, pop: &mut Population, potential: &P, k: u64) {
        pop.move_all(potential, self.walk, schedule::fast(k), Acceptance::Fast);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::peers::testing::{assert_iterates_as, full_walk};
    use hrla::{Point, Rastrigin};

    fn fast_beta(k: u64) -> f64 {
        (k as f64 + 1.0) * (k as f64 + 1.0).ln()
    }

    /// FSA's iteration k is the fast rule at `beta = (k + 1) ln(k + 1)`;
    /// from the same start and streams it moves more often than a
    /// Metropolis walk at FSA's own (cold) temperatures would.
    #[test]
    fn fsa_is_the_fast_rule_on_the_fast_schedule() {
        let fsa = Fsa {
            walk: full_walk(0.25),
        };
        assert_iterates_as(fsa, 40, |pop, k| {
            pop.move_all(&Rastrigin, full_walk(0.25), fast_beta(k), Acceptance::Fast);
        });
        let mut start = Point::new([1.0; 10]).unwrap();
        let mut fast = Population::new(&Rastrigin, &mut start, 30, 10, 8);
        let mut cold_metropolis = fast.clone();
        let mut moved = [0usize; 2];
        for k in 1..=40 {
            let before = (
                fast.positions().to_vec(),
                cold_metropolis.positions().to_vec(),
            );
            fsa.iterate(&mut fast, &Rastrigin, k);
            let (walk, beta) = (full_walk(0.25), fast_beta(k));
            cold_metropolis.move_all(&Rastrigin, walk, beta, Acceptance::Metropolis);
            moved[0] += count_moves(&before.0, fast.positions(), 10);
            moved[1] += count_moves(&before.1, cold_metropolis.positions(), 10);
        }
        assert!(moved[0] > moved[1], "{moved:?}");
    }

    /// Members (points of `d` coordinates) that moved.
    fn count_moves(before: &[f64], after: &[f64], d: usize) -> usize {
        before
            .chunks_exact(d)
            .zip(after.chunks_exact(d))
            .filter(|(x, y)| x != y)
            .count()
    }
}

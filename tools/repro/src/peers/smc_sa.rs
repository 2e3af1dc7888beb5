//! Sequential Monte Carlo simulated annealing (Zhou and Chen 2013): the
//! population tracks the Boltzmann laws `pi_k ∝ exp(-U / T_k)` of the
//! logarithmic schedule by reweighting with `pi_k / pi_{k-1}`, resampling,
//! and one SA move (which leaves `pi_k` invariant) per member.

use hrla::Potential;

use super::moves::{Acceptance, RandomWalk};
use super::{Peer, Population, schedule};

/// SMC-SA with its random-walk proposal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmcSa {
    /// The random-walk proposal.
    pub walk: RandomWalk,
}

impl Peer for SmcSa {
    fn iterate<P: Potential<f64, D>, const D: usize>(
        &self,
        pop: &mut Population<D>,
        potential: &P,
        k: u64,
    ) {
        let beta = schedule::logarithmic(k);
        pop.resample(beta - schedule::logarithmic(k - 1));
        pop.move_all(potential, self.walk, beta, Acceptance::Metropolis);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::peers::moves::{RandomWalk, Scope};

    fn walk(sd: f64) -> RandomWalk {
        RandomWalk {
            sd,
            scope: Scope::Full,
        }
    }
    use crate::peers::Sa;
    use hrla::{Gaussian, Point, Rastrigin};

    /// From one point every weight is equal, so whatever ancestors are
    /// drawn the first SMC-SA iteration is SA's, bit for bit (resampling
    /// draws from its own stream, never a member's). Later iterations are
    /// the reweighting by `ln((k + 1) / k)` followed by SA's move.
    #[test]
    fn smc_sa_is_resampling_then_sa() {
        let mut start = Point::new([1.0; 10]).unwrap();
        let mut smc = Population::<10>::new(&Rastrigin, &mut start, 25, 4);
        let mut sa = smc.clone();
        SmcSa { walk: walk(0.3) }.iterate(&mut smc, &Rastrigin, 1);
        Sa { walk: walk(0.3) }.iterate(&mut sa, &Rastrigin, 1);
        assert_eq!(smc.positions(), sa.positions());

        let mut start = Gaussian::new([0.0; 10], 1.0).unwrap();
        let mut a = Population::<10>::new(&Rastrigin, &mut start, 25, 4);
        let mut b = a.clone();
        for k in 1..=20 {
            SmcSa { walk: walk(0.3) }.iterate(&mut a, &Rastrigin, k);
            b.resample(((k + 1) as f64 / k as f64).ln());
            b.move_all(
                &Rastrigin,
                walk(0.3),
                ((k + 1) as f64).ln(),
                Acceptance::Metropolis,
            );
        }
        assert_eq!(a.positions(), b.positions());
        assert_eq!(a.evaluations(), 25 * 21);
    }
}

//! Curious simulated annealing (Guilmeau, Chouzenoux and Elvira 2021):
//! SMC-SA's population, reweighted and resampled along the logarithmic
//! schedule's Boltzmann laws, moved by FSA's kernel (acceptance
//! `1 / (1 + beta Δ+)` at the fast schedule's temperature), so that it
//! inherits FSA's convergence rate while resampling favours low members.

use hrla::Potential;

use super::moves::{Acceptance, RandomWalk};
use super::{Peer, Population, schedule};

/// CSA with its random-walk proposal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Csa {
    /// The random-walk proposal.
    pub walk: RandomWalk,
}

impl Peer for Csa {
    fn iterate<P: Potential<f64, D>, const D: usize>(
        &self,
        pop: &mut Population<D>,
        potential: &P,
        k: u64,
    ) {
        pop.resample(schedule::logarithmic(k) - schedule::logarithmic(k - 1));
        pop.move_all(potential, self.walk, schedule::fast(k), Acceptance::Fast);
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
    use hrla::{Gaussian, Rastrigin};

    /// CSA's iteration k resamples along the logarithmic schedule
    /// (`dbeta = ln((k + 1) / k)`), then makes FSA's move at
    /// `beta = (k + 1) ln(k + 1)`; resampling never evaluates `U`.
    #[test]
    fn csa_is_logarithmic_resampling_then_fsa() {
        let mut start = Gaussian::new([0.5; 10], 1.0).unwrap();
        let mut a = Population::<10>::new(&Rastrigin, &mut start, 30, 12);
        let mut b = a.clone();
        for k in 1..=20 {
            Csa { walk: walk(0.2) }.iterate(&mut a, &Rastrigin, k);
            b.resample(((k + 1) as f64 / k as f64).ln());
            let m = (k + 1) as f64;
            b.move_all(&Rastrigin, walk(0.2), m * m.ln(), Acceptance::Fast);
        }
        assert_eq!(a.positions(), b.positions());
        assert_eq!(a.values(), b.values());
        assert_eq!(a.evaluations(), 30 * 21);
    }
}

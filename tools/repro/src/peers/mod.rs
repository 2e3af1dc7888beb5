//! The simulated-annealing peers of the paper's T3, run rather than cited:
//! SA (Haario and Saksman 1991), fast SA (Rubenthaler, Rydén and
//! Wiktorsson 2009), sequential Monte Carlo SA (Zhou and Chen 2013) and
//! curious SA (Guilmeau, Chouzenoux and Elvira 2021), set up as Guilmeau et
//! al. compared them: a population of `N` samples, every one proposing a
//! Gaussian random-walk move once per iteration (one evaluation of `U`,
//! never of `∇U`).
//!
//! - [`Population`]: the samples, their values and their random streams.
//! - [`Peer`]: one iteration of a method; [`Sa`], [`Fsa`], [`SmcSa`] and
//!   [`Csa`] are the four methods, [`PeerKind`] names them.
//! - [`schedule`]: the logarithmic and the fast cooling.
//! - [`moves`]: the random-walk proposal and the two acceptance rules.
//! - [`resample`]: the SMC reweighting and multinomial resampling.
//!
//! Streams follow the tool's scheme (see [`crate::seed`]): member `c` of run
//! `i` draws its start, proposals and acceptances from
//! `Xoshiro256PlusPlus::seed_from_u64(chain_seed(run_seed, c))`, as HRLA's
//! chain `c` does, so both start from the same points; the resampling of
//! SMC-SA and CSA draws from its own stream, `chain_seed(run_seed,
//! u64::MAX)`, which no member uses.

mod csa;
mod fsa;
pub mod moves;
mod population;
pub mod resample;
mod sa;
pub mod schedule;
mod smc_sa;

pub use csa::Csa;
pub use fsa::Fsa;
pub use moves::{RandomWalk, Scope};
pub use population::{Peer, Population};
pub use sa::Sa;
pub use smc_sa::SmcSa;

use hrla::SlicePotential;

/// The proposal when none is given: the random walk `y = x + 0.25 z`,
/// `z ~ N(0, I)`, of every coordinate.
pub const DEFAULT_WALK: RandomWalk = RandomWalk {
    sd: 0.25,
    scope: Scope::Full,
};

/// The four peers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum PeerKind {
    /// Simulated annealing, Metropolis acceptance, logarithmic cooling.
    Sa,
    /// Fast SA: acceptance `1 / (1 + beta Δ)`, fast cooling.
    Fsa,
    /// Sequential Monte Carlo SA: resampling, then SA's move.
    SmcSa,
    /// Curious SA: SMC-SA's resampling, then FSA's move.
    Csa,
}

impl PeerKind {
    /// Every peer, in the paper's order.
    pub const ALL: [PeerKind; 4] = [PeerKind::Sa, PeerKind::Fsa, PeerKind::SmcSa, PeerKind::Csa];

    /// `SA`, `FSA`, `SMC-SA`, `CSA`.
    pub fn label(self) -> &'static str {
        match self {
            PeerKind::Sa => "SA",
            PeerKind::Fsa => "FSA",
            PeerKind::SmcSa => "SMC-SA",
            PeerKind::Csa => "CSA",
        }
    }

    /// The cooling, in words, for the tables.
    pub fn schedule_label(self) -> &'static str {
        match self {
            PeerKind::Sa => "T = 1/ln(k+1)",
            PeerKind::Fsa => "T = 1/((k+1) ln(k+1))",
            PeerKind::SmcSa => "T = 1/ln(k+1), resampled",
            PeerKind::Csa => "T = 1/((k+1) ln(k+1)), resampled on 1/ln(k+1)",
        }
    }

    /// The mean running best at `k = 50` and `k = 500` that the paper's
    /// Table 3 copied from Guilmeau et al. (10-D Rastrigin, N = 250, start
    /// `(1, ..., 1)`, M = 50).
    pub fn paper_means(self) -> [(u64, f64); 2] {
        let (k50, k500) = match self {
            PeerKind::Sa => (3.29, 2.52),
            PeerKind::Fsa => (3.36, 2.64),
            PeerKind::SmcSa => (3.26, 2.62),
            PeerKind::Csa => (3.23, 2.47),
        };
        [(50, k50), (500, k500)]
    }

    /// The copied mean at iterate `k`, if the paper has one.
    pub fn paper_mean(self, k: u64) -> Option<f64> {
        self.paper_means()
            .into_iter()
            .find(|&(at, _)| at == k)
            .map(|(_, m)| m)
    }

    /// The method with the proposal `walk`.
    pub fn peer(self, walk: RandomWalk) -> AnyPeer {
        match self {
            PeerKind::Sa => AnyPeer::Sa(Sa { walk }),
            PeerKind::Fsa => AnyPeer::Fsa(Fsa { walk }),
            PeerKind::SmcSa => AnyPeer::SmcSa(SmcSa { walk }),
            PeerKind::Csa => AnyPeer::Csa(Csa { walk }),
        }
    }
}

/// Any of the four methods behind one type.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnyPeer {
    /// [`Sa`].
    Sa(Sa),
    /// [`Fsa`].
    Fsa(Fsa),
    /// [`SmcSa`].
    SmcSa(SmcSa),
    /// [`Csa`].
    Csa(Csa),
}

impl Peer for AnyPeer {
    fn iterate<P: SlicePotential<f64>>(&self, pop: &mut Population, potential: &P, k: u64) {
        match self {
            AnyPeer::Sa(p) => p.iterate(pop, potential, k),
            AnyPeer::Fsa(p) => p.iterate(pop, potential, k),
            AnyPeer::SmcSa(p) => p.iterate(pop, potential, k),
            AnyPeer::Csa(p) => p.iterate(pop, potential, k),
        }
    }
}

/// What the methods' tests share: a full random walk, and the check that a
/// method's iterations are exactly a given sequence of population steps.
#[cfg(test)]
pub(crate) mod testing {
    use super::*;
    use hrla::{Gaussian, Rastrigin};

    /// The full random walk with standard deviation `sd`.
    pub fn full_walk(sd: f64) -> RandomWalk {
        RandomWalk {
            sd,
            scope: Scope::Full,
        }
    }

    /// Runs `peer` for iterations `1..=k` on 30 members of 10-D Rastrigin
    /// started from N(0.5·1, I), and `by_hand` on a copy; both must end
    /// bit for bit equal, after `N (k + 1)` evaluations each.
    pub fn assert_iterates_as(
        peer: impl Peer,
        k: u64,
        mut by_hand: impl FnMut(&mut Population, u64),
    ) {
        let mut start = Gaussian::new([0.5; 10], 1.0).unwrap();
        let mut a = Population::new(&Rastrigin, &mut start, 30, 10, 12);
        let mut b = a.clone();
        for i in 1..=k {
            peer.iterate(&mut a, &Rastrigin, i);
            by_hand(&mut b, i);
        }
        assert_eq!(a.positions(), b.positions());
        assert_eq!(a.values(), b.values());
        assert_eq!(a.evaluations(), 30 * (k + 1));
        assert_eq!(b.evaluations(), a.evaluations());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hrla::{Point, Potential, Rastrigin};

    /// One coordinate at a time, so that 20 members escape `(1, ..., 1)`
    /// within 60 iterations (a full-dimensional step from that local
    /// minimum is almost always refused).
    const ESCAPING: RandomWalk = RandomWalk {
        sd: 0.5,
        scope: Scope::Coordinate,
    };

    fn run(kind: PeerKind, seed: u64, k: u64) -> Population {
        let mut pop = Population::new(
            &Rastrigin,
            &mut Point::new([1.0; 10]).unwrap(),
            20,
            10,
            seed,
        );
        let peer = kind.peer(ESCAPING);
        for i in 1..=k {
            peer.iterate(&mut pop, &Rastrigin, i);
        }
        pop
    }

    /// Every peer is a function of its seed, improves on the start
    /// (`U = 10` at `(1, ..., 1)`) and evaluates `U` once per member and
    /// iteration.
    #[test]
    fn peers_are_reproducible_and_improve_on_the_start() {
        for kind in PeerKind::ALL {
            let a = run(kind, 1, 60);
            let b = run(kind, 1, 60);
            let c = run(kind, 2, 60);
            assert_eq!(a.positions(), b.positions(), "{}", kind.label());
            assert_ne!(a.positions(), c.positions(), "{}", kind.label());
            assert!(a.best_now() < 10.0, "{}", kind.label());
            assert_eq!(a.evaluations(), 20 * 61);
            for (x, &v) in a.positions().chunks_exact(10).zip(a.values()) {
                assert_eq!(v, Rastrigin.value(&<[f64; 10]>::try_from(x).unwrap()));
            }
        }
    }

    #[test]
    fn paper_figures_are_at_50_and_500() {
        assert_eq!(PeerKind::Csa.paper_mean(500), Some(2.47));
        assert_eq!(PeerKind::Sa.paper_mean(50), Some(3.29));
        assert_eq!(PeerKind::Sa.paper_mean(10), None);
    }
}

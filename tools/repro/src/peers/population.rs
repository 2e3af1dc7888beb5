//! A peer's population ([`Population`]) and one iteration of a method
//! ([`Peer`]): what the four methods and their moves share.

use hrla::rand_core::SeedableRng;
use hrla::{SlicePotential, Start, chain_seed};
use rand_xoshiro::Xoshiro256PlusPlus;

/// The stream index of the resampling generator (no member has it).
const RESAMPLER_STREAM: u64 = u64::MAX;

/// One iteration of a peer method.
pub trait Peer {
    /// Moves `pop` from iterate `k - 1` to iterate `k >= 1`: every member
    /// proposes once, one evaluation of `potential` each.
    fn iterate<P: SlicePotential<f64>>(&self, pop: &mut Population, potential: &P, k: u64);
}

/// The `N` samples of a peer in dimension `d`, their values of `U`, one
/// random stream per member and one for resampling, and the count of
/// evaluations of `U`.
#[derive(Clone, Debug)]
pub struct Population {
    /// The dimension.
    pub(super) d: usize,
    /// The members' points, `N x d` row-major.
    pub(super) xs: Vec<f64>,
    pub(super) values: Vec<f64>,
    pub(super) rngs: Vec<Xoshiro256PlusPlus>,
    pub(super) resampler: Xoshiro256PlusPlus,
    pub(super) evaluations: u64,
    /// A proposal and the gradient the potential writes beside its value
    /// (which no peer reads), `d` each.
    pub(super) proposal: Vec<f64>,
    pub(super) gradient: Vec<f64>,
}

impl Population {
    /// `n` members of dimension `d` started by `start` (member `c` from
    /// its own stream `chain_seed(seed, c)`), each evaluated once.
    pub fn new<P: SlicePotential<f64>, S: Start<f64>>(
        potential: &P,
        start: &mut S,
        n: usize,
        d: usize,
        seed: u64,
    ) -> Self {
        let mut rngs: Vec<_> = (0..n as u64)
            .map(|c| Xoshiro256PlusPlus::seed_from_u64(chain_seed(seed, c)))
            .collect();
        let mut xs = vec![0.0; n * d];
        for (c, (x, rng)) in xs.chunks_exact_mut(d).zip(&mut rngs).enumerate() {
            start.initial_point(c, rng, x);
        }
        let mut gradient = vec![0.0; d];
        let values = xs
            .chunks_exact(d)
            .map(|x| potential.value_and_gradient(x, &mut gradient))
            .collect();
        Self {
            d,
            xs,
            values,
            rngs,
            resampler: Xoshiro256PlusPlus::seed_from_u64(chain_seed(seed, RESAMPLER_STREAM)),
            evaluations: n as u64,
            proposal: vec![0.0; d],
            gradient,
        }
    }

    /// The dimension `d`.
    pub fn dim(&self) -> usize {
        self.d
    }

    /// The number of members `N`.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether the population has no member.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The members' positions, `N x d` row-major.
    pub fn positions(&self) -> &[f64] {
        &self.xs
    }

    /// The members' values of `U`.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// `min_n U(x_k^n)`, the best member now (`+inf` when empty).
    pub fn best_now(&self) -> f64 {
        self.values.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// Evaluations of `U` so far (`N` at the start, `N` per iteration).
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }
}

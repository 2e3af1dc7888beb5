//! Workloads shared by the criterion benchmarks (`benches/kernel.rs`) and
//! the peer comparison (`peers/`): the exact loops whose time is reported.

pub mod problems;

use hrla::rand_core::Rng;
use hrla::{
    AnyKernel, AnySampler, Builder, Chain, Chains, Float, Gaussian, Kernel, LANES, Linear,
    Optimizer, Potential, Rastrigin, Sampler, SamplerKind, Schedule, Xoshiro256Lanes,
};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

/// One of the three samplers at the paper's setting (h = 0.01).
pub fn paper<F: Float>(kind: SamplerKind) -> AnySampler<F> {
    AnySampler::paper(kind, F::from_f64(0.01)).expect("valid")
}

/// Its step at the paper's `a = 4`.
pub fn paper_kernel<F: Float>(kind: SamplerKind) -> AnyKernel<F> {
    paper(kind).at(constant()).expect("valid")
}

/// The shared generator of the [`Bare`] loops (the optimiser's chains have
/// their own, seeded by the kernel).
pub fn rng(seed: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(seed)
}

/// The optimiser of the benchmarks: every chain in one `Vec` it owns.
pub type Swarm<F, C, const D: usize> =
    Optimizer<F, Rastrigin, AnySampler<F>, C, Chains<F, Vec<Chain<F, D>>, D>>;

/// Algorithm 1 on D-dimensional Rastrigin from the paper's start, with a
/// schedule, over `chains` chains on the heap seeded with `seed` (each
/// chain draws from its own generator, `hrla::chain_seed(seed, c)`): every
/// [`step`](Optimizer::step) evaluates `U` and `∇U` and updates the running
/// best. No stopping rule: the benchmarks step it as long as they like (a
/// schedule with a length gets it as a budget, which only `run` reads).
pub fn optimizer<F: Float, C: Schedule<F>, const D: usize>(
    method: SamplerKind,
    schedule: C,
    chains: usize,
    seed: u64,
) -> Swarm<F, C, D> {
    let start = Gaussian::new([F::from_f64(3.0); D], F::from_f64(10f64.sqrt())).expect("valid");
    let storage = (0..chains).map(|_| Chain::new()).collect::<Vec<_>>();
    Builder::new(Rastrigin, paper(method), schedule, start)
        .seed(seed)
        .build(storage)
        .expect("valid")
}

/// The constant schedule of the paper's setting, `a = 4`.
pub fn constant<F: Float>() -> F {
    F::from_f64(4.0)
}

/// A linear annealing from 4 to 4.4 over 10^9 steps: `a_k` changes at
/// every step (so the sampler refreshes its coefficients every step) while
/// the dynamics stay those of the constant benchmark (a = 4), so the two
/// differ only by the refresh.
pub fn slow_linear<F: Float>() -> Linear<F> {
    Linear::new(F::from_f64(4.0), F::from_f64(4.4), 1_000_000_000).expect("valid")
}

/// Chains without the optimiser: position, velocity, gradient. Unlike the
/// optimiser's chains, which each own a generator, the bare chains all draw
/// from one shared generator passed to every call: they measure the
/// sampler's step (and the floor's parts) alone, as a plain sampling loop
/// would run it, and their random stream need not be the optimiser's.
pub struct Bare<F, const D: usize> {
    x: Vec<[F; D]>,
    y: Vec<[F; D]>,
    g: Vec<[F; D]>,
}

impl<F: Float, const D: usize> Bare<F, D> {
    /// `chains` chains at the paper's start.
    pub fn new(chains: usize, rng: &mut Xoshiro256PlusPlus) -> Self {
        let mut x = Vec::with_capacity(chains);
        for _ in 0..chains {
            let mut p = [F::from_f64(3.0); D];
            for v in &mut p {
                *v += F::from_f64(10f64.sqrt()) * F::standard_normal(rng);
            }
            x.push(p);
        }
        let g = x
            .iter()
            .map(|p| {
                let mut g = [F::ZERO; D];
                Potential::<F, D>::gradient(&Rastrigin, p, &mut g);
                g
            })
            .collect();
        Self {
            y: vec![[F::ZERO; D]; chains],
            x,
            g,
        }
    }

    /// One step of every chain and a gradient evaluation, without `U`: the
    /// sampler alone, as a pure sampling loop would run it.
    #[inline]
    pub fn step<K: Kernel<F>>(&mut self, kernel: &K, rng: &mut Xoshiro256PlusPlus) {
        for ((x, y), g) in self.x.iter_mut().zip(&mut self.y).zip(&mut self.g) {
            kernel.step(x, y, g, rng);
            Potential::<F, D>::gradient(&Rastrigin, x, g);
        }
    }

    /// The unavoidable work of one step of every chain: `2 D` standard
    /// normals and one value-and-gradient evaluation (the floor). The results
    /// are folded by XOR of their bits, not summed: a chain of dependent
    /// float additions (3-4 cycles each) would itself cost as much as a
    /// normal and inflate the floor.
    #[inline]
    pub fn floor(&mut self, rng: &mut Xoshiro256PlusPlus) -> u64 {
        let mut acc = 0u64;
        for (x, g) in self.x.iter_mut().zip(&mut self.g) {
            for _ in 0..D {
                let (z1, z2) = F::standard_normal_pair(rng);
                acc ^= z1.to_bits_u64() ^ z2.to_bits_u64();
            }
            acc ^= Rastrigin.value_and_gradient(x, g).to_bits_u64();
        }
        acc
    }

    /// The floor with the optimiser's lanes: every group of [`LANES`]
    /// chains draws its `2 D` normals per chain in lockstep from four
    /// generators ([`Xoshiro256Lanes`]), then evaluates each chain (the
    /// unavoidable work of a step in lockstep; a remainder of fewer than
    /// four chains draws nothing).
    #[inline]
    pub fn floor_lanes(&mut self, rng: &mut Xoshiro256Lanes) -> u64 {
        let mut acc = 0u64;
        for (xs, gs) in self
            .x
            .chunks_exact_mut(LANES)
            .zip(self.g.chunks_exact_mut(LANES))
        {
            for _ in 0..D {
                for (z1, z2) in F::standard_normal_pair_lanes(rng) {
                    acc ^= z1.to_bits_u64() ^ z2.to_bits_u64();
                }
            }
            for (x, g) in xs.iter().zip(gs) {
                acc ^= Rastrigin.value_and_gradient(x, g).to_bits_u64();
            }
        }
        acc
    }

    /// The floor's normals alone: `2 D` per chain.
    #[inline]
    pub fn normals(&mut self, rng: &mut Xoshiro256PlusPlus) -> u64 {
        let mut acc = 0u64;
        for _ in 0..self.x.len() * D {
            let (z1, z2) = F::standard_normal_pair(rng);
            acc ^= z1.to_bits_u64() ^ z2.to_bits_u64();
        }
        acc
    }

    /// The floor's value-and-gradient evaluations alone.
    #[inline]
    pub fn value_and_gradient(&mut self) -> u64 {
        let mut acc = 0u64;
        for (x, g) in self.x.iter().zip(&mut self.g) {
            acc ^= Rastrigin.value_and_gradient(x, g).to_bits_u64();
        }
        acc
    }

    /// The random bits of the floor's normals, as the Ziggurat's fast path
    /// draws them: `2 D` `next_u64` per chain for f64, `D` for f32 (whose
    /// pairs of normals split one word).
    #[inline]
    pub fn bits(&mut self, rng: &mut Xoshiro256PlusPlus) -> u64 {
        let words = if core::mem::size_of::<F>() == 8 {
            2 * D
        } else {
            D
        };
        let mut acc = 0u64;
        for _ in 0..self.x.len() * words {
            acc ^= rng.next_u64();
        }
        acc
    }
}

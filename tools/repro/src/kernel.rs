//! The one place the tool meets the kernel's optimiser: one run of a
//! kernel sampler at its run-time dimension `d` ([`KernelRun`]), the start
//! it and the peers draw from ([`RunStart`]), and the bytes of its chains
//! ([`chain_bytes`]).
//!
//! A run is the kernel's optimiser over flat storage of dimension `d`:
//! every `d >= 1`, with the bits of the same run over
//! `Chain<f64, d>`s (the kernel's promise, checked here for several `d`).
//! Everything else in the tool sees only [`KernelRun`]'s few methods.

use hrla::rand_core::{Rng, SeedableRng};
use hrla::{AnySampler, AnySchedule, Builder, FlatChains, Rastrigin, StandardNormal, Start, Stop};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::config::{RunSpec, StartSpec};

/// Each chain's generator (the kernel's, and the peers').
type Generator = Xoshiro256PlusPlus;

/// `N` chains of dimension `d`, in `Vec`s the optimiser owns (on the heap,
/// so T2's 10 000 chains never touch a worker's stack).
type Chains = FlatChains<f64, Generator, Vec<f64>, Vec<u64>, Vec<bool>, Vec<Generator>>;

type Optimizer = hrla::Optimizer<f64, Rastrigin, AnySampler<f64>, AnySchedule<f64>, Chains>;

/// The bytes of one kernel chain in dimension `d`: its floats (position,
/// velocity, gradient and best point, `d` each, and two values), its best
/// iteration, divergence flag and generator; `None` past `usize`. A run of
/// `N` chains holds `N` of them; a peer's member (a point, its value and
/// its generator) is smaller.
pub fn chain_bytes(d: usize) -> Option<usize> {
    Chains::floats(1, d)
        .checked_mul(size_of::<f64>())?
        .checked_add(size_of::<u64>() + size_of::<bool>() + size_of::<Generator>())
}

/// The initial points of a run in any dimension (velocities start at 0):
/// the draws of the kernel's [`hrla::Gaussian`] and [`hrla::Point`],
/// coordinate after coordinate from the chain's own generator. The peers
/// start from it too, so member `c` starts where the kernel's chain `c`
/// does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RunStart {
    /// `x_i = centre + std_dev z_i`, `z_i ~ N(0, 1)`.
    Gaussian {
        /// Every coordinate of the mean.
        centre: f64,
        /// The standard deviation of each coordinate.
        std_dev: f64,
    },
    /// Every chain at `value · 1`.
    Point(f64),
}

impl RunStart {
    /// The start of [`StartSpec`] (checked by [`RunSpec::validate`]).
    pub fn of(spec: StartSpec) -> Self {
        match spec {
            StartSpec::Gaussian { centre, variance } => RunStart::Gaussian {
                centre,
                std_dev: variance.sqrt(),
            },
            StartSpec::Point(v) => RunStart::Point(v),
        }
    }
}

impl Start<f64> for RunStart {
    fn initial_point<R: Rng + ?Sized>(&mut self, _chain: usize, rng: &mut R, x: &mut [f64]) {
        match *self {
            RunStart::Gaussian { centre, std_dev } => {
                for xi in x.iter_mut() {
                    *xi = centre + std_dev * f64::standard_normal(rng);
                }
            }
            RunStart::Point(v) => x.fill(v),
        }
    }
}

/// One run of a kernel sampler: its `N` chains, stepped one iteration at
/// a time.
pub struct KernelRun {
    opt: Optimizer,
}

impl KernelRun {
    /// The run of `spec` seeded with `seed` (see
    /// [`run_seed`](crate::seed::run_seed)): `spec.chains` chains of
    /// dimension `spec.d`, chain `c` drawing its start and its steps from
    /// its own generator (`hrla::chain_seed(seed, c)`), a step budget of
    /// `K = spec.steps` (which a linear schedule's length equals; the
    /// builder checks) and the kernel's running best on the tool's stride.
    pub fn new(spec: &RunSpec, seed: u64) -> Result<Self, hrla::Error> {
        let (schedule, sampler) = spec.kernel_setup()?;
        let (n, d) = (spec.chains, spec.d);
        // The builder seeds every generator; these are placeholders.
        let chains = FlatChains::new(
            d,
            vec![0.0; Chains::floats(n, d)],
            vec![0; n],
            vec![false; n],
            vec![Generator::seed_from_u64(0); n],
        )?;
        let opt = Builder::new(Rastrigin, sampler, schedule, RunStart::of(spec.start))
            .seed(seed)
            .stride(spec.stride)
            .stop(Stop::new().steps(spec.steps))
            .build(chains)?;
        Ok(Self { opt })
    }

    /// One step of every live chain. A run whose chains have all diverged
    /// is not an error for the tool: its remaining iterates have no best
    /// chain (`+inf`, within no tolerance).
    pub fn step(&mut self) -> Result<(), hrla::Error> {
        match self.opt.step() {
            Ok(_) | Err(hrla::Error::AllDiverged { .. }) => Ok(()),
            Err(e) => Err(e),
        }
    }

    /// `min_c U(x_k^c)` over the live chains at the current iterate
    /// (`+inf` when every chain has diverged).
    pub fn best_now(&self) -> f64 {
        self.opt.current_best().map_or(f64::INFINITY, |(_, v)| v)
    }

    /// The kernel's running best (over every iterate on the stride,
    /// iterate 0 included).
    pub fn kernel_best(&self) -> f64 {
        self.opt.best().value
    }

    /// The chains' positions, `N x d` row-major.
    pub fn positions(&self) -> &[f64] {
        self.opt.chains().positions()
    }

    /// Chains diverged so far.
    pub fn diverged_chains(&self) -> usize {
        self.opt.diverged_chains()
    }

    /// Evaluations of `U` and `∇U` so far.
    pub fn evaluations(&self) -> u64 {
        self.opt.evaluations()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{Method, Temperature};
    use crate::seed::run_seed;
    use hrla::{Chain, Gaussian, Point, SamplerKind};

    fn spec(d: usize, start: StartSpec, temperature: Temperature) -> RunSpec {
        RunSpec {
            method: Method::Kernel(SamplerKind::Hrla),
            d,
            h: 0.01,
            chains: 9,
            steps: 60,
            temperature,
            start,
            stride: 1,
            checkpoints: vec![60],
            eps: vec![],
            curve_every: None,
        }
    }

    /// The bits of the positions and of the best chain now at every
    /// iterate `0..=K`.
    type Trace = Vec<(Vec<u64>, u64)>;

    fn bits(x: &[f64], best: f64) -> (Vec<u64>, u64) {
        (x.iter().map(|v| v.to_bits()).collect(), best.to_bits())
    }

    /// The same run over `Chain<f64, D>`s from the kernel's own `Gaussian`
    /// or `Point`: the const-generic path.
    fn const_path<const D: usize>(s: &RunSpec, seed: u64) -> Trace {
        fn trace<const D: usize>(s: &RunSpec, seed: u64, start: impl hrla::Start<f64>) -> Trace {
            let (schedule, sampler) = s.kernel_setup().unwrap();
            let mut opt = Builder::new(Rastrigin, sampler, schedule, start)
                .seed(seed)
                .stride(s.stride)
                .stop(Stop::new().steps(s.steps))
                .build(vec![Chain::<f64, D>::new(); s.chains])
                .unwrap();
            let mut seen = Vec::new();
            for k in 0..=s.steps {
                if k > 0 {
                    match opt.step() {
                        Ok(_) | Err(hrla::Error::AllDiverged { .. }) => {}
                        Err(e) => panic!("{e}"),
                    }
                }
                let x: Vec<f64> = opt.chains().iter().flat_map(|c| *c.x()).collect();
                let best = opt.current_best().map_or(f64::INFINITY, |(_, v)| v);
                seen.push(bits(&x, best));
            }
            seen
        }
        match s.start {
            StartSpec::Gaussian { centre, variance } => {
                let start = Gaussian::new([centre; D], variance.sqrt()).unwrap();
                trace::<D>(s, seed, start)
            }
            StartSpec::Point(v) => trace::<D>(s, seed, Point::new([v; D]).unwrap()),
        }
    }

    fn flat_path(s: &RunSpec, seed: u64) -> Trace {
        let mut run = KernelRun::new(s, seed).unwrap();
        let mut seen = Vec::new();
        for k in 0..=s.steps {
            if k > 0 {
                run.step().unwrap();
            }
            seen.push(bits(run.positions(), run.best_now()));
        }
        seen
    }

    /// A run at `Dyn(d)` is bit for bit the run over `Chain<f64, d>`s, at
    /// every iterate: dimensions of the paper and others (3, 7), both
    /// starts, constant `a` and annealing, a sampler that diverges.
    #[test]
    fn a_run_at_any_dimension_has_the_bits_of_the_const_path() {
        let starts = [
            StartSpec::Gaussian {
                centre: 3.0,
                variance: 10.0,
            },
            StartSpec::Point(1.0),
        ];
        let temperatures = [
            Temperature::Constant(3.0),
            Temperature::Linear {
                low: 0.1,
                high: 4.0,
            },
        ];
        for start in starts {
            for temperature in temperatures {
                for (i, d) in [1, 2, 3, 5, 7, 10, 20, 50, 100].into_iter().enumerate() {
                    let s = spec(d, start, temperature);
                    let seed = run_seed(2025, i as u64);
                    let expected = match d {
                        1 => const_path::<1>(&s, seed),
                        2 => const_path::<2>(&s, seed),
                        3 => const_path::<3>(&s, seed),
                        5 => const_path::<5>(&s, seed),
                        7 => const_path::<7>(&s, seed),
                        10 => const_path::<10>(&s, seed),
                        20 => const_path::<20>(&s, seed),
                        50 => const_path::<50>(&s, seed),
                        _ => const_path::<100>(&s, seed),
                    };
                    assert_eq!(flat_path(&s, seed), expected, "d = {d}, {start:?}");
                }
            }
        }
        let mut diverging = spec(3, starts[0], temperatures[0]);
        diverging.method = Method::Kernel(SamplerKind::Ula);
        diverging.h = 40.0;
        diverging.steps = 400;
        diverging.checkpoints = vec![400];
        let seed = run_seed(1, 0);
        let expected = const_path::<3>(&diverging, seed);
        assert_eq!(expected.last().unwrap().1, f64::INFINITY.to_bits());
        assert_eq!(flat_path(&diverging, seed), expected);
    }

    /// Chain `c` of a run draws from a stream of `(run seed, c)` alone: the
    /// first chains of a run of 5 follow exactly the trajectories of the
    /// first 5 of a run of 69 with the same seed, at constant `a` and
    /// annealing. So the chain count neither shifts any chain's stream
    /// (nor could the order in which the kernel steps them).
    #[test]
    fn a_chain_does_not_depend_on_how_many_run_beside_it() {
        let gaussian = StartSpec::Gaussian {
            centre: 3.0,
            variance: 10.0,
        };
        for temperature in [
            Temperature::Constant(3.0),
            Temperature::Linear {
                low: 0.1,
                high: 4.0,
            },
        ] {
            let with = |chains| RunSpec {
                chains,
                steps: 50,
                checkpoints: vec![50],
                ..spec(10, gaussian, temperature)
            };
            let seed = run_seed(11, 0);
            let mut many = KernelRun::new(&with(69), seed).unwrap();
            let mut few = KernelRun::new(&with(5), seed).unwrap();
            assert_eq!(many.positions()[..50], few.positions()[..]);
            for _ in 0..50 {
                many.step().unwrap();
                few.step().unwrap();
            }
            assert_eq!(many.positions()[..50], few.positions()[..]);
            let other = KernelRun::new(&with(5), run_seed(11, 1)).unwrap();
            assert_ne!(other.positions(), &few.positions()[..50]);
        }
    }

    /// Cross-check of the tool's running best with the kernel's: from
    /// N(3·1, 10 I) the initial points are far worse than anything after a
    /// few hundred steps, so the kernel's best (which includes iterate 0)
    /// must equal the tool's (which does not), at stride 1.
    #[test]
    fn running_best_agrees_with_the_kernel_when_iterate_0_is_not_the_best() {
        let start = StartSpec::Gaussian {
            centre: 3.0,
            variance: 10.0,
        };
        let s = RunSpec {
            chains: 40,
            steps: 300,
            checkpoints: vec![300],
            ..spec(10, start, Temperature::Constant(3.0))
        };
        let mut run = KernelRun::new(&s, run_seed(3, 0)).unwrap();
        let start_best = run.best_now();
        let mut none = [];
        let mut tracker =
            crate::stats::Tracker::new(s.steps, 1, None, &s.checkpoints, &[], 0.0, &mut none);
        for k in 1..=s.steps {
            run.step().unwrap();
            tracker.observe(k, run.best_now());
        }
        let ours = tracker.at_checkpoints()[0];
        assert!(ours < start_best);
        assert_eq!(ours, run.kernel_best());
    }

    #[test]
    fn a_chain_takes_its_storage_and_no_more() {
        for d in [1, 3, 10, 100] {
            let floats = (4 * d + 2) * size_of::<f64>();
            assert_eq!(
                chain_bytes(d),
                Some(floats + 9 + size_of::<Generator>()),
                "{d}"
            );
        }
        assert_eq!(chain_bytes(usize::MAX), None);
    }
}

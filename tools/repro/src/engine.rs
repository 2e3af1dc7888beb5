//! The run loop: one run of one configuration, the kernel's optimisers
//! driven step by step, with the best chain value handed to a [`Tracker`].

use hrla::rand_core::Rng;
use hrla::{AnySampler, AnySchedule, Gaussian, Optimizer, Point, Rastrigin, Start};

use crate::config::{RunSpec, StartSpec};
use crate::error::ReproError;
use crate::stats::Tracker;

/// Chains per kernel optimiser. A run of `N` chains is split into
/// `ceil(N / CHUNK)` optimisers stepped in order with one generator, which
/// draws exactly the numbers one optimiser of `N` chains would (initial
/// points chain after chain, then each step chain after chain; tested), but
/// keeps every optimiser small enough to build on a worker thread's stack
/// before it is boxed (`CHUNK (4D + 2) 8` bytes, 100 KiB at `D = 100`).
pub const CHUNK: usize = 32;

/// Gaussian or fixed-point start behind one type.
#[derive(Clone, Copy, Debug)]
enum AnyStart<const D: usize> {
    Gaussian(Gaussian<f64, D>),
    Point(Point<f64, D>),
}

impl<const D: usize> AnyStart<D> {
    fn new(spec: StartSpec) -> Result<Self, hrla::Error> {
        Ok(match spec {
            StartSpec::Gaussian { centre, variance } => {
                AnyStart::Gaussian(Gaussian::new([centre; D], variance.sqrt())?)
            }
            StartSpec::Point(v) => AnyStart::Point(Point::new([v; D])?),
        })
    }
}

impl<const D: usize> Start<f64, D> for AnyStart<D> {
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R) -> [f64; D] {
        match self {
            AnyStart::Gaussian(s) => s.initial_point(chain, rng),
            AnyStart::Point(s) => s.initial_point(chain, rng),
        }
    }
}

type Part<const D: usize> = Optimizer<f64, Rastrigin, AnySampler<f64>, AnySchedule<f64>, D, CHUNK>;

/// `N` chains as a list of boxed kernel optimisers of at most [`CHUNK`]
/// chains each, stepped in order with one generator.
pub struct Swarm<const D: usize> {
    parts: Vec<Box<Part<D>>>,
}

impl<const D: usize> Swarm<D> {
    /// Draws the initial points of `spec.chains` chains, chunk after chunk.
    pub fn new<R: Rng + ?Sized>(spec: &RunSpec, rng: &mut R) -> Result<Self, hrla::Error> {
        let (schedule, sampler) = spec.kernel_setup()?;
        let mut start = AnyStart::<D>::new(spec.start)?;
        let mut parts = Vec::with_capacity(spec.chains.div_ceil(CHUNK));
        let mut left = spec.chains;
        while left > 0 {
            let n = left.min(CHUNK);
            let part = Optimizer::new(Rastrigin, sampler, schedule, n, &mut start, rng)?;
            parts.push(Box::new(part));
            left -= n;
        }
        Ok(Self { parts })
    }

    /// One step of every chain.
    pub fn step<R: Rng + ?Sized>(&mut self, rng: &mut R) -> Result<(), hrla::Error> {
        for part in &mut self.parts {
            part.step(rng)?;
        }
        Ok(())
    }

    /// `min_c U(x_k^c)` over the live chains at the current iterate
    /// (`+inf` when every chain has diverged).
    pub fn best_now(&self) -> f64 {
        self.parts
            .iter()
            .filter_map(|p| p.current_best())
            .map(|(_, v)| v)
            .fold(f64::INFINITY, f64::min)
    }

    /// The kernel's own global running best (over `k = 0, s, 2s, ...` of
    /// each optimiser's stride, so including the initial points).
    pub fn kernel_best(&self) -> f64 {
        self.parts
            .iter()
            .map(|p| p.best().value)
            .fold(f64::INFINITY, f64::min)
    }

    /// Chains that diverged (non-finite potential or gradient).
    pub fn diverged(&self) -> usize {
        self.parts.iter().map(|p| p.report().diverged_chains).sum()
    }

    /// Current positions of every chain, in order (for tests).
    pub fn positions(&self) -> impl Iterator<Item = &[f64; D]> {
        self.parts
            .iter()
            .flat_map(|p| p.chains().iter().map(|c| c.x()))
    }
}

/// What one run leaves besides its probability counts.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutcome {
    /// The paper's running best at each checkpoint (see [`Tracker`]).
    pub running_best: Vec<f64>,
    /// Chains that diverged during the run.
    pub diverged: usize,
}

/// How many iterates a run does between two progress reports.
const PROGRESS_EVERY: u64 = 1024;

/// Runs one configuration once with `rng`, adding its probability counts
/// into `counts` (length [`RunSpec::count_len`]) and calling `progress`
/// with chain-steps done every 1024 iterates and at the end.
pub fn run_once<R: Rng + ?Sized>(
    spec: &RunSpec,
    rng: &mut R,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    match spec.d {
        1 => run_d::<1, R>(spec, rng, counts, progress),
        2 => run_d::<2, R>(spec, rng, counts, progress),
        5 => run_d::<5, R>(spec, rng, counts, progress),
        10 => run_d::<10, R>(spec, rng, counts, progress),
        20 => run_d::<20, R>(spec, rng, counts, progress),
        50 => run_d::<50, R>(spec, rng, counts, progress),
        100 => run_d::<100, R>(spec, rng, counts, progress),
        d => Err(ReproError::Dimension(d)),
    }
}

fn run_d<const D: usize, R: Rng + ?Sized>(
    spec: &RunSpec,
    rng: &mut R,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    let mut swarm = Swarm::<D>::new(spec, rng)?;
    // Rastrigin's global minimum U* = 0.
    let mut tracker = Tracker::new(
        spec.steps,
        spec.stride,
        spec.curve_every,
        &spec.checkpoints,
        &spec.eps,
        0.0,
        counts,
    );
    if tracker.wants(0) {
        tracker.observe(0, swarm.best_now());
    }
    let n = spec.chains as u64;
    for k in 1..=spec.steps {
        swarm.step(rng)?;
        if tracker.wants(k) {
            tracker.observe(k, swarm.best_now());
        }
        if k % PROGRESS_EVERY == 0 {
            progress(PROGRESS_EVERY * n);
        }
    }
    progress((spec.steps % PROGRESS_EVERY) * n);
    Ok(RunOutcome {
        running_best: tracker.at_checkpoints().to_vec(),
        diverged: swarm.diverged(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Temperature;
    use crate::seed::run_rng;
    use hrla::SamplerKind;

    fn spec(chains: usize, temperature: Temperature) -> RunSpec {
        RunSpec {
            sampler: SamplerKind::Hrla,
            d: 10,
            h: 0.01,
            chains,
            steps: 50,
            temperature,
            start: StartSpec::Gaussian {
                centre: 3.0,
                variance: 10.0,
            },
            stride: 1,
            checkpoints: vec![50],
            eps: vec![],
            curve_every: None,
        }
    }

    /// A swarm split into chunks draws the same numbers as one optimiser of
    /// all its chains, so the split is invisible in the results.
    #[test]
    fn split_swarm_equals_one_optimiser() {
        const N: usize = 2 * CHUNK + 5;
        for temperature in [
            Temperature::Constant(3.0),
            Temperature::Linear {
                low: 0.1,
                high: 4.0,
            },
        ] {
            let s = spec(N, temperature);
            let mut rng_a = run_rng(11, 0);
            let mut swarm = Swarm::<10>::new(&s, &mut rng_a).unwrap();
            let mut rng_b = run_rng(11, 0);
            let (schedule, sampler) = s.kernel_setup().unwrap();
            let mut start = AnyStart::<10>::new(s.start).unwrap();
            let mut whole: Box<
                Optimizer<f64, Rastrigin, AnySampler<f64>, AnySchedule<f64>, 10, N>,
            > = Box::new(
                Optimizer::new(Rastrigin, sampler, schedule, N, &mut start, &mut rng_b).unwrap(),
            );
            for _ in 0..s.steps {
                swarm.step(&mut rng_a).unwrap();
                whole.step(&mut rng_b).unwrap();
            }
            let split: Vec<[f64; 10]> = swarm.positions().copied().collect();
            let one: Vec<[f64; 10]> = whole.chains().iter().map(|c| *c.x()).collect();
            assert_eq!(split, one);
            assert_eq!(swarm.best_now(), whole.current_best().unwrap().1);
        }
    }

    /// Cross-check of the tool's running best with the kernel's: from
    /// N(3·1, 10 I) the initial points are far worse than anything after a
    /// few hundred steps, so the kernel's best (which includes iterate 0)
    /// must equal the tool's (which does not), at stride 1.
    #[test]
    fn running_best_agrees_with_the_kernel_when_iterate_0_is_not_the_best() {
        let mut s = spec(40, Temperature::Constant(3.0));
        s.steps = 300;
        s.checkpoints = vec![300];
        let mut rng = run_rng(3, 0);
        let mut swarm = Swarm::<10>::new(&s, &mut rng).unwrap();
        let start_best = swarm.best_now();
        let mut none = [];
        let mut tracker = Tracker::new(s.steps, 1, None, &s.checkpoints, &[], 0.0, &mut none);
        for k in 1..=s.steps {
            swarm.step(&mut rng).unwrap();
            tracker.observe(k, swarm.best_now());
        }
        let ours = tracker.at_checkpoints()[0];
        assert!(ours < start_best);
        assert_eq!(ours, swarm.kernel_best());
    }

    #[test]
    fn a_run_is_a_function_of_its_seed() {
        let mut s = spec(7, Temperature::Constant(2.0));
        s.eps = vec![1.0, 5.0, 50.0];
        s.curve_every = Some(5);
        let mut c1 = vec![0; s.count_len()];
        let mut c2 = vec![0; s.count_len()];
        let r1 = run_once(&s, &mut run_rng(5, 9), &mut c1, &|_| {}).unwrap();
        let r2 = run_once(&s, &mut run_rng(5, 9), &mut c2, &|_| {}).unwrap();
        assert_eq!(r1, r2);
        assert_eq!(c1, c2);
        assert!(r1.running_best[0].is_finite());
    }

    #[test]
    fn progress_adds_up_to_n_k() {
        use std::sync::atomic::{AtomicU64, Ordering};
        let mut s = spec(3, Temperature::Constant(1.0));
        s.steps = 2500;
        s.checkpoints = vec![2500];
        let done = AtomicU64::new(0);
        run_once(&s, &mut run_rng(1, 1), &mut [], &|n| {
            done.fetch_add(n, Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(done.into_inner(), 3 * 2500);
    }

    /// `DIMENSIONS` (what plans accept) and the dispatch of `run_once` are
    /// two lists; a dimension in the first only would fail mid-run.
    #[test]
    fn every_listed_dimension_is_compiled_in() {
        for d in crate::config::DIMENSIONS {
            let mut s = spec(1, Temperature::Constant(1.0));
            s.d = d;
            s.steps = 2;
            s.checkpoints = vec![2];
            assert!(run_once(&s, &mut run_rng(0, 0), &mut [], &|_| {}).is_ok());
        }
    }

    #[test]
    fn unsupported_dimension_is_an_error() {
        let mut s = spec(1, Temperature::Constant(1.0));
        s.d = 3;
        assert!(matches!(s.validate(), Err(ReproError::Dimension(3))));
        assert!(matches!(
            run_once(&s, &mut run_rng(0, 0), &mut [], &|_| {}),
            Err(ReproError::Dimension(3))
        ));
    }
}

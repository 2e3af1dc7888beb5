//! The run loop: one run of one configuration, one kernel optimiser over
//! all its chains driven step by step, with the best chain value handed to
//! a [`Tracker`].
//!
//! The loop calls [`Optimizer::step`] itself rather than
//! [`Optimizer::run_with`]: the tracker needs `min_c U(x_k^c)` (the best
//! chain *now*, not the running best) at every iterate on the stride or the
//! curve grid, which the observer's [`Progress`](hrla::Progress) does not
//! carry and which it would only see every `every` steps; stepping by hand
//! reads [`Optimizer::current_best`] at exactly the iterates wanted, and
//! the progress bar is a counter in the same loop.

use hrla::{
    AnySampler, AnySchedule, Builder, Chain, Chains, Gaussian, Optimizer, Point, Rastrigin, Stop,
};
use hrla_dyn::AnyStart;

use crate::config::{RunSpec, StartSpec};
use crate::error::ReproError;
use crate::peers::{AnyPeer, Peer, Population};
use crate::stats::Tracker;

/// The start of a run in dimension `D`, as the layer's one type of
/// start (the peers start from it too, so member `c` starts where the
/// kernel's chain `c` does).
fn start<const D: usize>(spec: StartSpec) -> Result<AnyStart<D>, hrla::Error> {
    Ok(match spec {
        StartSpec::Gaussian { centre, variance } => {
            AnyStart::Gaussian(Gaussian::new([centre; D], variance.sqrt())?)
        }
        StartSpec::Point(v) => AnyStart::Point(Point::new([v; D])?),
    })
}

/// The kernel optimiser of one run: its `N` chains in one `Vec` it owns
/// (on the heap, so T2's 10 000 chains never touch a worker's stack).
pub type RunOptimizer<const D: usize> = Optimizer<
    f64,
    Rastrigin,
    AnySampler<f64>,
    AnySchedule<f64>,
    Chains<f64, Vec<Chain<f64, D>>, D>,
>;

/// Builds the optimiser of one run of `spec` seeded with `seed` (see
/// [`run_seed`](crate::seed::run_seed)): `spec.chains` chains, chain `c`
/// drawing its start and its steps from its own generator
/// (`hrla::chain_seed(seed, c)`), a step budget of `K = spec.steps` (which
/// a linear schedule's length equals; the builder checks) and the
/// kernel's running best on the tool's stride.
pub fn optimizer<const D: usize>(
    spec: &RunSpec,
    seed: u64,
) -> Result<RunOptimizer<D>, hrla::Error> {
    let (schedule, sampler) = spec.kernel_setup()?;
    let chains = (0..spec.chains).map(|_| Chain::new()).collect::<Vec<_>>();
    Builder::new(Rastrigin, sampler, schedule, start::<D>(spec.start)?)
        .seed(seed)
        .stride(spec.stride)
        .stop(Stop::new().steps(spec.steps))
        .build(chains)
}

/// `min_c U(x_k^c)` over the live chains at the current iterate (`+inf`
/// when every chain has diverged).
pub fn best_now<const D: usize>(opt: &RunOptimizer<D>) -> f64 {
    opt.current_best().map_or(f64::INFINITY, |(_, v)| v)
}

/// One step of every live chain. A run whose chains have all diverged is
/// not an error for the tool: its remaining iterates have no best chain
/// (`+inf`, within no tolerance), as before the kernel made it one.
fn step<const D: usize>(opt: &mut RunOptimizer<D>) -> Result<(), hrla::Error> {
    match opt.step() {
        Ok(_) | Err(hrla::Error::AllDiverged { .. }) => Ok(()),
        Err(e) => Err(e),
    }
}

/// What one run leaves besides its probability counts.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutcome {
    /// The paper's running best at each checkpoint (see [`Tracker`]).
    pub running_best: Vec<f64>,
    /// Chains that diverged during the run.
    pub diverged: usize,
    /// Evaluations of the potential: of `U` and `∇U` together for the
    /// kernel's samplers, of `U` alone for the peers.
    pub evaluations: u64,
}

/// The global minimum `U* = 0` of the paper's Rastrigin, which every run
/// minimises: the tolerances of the probability curves are on `U - U*`,
/// and no running best is below it (the value is a sum of non-negative
/// terms, each formed without cancellation).
pub const U_STAR: f64 = 0.0;

/// How many iterates a run does between two progress reports.
const PROGRESS_EVERY: u64 = 1024;

/// Runs one configuration once with the run seed `seed`, adding its
/// probability counts into `counts` (length [`RunSpec::count_len`]) and
/// calling `progress` with chain-steps done every 1024 iterates and at the
/// end.
pub fn run_once(
    spec: &RunSpec,
    seed: u64,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    match spec.d {
        1 => run_d::<1>(spec, seed, counts, progress),
        2 => run_d::<2>(spec, seed, counts, progress),
        5 => run_d::<5>(spec, seed, counts, progress),
        10 => run_d::<10>(spec, seed, counts, progress),
        20 => run_d::<20>(spec, seed, counts, progress),
        50 => run_d::<50>(spec, seed, counts, progress),
        100 => run_d::<100>(spec, seed, counts, progress),
        d => Err(ReproError::Dimension(d)),
    }
}

fn run_d<const D: usize>(
    spec: &RunSpec,
    seed: u64,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    match spec.method.peer() {
        Some(peer) => run_peer::<D>(spec, peer, seed, counts, progress),
        None => run_kernel::<D>(spec, seed, counts, progress),
    }
}

/// The bytes of one kernel chain in dimension `d` (`None` for a dimension
/// not compiled in): a run of `N` chains holds `N` of them. A peer's member
/// (a point, its value and its generator) is smaller.
pub fn chain_bytes(d: usize) -> Option<usize> {
    if !crate::config::DIMENSIONS.contains(&d) {
        return None;
    }
    hrla_dyn::storage_bytes(d).ok()
}

/// A run being driven: one iteration at a time, and its best sample now.
trait Iterate {
    /// Iteration `k >= 1`.
    fn iterate(&mut self, k: u64) -> Result<(), ReproError>;
    /// `min` over the samples of `U` now (`+inf` when none is left).
    fn best_now(&self) -> f64;
}

impl<const D: usize> Iterate for RunOptimizer<D> {
    fn iterate(&mut self, _k: u64) -> Result<(), ReproError> {
        Ok(step(self)?)
    }
    fn best_now(&self) -> f64 {
        best_now(self)
    }
}

/// A peer's population and its method.
struct PeerRun<const D: usize> {
    pop: Population<D>,
    peer: AnyPeer,
}

impl<const D: usize> Iterate for PeerRun<D> {
    fn iterate(&mut self, k: u64) -> Result<(), ReproError> {
        self.peer.iterate(&mut self.pop, &Rastrigin, k);
        Ok(())
    }
    fn best_now(&self) -> f64 {
        self.pop.best_now()
    }
}

/// Runs `spec.steps` iterations of `run`, handing its best sample to the
/// tracker (Rastrigin's global minimum [`U_STAR`]) at the iterates it wants
/// and reporting progress; returns the running best at the checkpoints.
fn drive(
    spec: &RunSpec,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
    run: &mut impl Iterate,
) -> Result<Vec<f64>, ReproError> {
    let mut tracker = Tracker::new(
        spec.steps,
        spec.stride,
        spec.curve_every,
        &spec.checkpoints,
        &spec.eps,
        U_STAR,
        counts,
    );
    if tracker.wants(0) {
        tracker.observe(0, run.best_now());
    }
    let n = spec.chains as u64;
    for k in 1..=spec.steps {
        run.iterate(k)?;
        if tracker.wants(k) {
            tracker.observe(k, run.best_now());
        }
        if k % PROGRESS_EVERY == 0 {
            progress(PROGRESS_EVERY * n);
        }
    }
    progress((spec.steps % PROGRESS_EVERY) * n);
    Ok(tracker.at_checkpoints().to_vec())
}

fn run_kernel<const D: usize>(
    spec: &RunSpec,
    seed: u64,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    let mut opt = optimizer::<D>(spec, seed)?;
    let running_best = drive(spec, counts, progress, &mut opt)?;
    Ok(RunOutcome {
        running_best,
        diverged: opt.diverged_chains(),
        evaluations: opt.evaluations(),
    })
}

/// A peer's run: `spec.chains` members from `spec.start`, member `c` on
/// the stream `chain_seed(seed, c)` as the kernel's chain `c`.
fn run_peer<const D: usize>(
    spec: &RunSpec,
    peer: AnyPeer,
    seed: u64,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    let mut start = start::<D>(spec.start)?;
    let pop = Population::new(&Rastrigin, &mut start, spec.chains, seed);
    let mut run = PeerRun { pop, peer };
    let running_best = drive(spec, counts, progress, &mut run)?;
    Ok(RunOutcome {
        running_best,
        diverged: 0,
        evaluations: run.pop.evaluations(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{Method, Temperature};
    use crate::seed::run_seed;
    use hrla::SamplerKind;

    fn spec(chains: usize, temperature: Temperature) -> RunSpec {
        RunSpec {
            method: Method::Kernel(SamplerKind::Hrla),
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

    fn positions<const D: usize>(opt: &RunOptimizer<D>) -> Vec<[f64; D]> {
        opt.chains().iter().map(|c| *c.x()).collect()
    }

    /// Chain `c` of a run draws from a stream of `(run seed, c)` alone: the
    /// first chains of a run of 5 follow exactly the trajectories of the
    /// first 5 of a run of 69 with the same seed, at constant `a` and
    /// annealing. So the chain count neither shifts any chain's stream
    /// (nor could the order in which the kernel steps them).
    #[test]
    fn a_chain_does_not_depend_on_how_many_run_beside_it() {
        for temperature in [
            Temperature::Constant(3.0),
            Temperature::Linear {
                low: 0.1,
                high: 4.0,
            },
        ] {
            let seed = run_seed(11, 0);
            let mut many = optimizer::<10>(&spec(69, temperature), seed).unwrap();
            let mut few = optimizer::<10>(&spec(5, temperature), seed).unwrap();
            assert_eq!(positions(&many)[..5], positions(&few)[..]);
            for _ in 0..50 {
                many.step().unwrap();
                few.step().unwrap();
            }
            assert_eq!(positions(&many)[..5], positions(&few)[..]);
            let other = optimizer::<10>(&spec(5, temperature), run_seed(11, 1)).unwrap();
            assert_ne!(positions(&other), positions(&few)[..5]);
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
        let mut opt = optimizer::<10>(&s, run_seed(3, 0)).unwrap();
        let start_best = best_now(&opt);
        let mut none = [];
        let mut tracker = Tracker::new(s.steps, 1, None, &s.checkpoints, &[], 0.0, &mut none);
        for k in 1..=s.steps {
            opt.step().unwrap();
            tracker.observe(k, best_now(&opt));
        }
        let ours = tracker.at_checkpoints()[0];
        assert!(ours < start_best);
        assert_eq!(ours, opt.best().value);
    }

    #[test]
    fn a_run_is_a_function_of_its_seed() {
        let mut s = spec(7, Temperature::Constant(2.0));
        s.eps = vec![1.0, 5.0, 50.0];
        s.curve_every = Some(5);
        let mut c1 = vec![0; s.count_len()];
        let mut c2 = vec![0; s.count_len()];
        let mut c3 = vec![0; s.count_len()];
        let r1 = run_once(&s, run_seed(5, 9), &mut c1, &|_| {}).unwrap();
        let r2 = run_once(&s, run_seed(5, 9), &mut c2, &|_| {}).unwrap();
        let r3 = run_once(&s, run_seed(5, 10), &mut c3, &|_| {}).unwrap();
        assert_eq!(r1, r2);
        assert_eq!(c1, c2);
        assert_ne!(r1, r3);
        assert!(r1.running_best[0].is_finite());
    }

    /// A run whose chains all diverge (ULA with a step far beyond
    /// stability) still finishes: the kernel's `AllDiverged` ends no
    /// protocol, and after it no iterate has a best chain.
    #[test]
    fn a_run_whose_chains_all_diverge_completes() {
        let mut s = spec(3, Temperature::Constant(1.0));
        s.method = Method::Kernel(SamplerKind::Ula);
        s.h = 40.0;
        s.steps = 400;
        s.checkpoints = vec![400];
        s.eps = vec![1e9];
        s.curve_every = Some(400);
        let mut counts = vec![0; s.count_len()];
        let out = run_once(&s, run_seed(1, 0), &mut counts, &|_| {}).unwrap();
        assert_eq!(out.diverged, 3);
        // Within 1e9 at k = 0 (the start), not at k = 400 (no chain left).
        assert_eq!(counts, [1, 0]);
    }

    #[test]
    fn progress_adds_up_to_n_k() {
        use std::sync::atomic::{AtomicU64, Ordering};
        let mut s = spec(3, Temperature::Constant(1.0));
        s.steps = 2500;
        s.checkpoints = vec![2500];
        let done = AtomicU64::new(0);
        run_once(&s, run_seed(1, 1), &mut [], &|n| {
            done.fetch_add(n, Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(done.into_inner(), 3 * 2500);
    }

    /// `DIMENSIONS` (what plans accept) and the dispatches of `run_once`
    /// and `chain_bytes` are three lists; a dimension in the first only
    /// would fail mid-run.
    #[test]
    fn every_listed_dimension_is_compiled_in() {
        for d in crate::config::DIMENSIONS {
            assert!(chain_bytes(d).is_some_and(|b| b >= 3 * 8 * d), "{d}");
            let mut s = spec(1, Temperature::Constant(1.0));
            s.d = d;
            s.steps = 2;
            s.checkpoints = vec![2];
            assert!(run_once(&s, run_seed(0, 0), &mut [], &|_| {}).is_ok());
        }
    }

    #[test]
    fn unsupported_dimension_is_an_error() {
        let mut s = spec(1, Temperature::Constant(1.0));
        s.d = 3;
        assert!(matches!(s.validate(), Err(ReproError::Dimension(3))));
        assert!(matches!(
            run_once(&s, run_seed(0, 0), &mut [], &|_| {}),
            Err(ReproError::Dimension(3))
        ));
    }
}

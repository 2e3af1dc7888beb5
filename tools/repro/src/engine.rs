//! The run loop: one run of one configuration, the kernel's chains
//! ([`KernelRun`]) or a peer's population driven one iteration at a time,
//! with the best sample now handed to a [`Tracker`].
//!
//! The loop steps the run itself rather than letting the kernel's `run`
//! drive it: the tracker needs `min_c U(x_k^c)` (the best chain *now*, not
//! the running best) at every iterate on the stride or the curve grid,
//! which the kernel's observer does not carry and would only see every
//! `every` steps; stepping by hand reads the best chain at exactly the
//! iterates wanted, and the progress bar is a counter in the same loop.

use hrla::Rastrigin;

use crate::config::RunSpec;
use crate::error::ReproError;
use crate::kernel::{KernelRun, RunStart};
use crate::peers::{AnyPeer, Peer, Population};
use crate::stats::Tracker;

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
/// end. Any dimension `spec.d >= 1`.
pub fn run_once(
    spec: &RunSpec,
    seed: u64,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    match spec.method.peer() {
        Some(peer) => run_peer(spec, peer, seed, counts, progress),
        None => run_kernel(spec, seed, counts, progress),
    }
}

/// A run being driven: one iteration at a time, and its best sample now.
trait Iterate {
    /// Iteration `k >= 1`.
    fn iterate(&mut self, k: u64) -> Result<(), ReproError>;
    /// `min` over the samples of `U` now (`+inf` when none is left).
    fn best_now(&self) -> f64;
}

impl Iterate for KernelRun {
    fn iterate(&mut self, _k: u64) -> Result<(), ReproError> {
        Ok(self.step()?)
    }
    fn best_now(&self) -> f64 {
        KernelRun::best_now(self)
    }
}

/// A peer's population and its method.
struct PeerRun {
    pop: Population,
    peer: AnyPeer,
}

impl Iterate for PeerRun {
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

fn run_kernel(
    spec: &RunSpec,
    seed: u64,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    let mut run = KernelRun::new(spec, seed)?;
    let running_best = drive(spec, counts, progress, &mut run)?;
    Ok(RunOutcome {
        running_best,
        diverged: run.diverged_chains(),
        evaluations: run.evaluations(),
    })
}

/// A peer's run: `spec.chains` members from `spec.start`, member `c` on
/// the stream `chain_seed(seed, c)` as the kernel's chain `c`.
fn run_peer(
    spec: &RunSpec,
    peer: AnyPeer,
    seed: u64,
    counts: &mut [u32],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome, ReproError> {
    let mut start = RunStart::of(spec.start);
    let pop = Population::new(&Rastrigin, &mut start, spec.chains, spec.d, seed);
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
    use crate::config::{Method, StartSpec, Temperature};
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

    /// Any dimension runs, the kernel's and the peers' alike.
    #[test]
    fn every_dimension_runs() {
        for d in [1, 3, 7, 10, 101] {
            let mut s = spec(4, Temperature::Constant(1.0));
            s.d = d;
            s.steps = 20;
            s.checkpoints = vec![20];
            assert!(s.validate().is_ok());
            let kernel = run_once(&s, run_seed(0, 0), &mut [], &|_| {}).unwrap();
            assert!(kernel.running_best[0].is_finite(), "{d}");
            s.method = crate::config::Method::Peer {
                kind: crate::peers::PeerKind::Csa,
                walk: crate::peers::DEFAULT_WALK,
            };
            let peer = run_once(&s, run_seed(0, 0), &mut [], &|_| {}).unwrap();
            assert_eq!(peer.evaluations, 4 * 21, "{d}");
        }
    }
}

//! `--backend gpu`: a plan's runs on a GPU ([`hrla_gpu`]), with the CPU
//! backend's statistics, run seeds and shards.
//!
//! The runs of one configuration in one shard share an ensemble on the
//! device (in batches of at most [`MAX_BATCH_CHAINS`] chains): run `i`
//! takes `N` consecutive chains, chain `c` of it drawing from
//! `Xoshiro128PlusPlus::seed_from_u64(chain_seed(run_seed(seed, i), c))`.
//! That is the CPU backend's seeding with the device's generator
//! (xoshiro128++, not the CPU backend's xoshiro256++), so the two backends
//! draw different numbers and agree in law, not in bits; a run's numbers
//! do not depend on which runs share its ensemble, so shards merge into
//! the same result as one process.
//!
//! The statistics are the CPU backend's ([`Tracker`](crate::stats::Tracker)):
//! each chain keeps its running best on the device over `k = s, 2s, ...`
//! (without iterate 0), and a run's running best at a checkpoint is the
//! least of its chains'; the probability curves count, on the device, the
//! runs whose best live chain lies within each tolerance of `U*` at each
//! grid iterate. The device computes in `f64`, as the CPU backend does
//! (an adapter without `SHADER_F64` is refused). Shard files of the GPU
//! backend name its generator in their plan, so that a merge never mixes
//! them with the CPU backend's.

use std::time::Instant;

use hrla_gpu::{DevicePotential, EnsembleBuilder, Gpu, GpuError, Precision, Start};
use indicatif::ProgressBar;

use crate::config::{Method, RunSpec, StartSpec};
use crate::engine::{RunOutcome, U_STAR};
use crate::error::ReproError;
use crate::exec::{Part, ProtocolResult, finish};
use crate::protocol::Plan;
use crate::seed::run_seed;
use crate::split::Shard;
use crate::stats::grid_points;

/// Where the chains of a plan run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Backend {
    /// The CPU, one run per worker thread (the default).
    #[default]
    Cpu,
    /// A GPU through wgpu (Vulkan, Metal, DX12), or a software Vulkan
    /// such as lavapipe.
    Gpu,
}

impl Backend {
    /// Starts the worker threads that a command on this backend uses,
    /// once `threads` (`--threads`, 0: one per core) is checked against
    /// [`max_threads`](crate::limits::max_threads) whatever the backend:
    /// runs on the CPU start them ([`exec::start_workers`](crate::exec::start_workers))
    /// and return how many run; runs on the GPU and a merge (`merge`)
    /// start none (`None`).
    pub fn start_workers(self, threads: usize, merge: bool) -> Result<Option<usize>, ReproError> {
        crate::limits::check_threads(threads, crate::limits::cores())?;
        if self == Backend::Gpu || merge {
            return Ok(None);
        }
        crate::exec::start_workers(threads).map(Some)
    }
}

/// The device's generator, as shard files name it.
pub const GENERATOR: &str = "xoshiro128++";

/// The most chains one ensemble holds: a configuration's runs beyond it go
/// in further batches (whole runs each), so that the device's buffers stay
/// far below its limits.
pub const MAX_BATCH_CHAINS: usize = 1 << 22;

/// One more than the most steps a run on the device takes.
const MAX_STEPS: u64 = u32::MAX as u64;

/// Steps between two progress reports (each waits for the device).
const PROGRESS_STEPS: u64 = 2000;

/// Steps each chain takes in registers per dispatch.
const STEPS_PER_DISPATCH: u32 = 200;

/// The device the plans run on.
pub struct GpuBackend {
    gpu: Gpu,
}

impl std::fmt::Debug for GpuBackend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.describe())
    }
}

impl GpuBackend {
    /// The first adapter wgpu offers (`WGPU_BACKEND` and
    /// `WGPU_ADAPTER_NAME` steer the choice), computing in `f64` as the
    /// CPU backend does.
    ///
    /// Errors: [`ReproError::Gpu`] with [`GpuError::NoAdapter`] when there
    /// is no adapter at all (no GPU and no software Vulkan),
    /// [`GpuError::Device`] when it refuses to open, or
    /// [`GpuError::Unsupported`] when it has no `SHADER_F64` (Apple's GPUs,
    /// for one).
    pub fn open() -> Result<Self, ReproError> {
        let gpu = Gpu::new()?;
        if !gpu.supports_f64() {
            return Err(ReproError::Gpu(GpuError::Unsupported(format!(
                "f64: the adapter {} has no SHADER_F64, and the protocols are computed in f64",
                gpu.describe()
            ))));
        }
        Ok(Self { gpu })
    }

    /// Checks that `plan` is one the device runs, before anything opens
    /// or runs: [`ReproError::Flag`] for T3's peers (they run on the CPU
    /// only), a `K` of 2^32 - 1 or more (the device's iterates are
    /// 32-bit), or a start beyond `f32` (the device draws the starts in
    /// `f32`: the centre or point, and the standard deviation, the square
    /// root of `--start-var`), naming the option and its value.
    pub fn check(plan: &Plan) -> Result<(), ReproError> {
        if let Some(spec) = plan
            .configs
            .iter()
            .find(|s| !matches!(s.method, Method::Kernel(_)))
        {
            return Err(ReproError::Flag {
                flag: "--backend",
                reason: format!(
                    "{} runs on the CPU only (the GPU backend steps the kernel's samplers); \
                     run {} without --backend gpu",
                    spec.method.label(),
                    plan.id.name()
                ),
            });
        }
        // The device counts iterates in 32 bits: a K beyond is refused
        // before anything runs, not after 2^32 steps.
        if let Some(spec) = plan.configs.iter().find(|s| s.steps >= MAX_STEPS) {
            return Err(ReproError::Flag {
                flag: "--k",
                reason: format!(
                    "K = {} is beyond the GPU backend's {} steps (iterates are 32-bit on the \
                     device); run it with --backend cpu",
                    spec.steps,
                    MAX_STEPS - 1
                ),
            });
        }
        // The device draws the starts in f32.
        let beyond = |v: f64| !(v as f32).is_finite();
        for spec in &plan.configs {
            let (flag, value, what) = match spec.start {
                StartSpec::Gaussian { variance, .. } if beyond(variance.sqrt()) => (
                    "--start-var",
                    variance,
                    "its square root, the standard deviation, is",
                ),
                StartSpec::Gaussian { centre, .. } if beyond(centre) => {
                    ("--start-centre", centre, "it is")
                }
                StartSpec::Point(v) if beyond(v) => ("--start-point", v, "it is"),
                _ => continue,
            };
            return Err(ReproError::Flag {
                flag,
                reason: format!(
                    "got {value:e}: the GPU backend draws the start in f32, and {what} \
                     beyond f32's range (+-{:e})",
                    f32::MAX
                ),
            });
        }
        Ok(())
    }

    /// The adapter, the float type and the generator, for the run's
    /// metadata.
    pub fn describe(&self) -> String {
        format!("gpu: {}, f64, {GENERATOR}", self.gpu.describe())
    }

    /// Every run of `plan`, as [`exec::execute`](crate::exec::execute)
    /// does them on the CPU.
    pub fn execute(
        &self,
        plan: &Plan,
        seed: u64,
        bar: &ProgressBar,
    ) -> Result<ProtocolResult, ReproError> {
        let part = self.run_shard(plan, seed, Shard::WHOLE, bar)?;
        Ok(finish(plan, seed, part, 1))
    }

    /// The runs of one shard of `plan`, as
    /// [`exec::run_shard`](crate::exec::run_shard) does them on the CPU:
    /// the same [`Part`], a run without a finite running best at a
    /// checkpoint failing the shard ([`ReproError::FailedRun`]). `bar`
    /// advances by chain-steps.
    ///
    /// Errors besides the device's: those of [`check`](GpuBackend::check),
    /// before anything runs.
    pub fn run_shard(
        &self,
        plan: &Plan,
        seed: u64,
        shard: Shard,
        bar: &ProgressBar,
    ) -> Result<Part, ReproError> {
        Self::check(plan)?;
        let started = Instant::now();
        let mut part = Part::empty(plan);
        let tasks = plan.tasks(shard);
        for (c, spec) in plan.configs.iter().enumerate() {
            let runs: Vec<usize> = tasks
                .iter()
                .filter(|&&(config, _)| config == c)
                .map(|&(_, i)| i)
                .collect();
            let per_batch = (MAX_BATCH_CHAINS / spec.chains).max(1);
            for batch in runs.chunks(per_batch) {
                let batch_started = Instant::now();
                let outcomes = self.run_batch(spec, seed, batch, &mut part.counts[c], bar)?;
                for (&i, out) in batch.iter().zip(outcomes) {
                    part.record(spec, c, i, out)?;
                }
                // The runs of a batch share the device: their wall time is
                // the batch's, counted once.
                part.run_wall[c] = (part.run_wall[c].checked_add(batch_started.elapsed()))
                    .ok_or(ReproError::Overflow("run wall times"))?;
            }
        }
        part.wall = started.elapsed();
        Ok(part)
    }

    /// The runs `runs` of `spec` in one ensemble: their probability counts
    /// added into `counts`, and each run's running bests, diverged chains
    /// and evaluations.
    fn run_batch(
        &self,
        spec: &RunSpec,
        seed: u64,
        runs: &[usize],
        counts: &mut [u32],
        bar: &ProgressBar,
    ) -> Result<Vec<RunOutcome>, ReproError> {
        let (schedule, sampler) = spec.kernel_setup()?;
        let start = match spec.start {
            StartSpec::Gaussian { centre, variance } => {
                Start::gaussian(vec![centre; spec.d], variance.sqrt())?
            }
            StartSpec::Point(v) => Start::point(vec![v; spec.d])?,
        };
        let n = spec.chains;
        let chains = runs
            .len()
            .checked_mul(n)
            .ok_or(ReproError::Overflow("chains"))?;
        let mut ensemble =
            EnsembleBuilder::new(DevicePotential::Rastrigin, sampler, schedule, start)
                .chains(chains)
                .run_seeds(runs.iter().map(|&i| run_seed(seed, i as u64)).collect())
                .stride(spec.stride)
                .start_in_best(false)
                .precision(Precision::F64)
                .steps_per_dispatch(STEPS_PER_DISPATCH)
                .build(&self.gpu)?;
        let points = grid_points(spec.steps, spec.curve_every);
        let mut outcomes: Vec<RunOutcome> = runs
            .iter()
            .map(|_| RunOutcome {
                running_best: Vec::with_capacity(spec.checkpoints.len()),
                diverged: 0,
                evaluations: 0,
            })
            .collect();
        // Every chain diverged: the kernel's AllDiverged, which ends no
        // protocol (no iterate after it has a best chain).
        let mut all_diverged = false;
        for event in events(spec, points) {
            while !all_diverged && ensemble.iteration() < event.k {
                let steps = (event.k - ensemble.iteration()).min(PROGRESS_STEPS);
                match ensemble.run(steps) {
                    Ok(()) => {}
                    Err(GpuError::Kernel(hrla::Error::AllDiverged { .. })) => all_diverged = true,
                    Err(e) => return Err(e.into()),
                }
                bar.inc(steps * chains as u64);
            }
            if let Some(j) = event.grid
                && !all_diverged
                && !spec.eps.is_empty()
            {
                let shares = ensemble.probability(n, U_STAR, &spec.eps)?;
                for (e, p) in shares.iter().enumerate() {
                    // The share is a count over the batch's runs, divided.
                    let hits = (p.current * runs.len() as f64).round() as u32;
                    counts[e * points + j] = counts[e * points + j]
                        .checked_add(hits)
                        .ok_or(ReproError::Overflow("hit counts"))?;
                }
            }
            if event.checkpoint {
                for (out, g) in outcomes.iter_mut().zip(ensemble.group_bests(n)?) {
                    out.running_best.push(g.running);
                }
            }
        }
        if all_diverged {
            bar.inc((spec.steps - ensemble.iteration().min(spec.steps)) * chains as u64);
        }
        for (out, g) in outcomes.iter_mut().zip(ensemble.group_bests(n)?) {
            out.diverged = g.diverged;
            out.evaluations = g.evaluations;
        }
        Ok(outcomes)
    }
}

/// An iterate the statistics read: a point of the curve grid (its index)
/// and/or a checkpoint.
struct Event {
    k: u64,
    grid: Option<usize>,
    checkpoint: bool,
}

/// The iterates to read, increasing, with what to read at each; the last
/// is `K`, so that every run ends there.
fn events(spec: &RunSpec, points: usize) -> Vec<Event> {
    let mut ks: Vec<u64> = spec.checkpoints.clone();
    if let Some(every) = spec.curve_every {
        ks.extend((0..points as u64).map(|j| j * every));
    }
    ks.push(spec.steps);
    ks.sort_unstable();
    ks.dedup();
    ks.into_iter()
        .map(|k| Event {
            k,
            grid: spec
                .curve_every
                .filter(|&r| k.is_multiple_of(r) && ((k / r) as usize) < points)
                .map(|r| (k / r) as usize),
            checkpoint: spec.checkpoints.contains(&k),
        })
        .collect()
}

impl From<GpuError> for ReproError {
    /// The kernel's refusals keep their variant; the device's own errors
    /// are [`ReproError::Gpu`].
    fn from(e: GpuError) -> Self {
        match e {
            GpuError::Kernel(k) => ReproError::Kernel(k),
            other => ReproError::Gpu(other),
        }
    }
}

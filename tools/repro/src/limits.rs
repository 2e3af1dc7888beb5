//! How big a plan may be: the sizes the tool counts exactly, and the
//! memory a plan needs against what the machine has. A plan beyond either
//! is refused before anything runs, with an error naming the option
//! ([`ReproError::Flag`]), rather than aborting on an allocation, wrapping
//! a counter or running without end.
//!
//! - [`MAX_RUNS`]: M, because hit counts are `u32` (each run adds at most
//!   1 to each).
//! - [`MAX_CHAIN_STEPS`]: `K`, `N K`, and the plan's `M N K` summed over
//!   its configurations. Iterates `k <= K` become `f64` in the annealing
//!   schedule (`k / K`) and chain-steps in the rates of the metadata, both
//!   exact only up to 2^53; below it every counter of the tool (chain-steps,
//!   evaluations `M N (K + 1)`, diverged chains `<= M N`) fits its type.
//! - [`max_threads`]: `--threads`, at most [`THREADS_PER_CORE`] per core.
//! - [`Footprint`]: the bytes of a plan's largest buffers (one run's chains
//!   per worker thread, the probability counters, the running bests),
//!   against the machine's memory ([`machine_memory`]).

use crate::config::RunSpec;
use crate::error::ReproError;

/// The most runs M of a plan: `u32::MAX`, the hit counters' type.
pub const MAX_RUNS: usize = u32::MAX as usize;

/// The most chain-steps of a plan, and so of one run and its `K`: 2^53,
/// up to which every integer is an `f64`.
pub const MAX_CHAIN_STEPS: u64 = 1 << 53;

/// The most worker threads per core that `--threads` may ask for. A run
/// never waits, so threads beyond one per core only take turns; and each
/// worker holds one run's chains at a time.
pub const THREADS_PER_CORE: usize = 8;

/// The cores this process may use (`available_parallelism`: the machine's,
/// within its affinity mask and control group), 1 where it is unknown.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// The most worker threads on `cores` cores: [`THREADS_PER_CORE`] each.
pub fn max_threads(cores: usize) -> usize {
    cores.saturating_mul(THREADS_PER_CORE)
}

/// Checks `--threads` (0: one per core) against [`max_threads`] of
/// `cores`, before any thread is started.
pub fn check_threads(threads: usize, cores: usize) -> Result<(), ReproError> {
    let most = max_threads(cores);
    if threads > most {
        return Err(flag(
            "--threads",
            format!(
                "{threads} worker threads is more than {most}, {THREADS_PER_CORE} per core \
                 of the {cores} this process may use"
            ),
        ));
    }
    Ok(())
}

fn flag(flag: &'static str, reason: String) -> ReproError {
    ReproError::Flag { flag, reason }
}

/// Checks the sizes of a plan of `runs` runs of each of `configs` against
/// [`MAX_RUNS`] and [`MAX_CHAIN_STEPS`] (in checked arithmetic: nothing
/// here can overflow).
pub fn check_counts(configs: &[RunSpec], runs: usize) -> Result<(), ReproError> {
    if runs > MAX_RUNS {
        return Err(flag(
            "--m",
            format!(
                "M = {runs} runs is more than {MAX_RUNS}, the most a hit counter (u32) can count"
            ),
        ));
    }
    let most = MAX_CHAIN_STEPS;
    let mut per_run: u64 = 0;
    for s in configs {
        if s.steps > most {
            return Err(flag(
                "--k",
                format!("K = {} steps is more than 2^53 = {most}", s.steps),
            ));
        }
        let n = u64::try_from(s.chains).unwrap_or(u64::MAX);
        if n > most {
            return Err(flag(
                "--n",
                format!("N = {} chains is more than 2^53 = {most}", s.chains),
            ));
        }
        match n.checked_mul(s.steps).filter(|&nk| nk <= most) {
            Some(nk) => per_run = per_run.saturating_add(nk),
            None => {
                return Err(flag(
                    "--n",
                    format!(
                        "N K = {} x {} chain-steps a run is more than 2^53 = {most}",
                        s.chains, s.steps
                    ),
                ));
            }
        }
    }
    let m = u64::try_from(runs).unwrap_or(u64::MAX);
    if m.checked_mul(per_run).is_none_or(|total| total > most) {
        return Err(flag(
            "--m",
            format!(
                "M = {runs} runs of {per_run} chain-steps (N K summed over the {} configurations) \
                 is more than 2^53 = {most} chain-steps",
                configs.len()
            ),
        ));
    }
    Ok(())
}

/// The bytes of a plan's largest buffers, each `None` if it does not even
/// fit in a `u64`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Footprint {
    /// One run's chains (the kernel's, see
    /// [`chain_bytes`](crate::kernel::chain_bytes); a peer's members are
    /// smaller), for the largest `N` and `d` of the plan.
    pub chains: Option<u64>,
    /// The probability counters of every configuration, one set per
    /// partial result (one per worker while running, two while merging).
    pub counts: Option<u64>,
    /// The running bests of every run and the list of runs.
    pub runs: Option<u64>,
}

/// The counters of configuration `s`: tolerances times grid iterates.
fn counters(s: &RunSpec) -> Option<u64> {
    let points = s
        .curve_every
        .map_or(Some(0), |r| (s.steps / r).checked_add(1))?;
    points.checked_mul(u64::try_from(s.eps.len()).ok()?)
}

impl Footprint {
    /// The footprint of a plan of `runs` runs of each of `configs`.
    pub fn of(configs: &[RunSpec], runs: usize) -> Self {
        let size = |bytes: usize| u64::try_from(bytes).ok();
        let chains = configs.iter().try_fold(0u64, |most, s| {
            let one = size(crate::kernel::chain_bytes(s.d)?)?;
            Some(most.max(u64::try_from(s.chains).ok()?.checked_mul(one)?))
        });
        let counts = configs.iter().try_fold(0u64, |sum, s| {
            sum.checked_add(counters(s)?.checked_mul(size(size_of::<u32>())?)?)
        });
        // Per run and configuration: its index and a vector of checkpoints
        // in the part, and its place in the task list.
        let per_run = configs.iter().try_fold(0u64, |sum, s| {
            let values = size(s.checkpoints.len())?.checked_mul(size(size_of::<f64>())?)?;
            let entry = size(size_of::<(usize, Vec<f64>)>() + size_of::<(usize, usize)>())?;
            sum.checked_add(values.checked_add(entry)?)
        });
        let runs = per_run.and_then(|r| r.checked_mul(u64::try_from(runs).ok()?));
        Self {
            chains,
            counts,
            runs,
        }
    }

    /// The bytes of running with `workers` threads at once, or of a merge
    /// (`None`: no chains, two sets of counters).
    pub fn total(&self, workers: Option<u64>) -> Option<u64> {
        let (chains, parts) = match workers {
            Some(w) => (self.chains?.checked_mul(w)?, w.checked_add(1)?),
            None => (0, 2),
        };
        chains
            .checked_add(self.counts?.checked_mul(parts)?)?
            .checked_add(self.runs?)
    }
}

/// The bytes of memory this process may use: the smaller of the machine's
/// (`MemTotal` in `/proc/meminfo`) and its control group's limit
/// (`/sys/fs/cgroup/memory.max`); where neither is readable (not Linux),
/// `isize::MAX`, the most one allocation may ask for.
pub fn machine_memory() -> u64 {
    let total = std::fs::read_to_string("/proc/meminfo").ok().and_then(|s| {
        let line = s.lines().find(|l| l.starts_with("MemTotal:"))?;
        let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
        kib.checked_mul(1024)
    });
    let group = std::fs::read_to_string("/sys/fs/cgroup/memory.max")
        .ok()
        .and_then(|s| s.trim().parse::<u64>().ok());
    [total, group]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(isize::MAX as u64)
}

/// Checks that a plan of `runs` runs of each of `configs` fits in
/// `memory` bytes when run by `workers` threads at once (`None`: merged,
/// no chains). The error names the option behind the largest part that
/// does not fit.
pub fn check_memory(
    configs: &[RunSpec],
    runs: usize,
    workers: Option<usize>,
    memory: u64,
) -> Result<(), ReproError> {
    let f = Footprint::of(configs, runs);
    let tasks = configs.len().saturating_mul(runs);
    let workers = workers.map(|w| u64::try_from(w.clamp(1, tasks.max(1))).unwrap_or(u64::MAX));
    let shown = |b: Option<u64>| b.map_or("more than 2^64".to_string(), |b| format!("{b}"));
    let over = |b: Option<u64>| b.is_none_or(|b| b > memory);
    if let Some(w) = workers {
        let at_once = f.chains.and_then(|c| c.checked_mul(w));
        if over(at_once) {
            let (n, d) = configs
                .iter()
                .map(|s| (s.chains, s.d))
                .max()
                .unwrap_or((0, 0));
            return Err(flag(
                "--n/--d",
                format!(
                    "runs of up to N = {n} chains (d = {d}) on {w} threads take {} bytes, \
                     more than this machine's {memory}",
                    shown(at_once)
                ),
            ));
        }
    }
    let parts = workers.map_or(Some(2), |w| w.checked_add(1));
    let counts = f.counts.zip(parts).and_then(|(c, p)| c.checked_mul(p));
    if over(counts) {
        return Err(flag(
            "--curve-every",
            format!(
                "the probability counters (tolerances --eps times the iterates \
                 0, r, 2r, ..., K of the curve grid, with --k) take {} bytes, \
                 more than this machine's {memory}",
                shown(counts)
            ),
        ));
    }
    if over(f.runs) {
        return Err(flag(
            "--m",
            format!(
                "the running bests of M = {runs} runs take {} bytes, more than this machine's {memory}",
                shown(f.runs)
            ),
        ));
    }
    let total = f.total(workers);
    if over(total) {
        return Err(flag(
            "--m/--n/--k",
            format!(
                "the plan takes {} bytes (chains, probability counters and running bests), \
                 more than this machine's {memory}",
                shown(total)
            ),
        ));
    }
    Ok(())
}

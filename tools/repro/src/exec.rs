//! Runs a plan: every (configuration, run) pair in parallel, with the
//! per-iterate statistics folded into per-configuration counters, into a
//! [`ProtocolResult`] (with its [`ConfigResult`]s and
//! [`CheckpointResult`]s), which the writers read.

use std::time::{Duration, Instant};

use indicatif::ProgressBar;
use rayon::prelude::*;

use crate::config::RunSpec;
use crate::engine::{RunOutcome, U_STAR, run_once};
use crate::error::ReproError;
use crate::protocol::Plan;
use crate::seed::run_seed;
use crate::split::Shard;
use crate::stats::{Summary, check_running_best, grid_points};

/// The running best of every run at one checkpoint.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckpointResult {
    /// The iterate `k`.
    pub k: u64,
    /// The running best of each run at `k`, in run order.
    pub running_best: Vec<f64>,
    /// Their summary.
    pub summary: Summary,
}

/// The results of one configuration over its M runs.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigResult {
    /// The configuration.
    pub spec: RunSpec,
    /// The running best at each checkpoint of the configuration.
    pub checkpoints: Vec<CheckpointResult>,
    /// Runs within `eps[e]` at grid iterate `j`, at `counts[e * points + j]`.
    pub counts: Vec<u32>,
    /// Chains that diverged, over all runs.
    pub diverged: usize,
    /// Evaluations of the potential over all runs (of `U` and `∇U`
    /// together for the kernel's samplers, of `U` alone for the peers).
    pub evaluations: u64,
}

/// The results of a protocol.
#[derive(Clone, Debug, PartialEq)]
pub struct ProtocolResult {
    /// The plan that was run.
    pub plan: Plan,
    /// The base seed.
    pub seed: u64,
    /// One result per configuration, in plan order.
    pub configs: Vec<ConfigResult>,
    /// Wall time of the runs (not of writing the outputs).
    pub wall: Duration,
    /// Chain-steps done, `sum M N K`.
    pub chain_steps: u64,
    /// Worker threads.
    pub threads: usize,
    /// Per configuration (in plan order), the wall time of its runs added
    /// up: how long one run takes, whatever the thread count. Measured, so
    /// not reproducible, unlike everything in [`ConfigResult`].
    pub run_wall: Vec<Duration>,
}

impl ConfigResult {
    /// The curve at tolerance `spec.eps[e]`: `(k, runs within eps at k)` at
    /// every grid iterate (nothing without a grid).
    pub fn curve(&self, e: usize) -> impl Iterator<Item = (u64, u32)> + '_ {
        let every = self.spec.curve_every.unwrap_or(1);
        let points = grid_points(self.spec.steps, self.spec.curve_every);
        (0..points).map(move |j| (j as u64 * every, self.counts[e * points + j]))
    }
}

impl ProtocolResult {
    /// Chain-steps per second of wall time (a run too short for the clock
    /// counts as 1 ns rather than dividing by 0).
    pub fn chain_steps_per_second(&self) -> f64 {
        self.chain_steps as f64 / self.wall.as_secs_f64().max(1e-9)
    }
}

/// What the runs of a plan (or of a shard of it) leave: memory is
/// `O(configurations x points x tolerances + M)`, independent of how many
/// iterates are run. Parts of one plan merge into the whole in any order.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Per configuration: runs within each tolerance at each grid point.
    pub counts: Vec<Vec<u32>>,
    /// Per configuration: `(run index, running best at each checkpoint)`.
    pub values: Vec<Vec<(usize, Vec<f64>)>>,
    /// Per configuration: chains that diverged.
    pub diverged: Vec<usize>,
    /// Per configuration: evaluations over all runs.
    pub evaluations: Vec<u64>,
    /// Per configuration: the runs' wall times added up.
    pub run_wall: Vec<Duration>,
    /// Wall time of the runs.
    pub wall: Duration,
    /// Chain-steps done.
    pub chain_steps: u64,
}

impl Part {
    /// Nothing run yet.
    pub fn empty(plan: &Plan) -> Self {
        Self {
            counts: plan
                .configs
                .iter()
                .map(|c| vec![0; c.count_len()])
                .collect(),
            values: vec![Vec::new(); plan.configs.len()],
            diverged: vec![0; plan.configs.len()],
            evaluations: vec![0; plan.configs.len()],
            run_wall: vec![Duration::ZERO; plan.configs.len()],
            wall: Duration::ZERO,
            chain_steps: 0,
        }
    }

    /// Run `i` of configuration `c` (`spec`), which left `out`: its
    /// running best checked and kept, its counters added (within the
    /// limits of a plan, none can overflow). The wall time is the caller's
    /// to add: a run's own on the CPU, a batch's on a device.
    pub fn record(
        &mut self,
        spec: &RunSpec,
        c: usize,
        i: usize,
        out: RunOutcome,
    ) -> Result<(), ReproError> {
        check_running_best(&out.running_best, &spec.checkpoints, U_STAR).map_err(|problem| {
            ReproError::FailedRun {
                config: spec.name(),
                run: i,
                problem,
            }
        })?;
        self.values[c].push((i, out.running_best));
        let over = ReproError::Overflow;
        self.diverged[c] =
            (self.diverged[c].checked_add(out.diverged)).ok_or(over("diverged chains"))?;
        self.evaluations[c] =
            (self.evaluations[c].checked_add(out.evaluations)).ok_or(over("evaluations"))?;
        self.chain_steps =
            (self.chain_steps.checked_add(spec.chain_steps())).ok_or(over("chain-steps"))?;
        Ok(())
    }

    /// Both parts' runs (wall times add up), every counter added in
    /// checked arithmetic: [`ReproError::Overflow`] names the first that
    /// would overflow. Parts of one plan's disjoint runs never do (see
    /// [`limits`](crate::limits)); parts read from files might.
    pub fn merge(mut self, other: Part) -> Result<Self, ReproError> {
        fn add<T: Copy>(
            mine: &mut T,
            theirs: T,
            checked: fn(T, T) -> Option<T>,
            what: &'static str,
        ) -> Result<(), ReproError> {
            *mine = checked(*mine, theirs).ok_or(ReproError::Overflow(what))?;
            Ok(())
        }
        for (mine, theirs) in self.counts.iter_mut().zip(other.counts) {
            for (m, t) in mine.iter_mut().zip(theirs) {
                add(m, t, u32::checked_add, "hit counts")?;
            }
        }
        for (mine, theirs) in self.values.iter_mut().zip(other.values) {
            mine.extend(theirs);
        }
        for (mine, theirs) in self.diverged.iter_mut().zip(other.diverged) {
            add(mine, theirs, usize::checked_add, "diverged chains")?;
        }
        for (mine, theirs) in self.evaluations.iter_mut().zip(other.evaluations) {
            add(mine, theirs, u64::checked_add, "evaluations")?;
        }
        for (mine, theirs) in self.run_wall.iter_mut().zip(other.run_wall) {
            add(mine, theirs, Duration::checked_add, "run wall times")?;
        }
        add(
            &mut self.wall,
            other.wall,
            Duration::checked_add,
            "wall times",
        )?;
        add(
            &mut self.chain_steps,
            other.chain_steps,
            u64::checked_add,
            "chain-steps",
        )?;
        Ok(self)
    }
}

/// Starts the worker threads of the runs on the CPU (rayon's global pool):
/// `threads`, or one per core for 0, once the count is checked
/// ([`check_threads`](crate::limits::check_threads)), so that a refused
/// count starts none. Returns how many run.
pub fn start_workers(threads: usize) -> Result<usize, ReproError> {
    crate::limits::check_threads(threads, crate::limits::cores())?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .map_err(|e| ReproError::Flag {
            flag: "--threads",
            reason: format!("cannot start {threads} worker threads: {e}"),
        })?;
    Ok(rayon::current_num_threads())
}

/// Runs every configuration `plan.runs` times on the current rayon pool.
/// Run `i` of every configuration is seeded with [`run_seed`]`(seed, i)`
/// (each of its chains then has its own stream); counts are integers and
/// the summaries are taken in run order, so the result does not depend on
/// the number of threads, nor on whether the plan ran in shards
/// ([`run_shard`], merged with [`Part::merge`] and [`finish`]). `bar`
/// advances by chain-steps.
pub fn execute(plan: &Plan, seed: u64, bar: &ProgressBar) -> Result<ProtocolResult, ReproError> {
    let part = run_shard(plan, seed, Shard::WHOLE, bar)?;
    Ok(finish(plan, seed, part, rayon::current_num_threads()))
}

/// The runs of one shard of a plan, once the plan is known to fit in the
/// machine's memory on the current rayon pool
/// ([`check_memory`](crate::limits::check_memory)). A run without a finite
/// running best at a checkpoint fails the shard
/// ([`ReproError::FailedRun`]).
pub fn run_shard(
    plan: &Plan,
    seed: u64,
    shard: Shard,
    bar: &ProgressBar,
) -> Result<Part, ReproError> {
    crate::limits::check_memory(
        &plan.configs,
        plan.runs,
        Some(rayon::current_num_threads()),
        crate::limits::machine_memory(),
    )?;
    let started = Instant::now();
    let tasks = plan.tasks(shard);
    let progress = |n: u64| bar.inc(n);
    let mut part = tasks
        .par_iter()
        // One run per rayon job: a run is long (up to 10^6 chain-steps), so
        // scheduling costs nothing, and the last runs of a protocol are
        // spread over every core instead of queued behind one.
        .with_max_len(1)
        .try_fold(
            || Part::empty(plan),
            |mut acc, &(c, i)| {
                let spec = &plan.configs[c];
                let run_started = Instant::now();
                let out = run_once(
                    spec,
                    run_seed(seed, i as u64),
                    &mut acc.counts[c],
                    &progress,
                )?;
                acc.record(spec, c, i, out)?;
                acc.run_wall[c] = (acc.run_wall[c].checked_add(run_started.elapsed()))
                    .ok_or(ReproError::Overflow("run wall times"))?;
                Ok::<_, ReproError>(acc)
            },
        )
        .try_reduce(|| Part::empty(plan), Part::merge)?;
    part.wall = started.elapsed();
    Ok(part)
}

/// The protocol's result from all its runs (every shard merged).
pub fn finish(plan: &Plan, seed: u64, part: Part, threads: usize) -> ProtocolResult {
    let configs = plan
        .configs
        .iter()
        .zip(part.counts)
        .zip(part.values)
        .zip(part.diverged)
        .zip(part.evaluations)
        .map(|((((spec, counts), mut values), diverged), evaluations)| {
            values.sort_by_key(|(i, _)| *i);
            let checkpoints = spec
                .checkpoints
                .iter()
                .enumerate()
                .map(|(c, &k)| {
                    let running_best: Vec<f64> = values.iter().map(|(_, v)| v[c]).collect();
                    CheckpointResult {
                        k,
                        // Cannot be None: plans have M >= 1.
                        summary: Summary::of(&running_best).unwrap_or(Summary::EMPTY),
                        running_best,
                    }
                })
                .collect();
            ConfigResult {
                spec: spec.clone(),
                checkpoints,
                counts,
                diverged,
                evaluations,
            }
        })
        .collect();
    ProtocolResult {
        plan: plan.clone(),
        seed,
        configs,
        wall: part.wall,
        chain_steps: part.chain_steps,
        threads,
        run_wall: part.run_wall,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::{Overrides, ProtocolId, plan};

    /// The same plan on one thread and on four gives identical results.
    #[test]
    fn results_do_not_depend_on_the_thread_count() {
        let o = Overrides {
            m: Some(6),
            k: Some(vec![60]),
            a: Some(vec![1.0, 4.0]),
            ..Overrides::default()
        };
        let p = plan(ProtocolId::E1, &o, false).unwrap();
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| execute(&p, 42, &ProgressBar::hidden()).unwrap())
        };
        let one = run(1);
        let four = run(4);
        assert_eq!(one.configs, four.configs);
        assert_eq!(one.chain_steps, 2 * 6 * 10 * 60);
        // The probability at k = 0 is that of the initial points: the same
        // for both a (common random numbers).
        // K / 500 < 1: the grid is every iterate, k = 0..=60.
        let pts = 61;
        assert_eq!(one.configs[0].counts[0], one.configs[1].counts[0]);
        assert_eq!(one.configs[0].counts.len(), 6 * pts);
    }

    /// Three shards, merged in any order, are the whole plan; they are
    /// disjoint and cover every run.
    #[test]
    fn shards_merge_into_the_whole() {
        let o = Overrides {
            m: Some(5),
            k: Some(vec![40]),
            a: Some(vec![1.0, 4.0]),
            ..Overrides::default()
        };
        let p = plan(ProtocolId::E1, &o, false).unwrap();
        let bar = ProgressBar::hidden();
        let whole = execute(&p, 7, &bar).unwrap();
        let shards: Vec<Part> = (0..3)
            .map(|index| run_shard(&p, 7, Shard { index, count: 3 }, &bar).unwrap())
            .collect();
        let mut all: Vec<(usize, usize)> = (0..3)
            .flat_map(|index| p.tasks(Shard { index, count: 3 }))
            .collect();
        all.sort();
        assert_eq!(all, p.tasks(Shard::WHOLE));
        for order in [[0, 1, 2], [2, 0, 1]] {
            let merged = order
                .iter()
                .map(|&i| shards[i].clone())
                .try_fold(Part::empty(&p), Part::merge)
                .unwrap();
            let merged = finish(&p, 7, merged, 1);
            assert_eq!(merged.configs, whole.configs);
            assert_eq!(merged.chain_steps, whole.chain_steps);
        }
    }

    /// T3 with its peers: the same results on one thread and on three,
    /// and every configuration, kernel or peer, made the evaluations the
    /// comparison table states (`N (K + 1)` per run).
    #[test]
    fn peers_do_not_depend_on_the_thread_count_and_count_their_evaluations() {
        let o = Overrides {
            m: Some(3),
            a_high: Some(vec![4.0]),
            ..Overrides::default()
        };
        let p = plan(ProtocolId::T3, &o, true).unwrap();
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| execute(&p, 7, &ProgressBar::hidden()).unwrap())
        };
        let one = run(1);
        assert_eq!(one.configs, run(3).configs);
        assert_eq!(one.configs.len(), 2 + 4 * 2);
        for c in &one.configs {
            let per_run = c.spec.evaluations_to(c.spec.steps);
            assert_eq!(c.evaluations, 3 * per_run, "{:?}", c.spec.method);
        }
    }
}

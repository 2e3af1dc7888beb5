//! Runs a plan: every (configuration, run) pair in parallel, with the
//! per-iterate statistics folded into per-configuration counters, into a
//! [`ProtocolResult`] (with its [`ConfigResult`]s and
//! [`CheckpointResult`]s), which the writers read.

use std::time::{Duration, Instant};

use indicatif::ProgressBar;
use rayon::prelude::*;

use crate::config::RunSpec;
use crate::engine::run_once;
use crate::error::ReproError;
use crate::protocol::Plan;
use crate::seed::run_seed;
use crate::stats::{Summary, grid_points};

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

/// What a worker accumulates: memory is `O(configurations x points x
/// tolerances + M)`, independent of how many iterates are run.
struct Partial {
    counts: Vec<Vec<u32>>,
    values: Vec<Vec<(usize, Vec<f64>)>>,
    diverged: Vec<usize>,
    evaluations: Vec<u64>,
    wall: Vec<Duration>,
}

impl Partial {
    fn new(plan: &Plan) -> Self {
        Self {
            counts: plan
                .configs
                .iter()
                .map(|c| vec![0; c.count_len()])
                .collect(),
            values: vec![Vec::new(); plan.configs.len()],
            diverged: vec![0; plan.configs.len()],
            evaluations: vec![0; plan.configs.len()],
            wall: vec![Duration::ZERO; plan.configs.len()],
        }
    }

    fn merge(mut self, other: Partial) -> Self {
        for (mine, theirs) in self.counts.iter_mut().zip(other.counts) {
            for (m, t) in mine.iter_mut().zip(theirs) {
                *m += t;
            }
        }
        for (mine, theirs) in self.values.iter_mut().zip(other.values) {
            mine.extend(theirs);
        }
        for (mine, theirs) in self.diverged.iter_mut().zip(other.diverged) {
            *mine += theirs;
        }
        for (mine, theirs) in self.evaluations.iter_mut().zip(other.evaluations) {
            *mine += theirs;
        }
        for (mine, theirs) in self.wall.iter_mut().zip(other.wall) {
            *mine += theirs;
        }
        self
    }
}

/// Runs every configuration `plan.runs` times on the current rayon pool.
/// Run `i` of every configuration is seeded with [`run_seed`]`(seed, i)`
/// (each of its chains then has its own stream); counts are integers and the summaries are taken in run order, so the result does
/// not depend on the number of threads. `bar` advances by chain-steps.
pub fn execute(plan: &Plan, seed: u64, bar: &ProgressBar) -> Result<ProtocolResult, ReproError> {
    let started = Instant::now();
    let tasks: Vec<(usize, usize)> = (0..plan.configs.len())
        .flat_map(|c| (0..plan.runs).map(move |i| (c, i)))
        .collect();
    let progress = |n: u64| bar.inc(n);
    let total = tasks
        .par_iter()
        // One run per rayon job: a run is long (up to 10^6 chain-steps), so
        // scheduling costs nothing, and the last runs of a protocol are
        // spread over every core instead of queued behind one.
        .with_max_len(1)
        .try_fold(
            || Partial::new(plan),
            |mut acc, &(c, i)| {
                let spec = &plan.configs[c];
                let run_started = Instant::now();
                let out = run_once(
                    spec,
                    run_seed(seed, i as u64),
                    &mut acc.counts[c],
                    &progress,
                )?;
                acc.values[c].push((i, out.running_best));
                acc.diverged[c] += out.diverged;
                acc.evaluations[c] += out.evaluations;
                acc.wall[c] += run_started.elapsed();
                Ok::<_, ReproError>(acc)
            },
        )
        .try_reduce(|| Partial::new(plan), |a, b| Ok(a.merge(b)))?;
    let wall = started.elapsed();
    let configs = plan
        .configs
        .iter()
        .zip(total.counts)
        .zip(total.values)
        .zip(total.diverged)
        .zip(total.evaluations)
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
    Ok(ProtocolResult {
        plan: plan.clone(),
        seed,
        configs,
        wall,
        chain_steps: plan.chain_steps(),
        threads: rayon::current_num_threads(),
        run_wall: total.wall,
    })
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
            let per_run = crate::compare::evaluations_to(&c.spec, c.spec.steps);
            assert_eq!(c.evaluations, 3 * per_run, "{:?}", c.spec.method);
        }
    }
}

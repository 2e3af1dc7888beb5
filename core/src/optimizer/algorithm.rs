//! The optimiser: chains stepped by a sampler's kernel at the schedule's
//! inverse temperature, the running best, and the stopping rules, written
//! once over any chain store.

use core::cell::Cell;
use core::ops::ControlFlow;

use super::executor::Serial;
use super::report::{Observe, Progress, Report};
use super::stop::{Stop, Termination};
use super::store::{Best, Origin, RunsOn, Searches, Steps, Store, diverged_start};
use super::sweep::{Context, Verdict, judge};
use crate::domain::Unbounded;
use crate::error::{Error, floor};
use crate::float::Float;
use crate::polish::{PolishEnd, PolishSettings, Polished};
use crate::sampler::{Kernel, Sampler};
use crate::schedule::Schedule;

/// Algorithm 1 of the paper with running best: independent chains of a
/// [`Sampler`] on a potential `P`, at the inverse temperatures of a
/// [`Schedule`], in a chain store `St` that holds the caller's storage,
/// stepped by `E` ([`Serial`], on the calling thread, unless the builder
/// was given an [`Executor`](crate::Executor)). Built by
/// [`Builder`](crate::Builder).
///
/// The store is [`Chains`](crate::Chains) for [`Chain`](crate::Chain)s of
/// a dimension `D` fixed at compile time (an array, a slice, a
/// `heapless::Vec`, a `Vec`), with `P` a [`Potential`](crate::Potential);
/// or [`FlatChains`](crate::FlatChains) for a dimension known at run time,
/// with `P` a [`BatchPotential`](crate::BatchPotential) whose every step
/// evaluates the new points of many chains in one call. Both give the same
/// bits for the same run.
///
/// Iterate `k` of a chain is its state after `k` steps; the step from `k`
/// to `k + 1` runs at `a_k`. The running best (per chain and global) is the
/// minimum of `U` over the iterates `k = 0, s, 2s, ...` of the stride `s`
/// (default 1); it includes the initial points: they were evaluated, and an
/// optimiser never returns worse than its start.
///
/// Every chain draws from its own generator, so a run is a pure function of
/// the seed, whatever mix of [`step`](Optimizer::step) and
/// [`run`](Optimizer::run) drives it, whatever the executor, and chain `c`
/// is the same in any run of the same seed.
#[derive(Debug)]
pub struct Optimizer<F: Float, P, S: Sampler<F>, C, St, B = Unbounded, E = Serial> {
    potential: P,
    domain: B,
    sampler: S,
    kernel: S::Kernel,
    schedule: C,
    chains: St,
    executor: E,
    best: usize,
    iteration: u64,
    evaluations: u64,
    stride: u64,
    stop: Stop<F>,
    diverged: usize,
    stall_value: F,
    stall_since: u64,
    /// The error that ended the run, returned again by every later step:
    /// a failed run stays failed. [`Error::Poisoned`] while the potential
    /// is being evaluated, so that it stays if the potential panics.
    failed: Option<Error>,
}

/// A copy of the run; [`clone_from`](Clone::clone_from) copies into the
/// chains' own storage (a `Vec` keeps its buffer), so that a front end
/// that reads the chains in place can put a run back as it was.
impl<F, P, S, C, St, B, E> Clone for Optimizer<F, P, S, C, St, B, E>
where
    F: Float,
    P: Clone,
    S: Sampler<F> + Clone,
    C: Clone,
    St: Clone,
    B: Clone,
    E: Clone,
{
    fn clone(&self) -> Self {
        Self {
            potential: self.potential.clone(),
            domain: self.domain.clone(),
            sampler: self.sampler.clone(),
            kernel: self.kernel,
            schedule: self.schedule.clone(),
            chains: self.chains.clone(),
            executor: self.executor.clone(),
            best: self.best,
            iteration: self.iteration,
            evaluations: self.evaluations,
            stride: self.stride,
            stop: self.stop,
            diverged: self.diverged,
            stall_value: self.stall_value,
            stall_since: self.stall_since,
            failed: self.failed,
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.chains.clone_from(&source.chains);
        self.potential.clone_from(&source.potential);
        self.domain.clone_from(&source.domain);
        self.sampler.clone_from(&source.sampler);
        self.kernel = source.kernel;
        self.schedule.clone_from(&source.schedule);
        self.executor.clone_from(&source.executor);
        (self.best, self.iteration, self.evaluations) =
            (source.best, source.iteration, source.evaluations);
        (self.stride, self.stop, self.diverged) = (source.stride, source.stop, source.diverged);
        (self.stall_value, self.stall_since, self.failed) =
            (source.stall_value, source.stall_since, source.failed);
    }
}

/// `settings` within `left` evaluations of the run's budget, or, none
/// left, the outcome of a local search of no evaluation from `value`.
fn within_budget<F: Float>(
    settings: PolishSettings<F>,
    left: u64,
    value: F,
) -> Result<PolishSettings<F>, Polished<F>> {
    match settings.evaluations.min(left) {
        0 => Err(Polished {
            value,
            evaluations: 0,
            iterations: 0,
            end: PolishEnd::Budget,
        }),
        evaluations => Ok(PolishSettings {
            evaluations,
            ..settings
        }),
    }
}

/// A local search's error, an unbounded potential named by its chain.
fn on_chain(e: Error, chain: usize) -> Error {
    match e {
        Error::UnboundedBelow { value, .. } => Error::UnboundedBelow { chain, value },
        e => e,
    }
}

impl<F, P, S, C, St, B, E> Optimizer<F, P, S, C, St, B, E>
where
    F: Float,
    S: Sampler<F>,
    C: Schedule<F>,
    St: Steps<F, P, B>,
    E: RunsOn<F, St, S::Kernel, P, B>,
{
    /// The optimiser over chains the builder has initialised.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn assemble(
        potential: P,
        domain: B,
        sampler: S,
        kernel: S::Kernel,
        schedule: C,
        chains: St,
        executor: E,
        evaluations: u64,
        stride: u64,
        stop: Stop<F>,
    ) -> Self {
        // The chain with the lowest initial value, the first on ties.
        let mut best = 0;
        for c in 1..chains.len() {
            if chains.best(c).value < chains.best(best).value {
                best = c;
            }
        }
        let stall_value = chains.best(best).value;
        Self {
            potential,
            domain,
            sampler,
            kernel,
            schedule,
            chains,
            executor,
            best,
            iteration: 0,
            evaluations,
            stride,
            stop,
            diverged: 0,
            stall_value,
            stall_since: 0,
            failed: None,
        }
    }

    /// Advances every live chain by one step, then evaluates `U` and `∇U` at
    /// the new points and updates the running bests; what the step did.
    /// Stopping rules are not consulted: that is [`run`](Optimizer::run)'s
    /// job.
    ///
    /// Errors: the sampler's, if it refuses the schedule's `a_k` (the state
    /// is then unchanged); [`Error::UnboundedBelow`] if a chain's potential
    /// fell to `-inf` or below `-sqrt(F::MAX)`; [`Error::AllDiverged`] once
    /// every chain has diverged; [`Error::Poisoned`] if the potential
    /// panicked during an earlier call. After any of these, every later
    /// call returns the same error: a failed run never turns into a
    /// report.
    pub fn step(&mut self) -> Result<Progress<'_, F>, Error> {
        let improved = self.guarded(Self::advance)?;
        Ok(self.progress(improved))
    }

    /// `work`, which evaluates the potential, unless the run has failed.
    /// The run is marked poisoned while it runs, so that a panic in the
    /// potential leaves it poisoned (the chains may be partly stepped, the
    /// counters stale); a run that fails in it stays failed.
    fn guarded<T>(&mut self, work: impl FnOnce(&mut Self) -> Result<T, Error>) -> Result<T, Error> {
        if let Some(e) = self.failed {
            return Err(e);
        }
        self.failed = Some(Error::Poisoned);
        let result = work(self);
        self.failed = match result {
            Err(
                e @ (Error::UnboundedBelow { .. } | Error::AllDiverged { .. } | Error::Stopped),
            ) => Some(e),
            _ => None,
        };
        result
    }

    /// One step; whether it improved the global best.
    fn advance(&mut self) -> Result<bool, Error> {
        let n = self.chains.len();
        let a = self.schedule.inverse_temperature(self.iteration);
        if a != self.kernel.inverse_temperature() {
            self.kernel = self.sampler.at(a)?;
        }
        let k = self.iteration + 1;
        let cx = Context {
            kernel: &self.kernel,
            potential: &self.potential,
            domain: &self.domain,
            k,
            record: k.is_multiple_of(self.stride),
            floor: floor(),
        };
        let before = self.chains.best(self.best).value;
        let found = self.executor.sweep(&mut self.chains, &cx);
        if found.stopped {
            return Err(Error::Stopped);
        }
        self.evaluations += found.evaluated;
        self.diverged += found.diverged;
        self.iteration = k;
        let mut best_value = before;
        if let Some((value, c)) = found.best.filter(|&(value, _)| value < before) {
            self.best = c;
            best_value = value;
        }
        if let Some((chain, value)) = found.unbounded {
            return Err(Error::UnboundedBelow {
                chain,
                value: value.to_f64(),
            });
        }
        if self.diverged == n {
            return Err(Error::AllDiverged { chains: n });
        }
        if let Some((_, tolerance)) = self.stop.stall
            && best_value < self.stall_value - tolerance
        {
            self.stall_value = best_value;
            self.stall_since = k;
        }
        Ok(best_value < before)
    }

    /// What the run has done so far, `improved` saying whether the last
    /// step improved the running best.
    fn progress(&self, improved: bool) -> Progress<'_, F> {
        Progress {
            iteration: self.iteration,
            evaluations: self.evaluations,
            best: self.best(),
            improved,
            inverse_temperature: self.kernel.inverse_temperature(),
            diverged_chains: self.diverged,
            chains: &self.chains,
        }
    }

    /// Steps until a stopping rule holds, and reports why.
    ///
    /// Errors: [`Error::NoStoppingRule`] when the run has none (no
    /// [`Stop`] rule and a schedule without a length), and those of
    /// [`step`](Optimizer::step).
    pub fn run(&mut self) -> Result<Report<F>, Error> {
        if self.stop.is_empty() {
            return Err(Error::NoStoppingRule);
        }
        self.run_with(Observe::Never, |_| ControlFlow::Continue(()))
    }

    /// [`run`](Optimizer::run) with an observer, called after the steps
    /// `when` says; returning `ControlFlow::Break(())` ends the run with
    /// [`Termination::Observer`]. Without a stopping rule, only the
    /// observer ends the run. This is the one loop of Algorithm 1: every
    /// front end runs through it.
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use hrla::{Builder, Chain, Gaussian, Hrla, Observe, Rastrigin, Stop};
    ///
    /// let mut chains: Vec<Chain<f64, 2>> = (0..8).map(|_| Chain::new()).collect();
    /// let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, Gaussian::new([3.0; 2], 1.0)?)
    ///     .stop(Stop::new().steps(5_000))
    ///     .build(&mut chains)?;
    /// let mut improvements = 0;
    /// let report = opt.run_with(Observe::EveryAndNewBest(1_000), |p| {
    ///     improvements += usize::from(p.improved);
    ///     // A time budget, a progress bar or a plot would go here.
    ///     if p.best.value < 1e-3 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    /// })?;
    /// println!("{report} ({improvements} improvements)");
    /// # Ok::<(), hrla::Error>(())
    /// ```
    pub fn run_with<O>(&mut self, when: Observe, mut observer: O) -> Result<Report<F>, Error>
    where
        O: FnMut(&Progress<'_, F>) -> ControlFlow<()>,
    {
        loop {
            // A run that failed (in a step, a polish, a quench or a
            // restart) never turns into a report, even where a stopping
            // rule already holds.
            if let Some(e) = self.failed {
                return Err(e);
            }
            if let Some(termination) = self.termination() {
                return Ok(self.report(termination));
            }
            let improved = self.guarded(Self::advance)?;
            if when.wants(self.iteration, improved) && observer(&self.progress(improved)).is_break()
            {
                return Ok(self.report(Termination::Observer));
            }
        }
    }

    /// Polishes chain `chain`'s best point with L-BFGS (an
    /// [`Lbfgs`](crate::Lbfgs) over [`Chain`](crate::Chain)s, an
    /// [`LbfgsIn`](crate::LbfgsIn) of the run's dimension over
    /// [`FlatChains`](crate::FlatChains)): the point it polishes to
    /// replaces that best when it is lower (at the current iteration), and
    /// so the global best when it is lowest. The chain's state `(x, y)` is
    /// untouched, so sampling goes on as if no polish had run. Its
    /// evaluations count in the run's, and it never exceeds what remains
    /// of the evaluation budget (none left: a polish of no evaluation that
    /// ends with [`PolishEnd::Budget`]).
    ///
    /// ```
    /// use hrla::{Builder, Chain, Gaussian, Hrla, Lbfgs, PolishSettings, Rastrigin, Stop};
    ///
    /// let mut chains: Vec<Chain<f64, 10>> = (0..10).map(|_| Chain::new()).collect();
    /// let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, Gaussian::new([3.0; 10], 3.0)?)
    ///     .stop(Stop::new().evaluations(100_000))
    ///     .build(&mut chains)?;
    /// let sampled = opt.run()?;
    /// let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
    /// let polished = opt.polish(opt.best_chain(), &mut lbfgs, PolishSettings::new(1_000))?;
    /// assert!(polished.value <= sampled.value);
    /// assert!(opt.evaluations() <= 100_000);
    /// # Ok::<(), hrla::Error>(())
    /// ```
    ///
    /// Errors: [`Error::Index`] for a chain index out of range;
    /// [`Error::Length`] for an L-BFGS of another dimension; those of
    /// [`Lbfgs::minimize`](crate::Lbfgs::minimize)
    /// ([`Error::UnboundedBelow`] naming the chain, the run then failed);
    /// the error of a run that has failed.
    pub fn polish<L>(
        &mut self,
        chain: usize,
        lbfgs: &mut L,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error>
    where
        St: Searches<F, P, B, L>,
    {
        self.local_search(chain, Origin::Best, lbfgs, settings)
    }

    /// Quenches chain `chain`: polishes a copy of its current position
    /// (not its best) with L-BFGS, to find the bottom of the basin it is
    /// in. The chain's state is untouched; the point found becomes the
    /// chain's best when lower (and so the global best when lowest), and
    /// its evaluations count in the run's, within what is left of the
    /// evaluation budget (as [`polish`](Optimizer::polish)).
    ///
    /// Errors: as [`polish`](Optimizer::polish), and [`Error::NotFinite`]
    /// (with no evaluation) for a diverged chain: its current point is
    /// not feasible.
    pub fn quench<L>(
        &mut self,
        chain: usize,
        lbfgs: &mut L,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error>
    where
        St: Searches<F, P, B, L>,
    {
        self.local_search(chain, Origin::Current, lbfgs, settings)
    }

    /// L-BFGS from chain `chain`'s best or current point, within what is
    /// left of the evaluation budget; records the result when lower.
    fn local_search<L>(
        &mut self,
        chain: usize,
        from: Origin,
        lbfgs: &mut L,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error>
    where
        St: Searches<F, P, B, L>,
    {
        self.chain_at(chain)?;
        if let Some(e) = self.failed {
            return Err(e);
        }
        self.chains.fits(lbfgs)?;
        let (x, grad, value) = self.chains.point(chain);
        if from == Origin::Current && self.chains.is_diverged(chain) {
            return Err(diverged_start(x, grad, value));
        }
        let value = match from {
            Origin::Best => self.chains.best(chain).value,
            Origin::Current => value,
        };
        let settings = match within_budget(settings, self.evaluations_left(), value) {
            Ok(settings) => settings,
            Err(nothing) => return Ok(nothing),
        };
        self.guarded(|opt| {
            // Counted here, so that a search that fails counts what it
            // spent too.
            let calls = Cell::new(0);
            let k = opt.iteration;
            let done = opt.chains.search(
                chain,
                from,
                lbfgs,
                &opt.potential,
                &opt.domain,
                settings,
                k,
                &calls,
            );
            opt.evaluations += calls.get();
            let done = done.map_err(|e| on_chain(e, chain))?;
            opt.record(chain, done.value)?;
            Ok(done)
        })
    }

    /// Chain `chain`, or [`Error::Index`].
    fn chain_at(&self, chain: usize) -> Result<usize, Error> {
        let n = self.chains.len();
        if chain < n {
            Ok(chain)
        } else {
            Err(Error::Index {
                name: "chain",
                index: chain,
                len: n,
            })
        }
    }

    /// What is left of the evaluation budget (`u64::MAX` without one).
    fn evaluations_left(&self) -> u64 {
        self.stop
            .evaluations
            .map_or(u64::MAX, |b| b.saturating_sub(self.evaluations))
    }

    /// Moves chain `chain` to `x` (confined to the domain) with zero
    /// velocity and evaluates the potential there: one evaluation, within
    /// the budget (none left: nothing happens and `Ok(false)` is
    /// returned). A non-finite position, value or gradient there marks the
    /// chain diverged (a diverged chain restarted at a feasible point
    /// lives again).
    ///
    /// Errors: [`Error::Index`] for a chain out of range;
    /// [`Error::Length`] for `x` of another dimension than the run's;
    /// [`Error::UnboundedBelow`] if the value there is below
    /// `-sqrt(F::MAX)` (the run has then failed); the error of a run that
    /// has failed.
    pub fn restart(&mut self, chain: usize, x: &[F]) -> Result<bool, Error> {
        self.chain_at(chain)?;
        let d = self.chains.dim();
        if x.len() != d {
            return Err(Error::Length {
                name: "x",
                expected: d,
                got: x.len(),
            });
        }
        if let Some(e) = self.failed {
            return Err(e);
        }
        if self.evaluations_left() == 0 {
            return Ok(false);
        }
        self.guarded(|opt| {
            let was_diverged = opt.chains.is_diverged(chain);
            let value = opt.chains.place(chain, x, &opt.potential, &opt.domain)?;
            let (x, grad, _) = opt.chains.point(chain);
            let verdict = judge(x, value, grad, floor());
            let ok = verdict == Verdict::Feasible;
            opt.chains.set_diverged(chain, !ok);
            opt.evaluations += 1;
            opt.diverged = match (was_diverged, ok) {
                (true, true) => opt.diverged - 1,
                (false, false) => opt.diverged + 1,
                _ => opt.diverged,
            };
            if ok {
                opt.chains.offer(chain, None, value, opt.iteration);
                opt.record(chain, value)?;
            } else if verdict == Verdict::Unbounded {
                return Err(Error::UnboundedBelow {
                    chain,
                    value: value.to_f64(),
                });
            }
            Ok(true)
        })
    }

    /// Makes chain `chain` the global best when its best, just offered
    /// `value`, is now the lowest: the path of every value found outside
    /// a step. A value below the floor is refused.
    fn record(&mut self, chain: usize, value: F) -> Result<(), Error> {
        if value < floor() {
            return Err(Error::UnboundedBelow {
                chain,
                value: value.to_f64(),
            });
        }
        if self.chains.best(chain).value < self.best().value {
            self.best = chain;
        }
        Ok(())
    }
}

/// What the run is and where it stands, whatever the store.
impl<F, P, S, C, St, B, E> Optimizer<F, P, S, C, St, B, E>
where
    F: Float,
    S: Sampler<F>,
    C: Schedule<F>,
    St: Store<F>,
{
    /// The first stopping rule that holds now, if any.
    pub fn termination(&self) -> Option<Termination> {
        let live = (self.chains.len() - self.diverged) as u64;
        self.stop.holds(
            self.best().value,
            self.iteration,
            self.evaluations,
            live,
            self.stall_since,
        )
    }

    /// The report of a run that ends now, for `termination`.
    pub fn report(&self, termination: Termination) -> Report<F> {
        let best = self.best();
        Report {
            value: best.value,
            chain: self.best,
            found_at: best.iteration,
            iterations: self.iteration,
            evaluations: self.evaluations,
            diverged_chains: self.diverged,
            chains: self.chains.len(),
            termination,
        }
    }

    /// Replaces the sampler between steps (for a step size chosen once the
    /// run has seen its initial points), taking its kernel at the current
    /// inverse temperature. On error the optimiser is unchanged.
    pub fn set_sampler(&mut self, sampler: S) -> Result<(), Error> {
        let a = self.schedule.inverse_temperature(self.iteration);
        self.kernel = sampler.at(a)?;
        self.sampler = sampler;
        Ok(())
    }

    /// The schedule, to change it between steps (for a schedule that
    /// adapts to the run).
    pub fn schedule_mut(&mut self) -> &mut C {
        &mut self.schedule
    }

    /// The chain that holds the global running best.
    pub fn best_chain(&self) -> usize {
        self.best
    }

    /// The global running best.
    pub fn best(&self) -> Best<'_, F> {
        self.chains.best(self.best)
    }

    /// The index and current value of the live chain with the lowest `U(x_k)`
    /// (the paper's "best chain at iterate k", not running); `None` when
    /// every chain has diverged.
    pub fn current_best(&self) -> Option<(usize, F)> {
        let mut best: Option<(usize, F)> = None;
        for c in 0..self.chains.len() {
            let value = self.chains.point(c).2;
            if !self.chains.is_diverged(c) && best.is_none_or(|(_, v)| value < v) {
                best = Some((c, value));
            }
        }
        best
    }

    /// The chains: for [`Chains`](crate::Chains), the slice of
    /// [`Chain`](crate::Chain)s; for [`FlatChains`](crate::FlatChains), the
    /// arrays.
    pub fn chains(&self) -> &St {
        &self.chains
    }

    /// Gives the chain store back.
    pub fn into_chains(self) -> St {
        self.chains
    }

    /// Steps done so far (the current iterate index `k`).
    pub fn iteration(&self) -> u64 {
        self.iteration
    }

    /// Potential-and-gradient evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Chains diverged so far.
    pub fn diverged_chains(&self) -> usize {
        self.diverged
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.chains.dim()
    }

    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }

    /// The domain of the chains.
    pub fn domain(&self) -> &B {
        &self.domain
    }

    /// The sampler.
    pub fn sampler(&self) -> &S {
        &self.sampler
    }

    /// The sampler's kernel at the inverse temperature of the last step
    /// (`a_0` before the first).
    pub fn kernel(&self) -> &S::Kernel {
        &self.kernel
    }

    /// The schedule.
    pub fn schedule(&self) -> &C {
        &self.schedule
    }

    /// The stopping rules, with the step budget a schedule's length gave.
    pub fn stop(&self) -> &Stop<F> {
        &self.stop
    }
}

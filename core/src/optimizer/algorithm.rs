//! The optimiser: chains stepped by a sampler's kernel at the schedule's
//! inverse temperature, the running best, and the stopping rules.

use core::cell::Cell;
use core::marker::PhantomData;
use core::ops::ControlFlow;

use rand_core::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::chain::{Best, Chain};
use super::executor::Executor;
use super::report::{Progress, Report};
use super::stop::{Stop, Termination};
use super::sweep::{Context, Sweep, Verdict, judge, sweep};
use crate::domain::{Domain, Unbounded};
use crate::error::{Error, floor};
use crate::float::Float;
use crate::polish::{Lbfgs, PolishEnd, PolishSettings, Polished};
use crate::potential::Potential;
use crate::sampler::{Kernel, Sampler};
use crate::schedule::Schedule;

/// Algorithm 1 of the paper with running best: independent chains of a
/// [`Sampler`] on a [`Potential`], at the inverse temperatures of a
/// [`Schedule`], in chain storage `St` that the caller owns (any
/// `AsMut<[Chain]>`: an array, a slice, a `heapless::Vec`, a `Vec`).
/// Built by [`Builder`](crate::Builder).
///
/// Iterate `k` of a chain is its state after `k` steps; the step from `k`
/// to `k + 1` runs at `a_k`. The running best (per chain and global) is the
/// minimum of `U` over the iterates `k = 0, s, 2s, ...` of the stride `s`
/// (default 1); it includes the initial points: they were evaluated, and an
/// optimiser never returns worse than its start.
///
/// Every chain draws from its own generator, so a run is a pure function of
/// the seed, whatever mix of [`step`](Optimizer::step) and
/// [`run`](Optimizer::run) drives it, and chain `c` is the same in any run
/// of the same seed.
#[derive(Clone, Debug)]
pub struct Optimizer<
    F: Float,
    P,
    S: Sampler<F>,
    C,
    St,
    const D: usize,
    R = Xoshiro256PlusPlus,
    B = Unbounded,
> {
    potential: P,
    domain: B,
    sampler: S,
    kernel: S::Kernel,
    schedule: C,
    chains: St,
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
    rng: PhantomData<fn() -> R>,
}

/// A potential whose evaluations are counted.
struct Counted<'a, P> {
    potential: &'a P,
    calls: Cell<u64>,
}

impl<F: Float, P: Potential<F, D>, const D: usize> Potential<F, D> for Counted<'_, P> {
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        self.calls.set(self.calls.get() + 1);
        self.potential.value_and_gradient(x, grad)
    }
}

/// Where a local search starts: a chain's best point or its current one.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Origin {
    Best,
    Current,
}

/// The error of a quench from a diverged chain, with no evaluation:
/// nowhere feasible to start from, and what made the chain diverge.
pub(crate) fn diverged_start<F: Float>(x: &[F], grad: &[F], value: F) -> Error {
    let bad = x.iter().chain(grad).chain([&value]);
    let value = bad.copied().find(|v| !v.is_finite()).unwrap_or(value);
    Error::NotFinite {
        name: "the point of a diverged chain",
        value: value.to_f64(),
    }
}

/// `settings` within `left` evaluations of the run's budget, or, none
/// left, the outcome of a local search of no evaluation from `value`.
pub(crate) fn within_budget<F: Float>(
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
pub(crate) fn on_chain(e: Error, chain: usize) -> Error {
    match e {
        Error::UnboundedBelow { value, .. } => Error::UnboundedBelow { chain, value },
        e => e,
    }
}

/// The count of diverged chains after a restart took a chain from
/// diverged `was` to feasible `ok`.
pub(crate) fn after_restart(diverged: usize, was: bool, ok: bool) -> usize {
    match (was, ok) {
        (true, true) => diverged - 1,
        (false, false) => diverged + 1,
        _ => diverged,
    }
}

/// What a step found out.
enum Stepped {
    Improved,
    Unchanged,
}

impl<F, P, S, C, St, const D: usize, R, B> Optimizer<F, P, S, C, St, D, R, B>
where
    F: Float,
    P: Potential<F, D>,
    S: Sampler<F>,
    C: Schedule<F>,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
    R: Rng + 'static,
    B: Domain<F, D>,
{
    /// The optimiser over chains the builder has initialised, with `best`
    /// the index of the chain with the lowest initial value.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn assemble(
        potential: P,
        domain: B,
        sampler: S,
        kernel: S::Kernel,
        schedule: C,
        chains: St,
        best: usize,
        evaluations: u64,
        stride: u64,
        stop: Stop<F>,
    ) -> Self {
        let stall_value = chains.as_ref()[best].best.value;
        Self {
            potential,
            domain,
            sampler,
            kernel,
            schedule,
            chains,
            best,
            iteration: 0,
            evaluations,
            stride,
            stop,
            diverged: 0,
            stall_value,
            stall_since: 0,
            failed: None,
            rng: PhantomData,
        }
    }

    /// Advances every live chain by one step, then evaluates `U` and `∇U` at
    /// the new points and updates the running bests. Stopping rules are
    /// not consulted: that is [`run`](Optimizer::run)'s job.
    ///
    /// Errors: the sampler's, if it refuses the schedule's `a_k` (the state
    /// is then unchanged); [`Error::UnboundedBelow`] if a chain's potential
    /// fell to `-inf` or below `-sqrt(F::MAX)`; [`Error::AllDiverged`] once
    /// every chain has diverged; [`Error::Poisoned`] if the potential
    /// panicked during an earlier call. After any of these, every later
    /// call returns the same error: a failed run never turns into a
    /// report.
    pub fn step(&mut self) -> Result<(), Error> {
        self.advance().map(drop)
    }

    fn advance(&mut self) -> Result<Stepped, Error> {
        self.advance_by(|cx, chains| sweep(cx, chains, 0))
    }

    /// A step unless the run has failed, and the failure kept if it fails.
    fn advance_by<T>(&mut self, step_chains: T) -> Result<Stepped, Error>
    where
        T: FnOnce(&Context<'_, S::Kernel, P, B, F>, &mut [Chain<F, D, R>]) -> Sweep<F>,
    {
        self.guarded(|opt| opt.advance_live(step_chains))
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
            Err(e @ (Error::UnboundedBelow { .. } | Error::AllDiverged { .. })) => Some(e),
            _ => None,
        };
        result
    }

    /// One step, the chains stepped by `step_chains`.
    fn advance_live<T>(&mut self, step_chains: T) -> Result<Stepped, Error>
    where
        T: FnOnce(&Context<'_, S::Kernel, P, B, F>, &mut [Chain<F, D, R>]) -> Sweep<F>,
    {
        let n = self.chains.as_ref().len();
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
        let before = self.chains.as_ref()[self.best].best.value;
        let found = step_chains(&cx, self.chains.as_mut());
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
        Ok(if best_value < before {
            Stepped::Improved
        } else {
            Stepped::Unchanged
        })
    }

    /// The first stopping rule that holds now, if any.
    pub fn termination(&self) -> Option<Termination> {
        let live = (self.chains.as_ref().len() - self.diverged) as u64;
        self.stop.holds(
            self.best().value,
            self.iteration,
            self.evaluations,
            live,
            self.stall_since,
        )
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
        self.run_with(0, |_| ControlFlow::Continue(()))
    }

    /// [`run`](Optimizer::run) with an observer, called after every
    /// `every`-th step (never when `every = 0`) and after every step that
    /// improves the running best; returning `ControlFlow::Break(())` ends
    /// the run with [`Termination::Observer`]. Without a stopping rule,
    /// only the observer ends the run.
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use hrla::{Builder, Chain, Gaussian, Hrla, Rastrigin, Stop};
    ///
    /// let mut chains: Vec<Chain<f64, 2>> = (0..8).map(|_| Chain::new()).collect();
    /// let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, Gaussian::new([3.0; 2], 1.0)?)
    ///     .stop(Stop::new().steps(5_000))
    ///     .build(&mut chains)?;
    /// let mut improvements = 0;
    /// let report = opt.run_with(1_000, |p| {
    ///     improvements += usize::from(p.improved);
    ///     // A time budget, a progress bar or a plot would go here.
    ///     if p.best.value < 1e-3 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    /// })?;
    /// println!("{report} ({improvements} improvements)");
    /// # Ok::<(), hrla::Error>(())
    /// ```
    pub fn run_with<O>(&mut self, every: u64, observer: O) -> Result<Report<F>, Error>
    where
        O: FnMut(&Progress<'_, F, D>) -> ControlFlow<()>,
    {
        self.run_by(every, observer, &|cx, chains| sweep(cx, chains, 0))
    }

    /// The loop of [`run_with`](Optimizer::run_with), the chains of each
    /// step stepped by `step_chains`.
    fn run_by<O, T>(
        &mut self,
        every: u64,
        mut observer: O,
        step_chains: &T,
    ) -> Result<Report<F>, Error>
    where
        O: FnMut(&Progress<'_, F, D>) -> ControlFlow<()>,
        T: Fn(&Context<'_, S::Kernel, P, B, F>, &mut [Chain<F, D, R>]) -> Sweep<F>,
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
            let stepped = self.advance_by(step_chains)?;
            let improved = matches!(stepped, Stepped::Improved);
            if improved || (every > 0 && self.iteration.is_multiple_of(every)) {
                let progress = Progress {
                    iteration: self.iteration,
                    evaluations: self.evaluations,
                    best: self.best(),
                    improved,
                    inverse_temperature: self.kernel.inverse_temperature(),
                    diverged_chains: self.diverged,
                };
                if observer(&progress).is_break() {
                    return Ok(self.report(Termination::Observer));
                }
            }
        }
    }

    fn report(&self, termination: Termination) -> Report<F> {
        let best = self.best();
        Report {
            value: best.value,
            chain: self.best,
            found_at: best.iteration,
            iterations: self.iteration,
            evaluations: self.evaluations,
            diverged_chains: self.diverged,
            chains: self.chains.as_ref().len(),
            termination,
        }
    }

    /// Polishes chain `chain`'s best point with L-BFGS ([`Lbfgs`]): the
    /// point it polishes to replaces that best when it is lower (at the
    /// current iteration), and so the global best when it is lowest. The
    /// chain's state `(x, y)` is untouched, so sampling goes on as if no
    /// polish had run. Its evaluations count in the run's, and it never
    /// exceeds what remains of the evaluation budget (none left: a polish
    /// of no evaluation that ends with [`PolishEnd::Budget`]).
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
    /// Errors: [`Error::Index`] for a chain index out of range; those of
    /// [`Lbfgs::minimize`] ([`Error::UnboundedBelow`] naming the chain, the
    /// run then failed); the error of a run that has failed.
    pub fn polish<const M: usize>(
        &mut self,
        chain: usize,
        lbfgs: &mut Lbfgs<F, D, M>,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
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
    pub fn quench<const M: usize>(
        &mut self,
        chain: usize,
        lbfgs: &mut Lbfgs<F, D, M>,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        self.local_search(chain, Origin::Current, lbfgs, settings)
    }

    /// L-BFGS from chain `chain`'s best or current point, within what is
    /// left of the evaluation budget; records the result when lower.
    fn local_search<const M: usize>(
        &mut self,
        chain: usize,
        from: Origin,
        lbfgs: &mut Lbfgs<F, D, M>,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        let c = self.chain_at(chain)?;
        if let Some(e) = self.failed {
            return Err(e);
        }
        if from == Origin::Current && c.diverged {
            return Err(diverged_start(&c.x, &c.grad, c.value));
        }
        let (mut x, value) = match from {
            Origin::Best => (c.best.x, c.best.value),
            Origin::Current => (c.x, c.value),
        };
        let settings = match within_budget(settings, self.evaluations_left(), value) {
            Ok(settings) => settings,
            Err(nothing) => return Ok(nothing),
        };
        self.guarded(|opt| {
            // Counted here, so that a polish that fails counts what it
            // spent too.
            let counted = Counted {
                potential: &opt.potential,
                calls: Cell::new(0),
            };
            let done = lbfgs.minimize_in(&counted, &opt.domain, &mut x, settings);
            opt.evaluations += counted.calls.get();
            let done = done.map_err(|e| on_chain(e, chain))?;
            opt.record(chain, &x, done.value)?;
            Ok(done)
        })
    }

    /// Chain `chain`, or [`Error::Index`].
    fn chain_at(&self, chain: usize) -> Result<&Chain<F, D, R>, Error> {
        let chains = self.chains.as_ref();
        chains.get(chain).ok_or(Error::Index {
            name: "chain",
            index: chain,
            len: chains.len(),
        })
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
    /// [`Error::UnboundedBelow`] if the value there is below
    /// `-sqrt(F::MAX)` (the run has then failed); the error of a run that
    /// has failed.
    pub fn restart(&mut self, chain: usize, x: &[F; D]) -> Result<bool, Error> {
        self.chain_at(chain)?;
        if let Some(e) = self.failed {
            return Err(e);
        }
        if self.evaluations_left() == 0 {
            return Ok(false);
        }
        self.guarded(|opt| {
            let was_diverged = opt.chains.as_ref()[chain].diverged;
            let c = &mut opt.chains.as_mut()[chain];
            c.x = *x;
            c.y = [F::ZERO; D];
            opt.domain.confine(&mut c.x, &mut c.y);
            let value = opt.potential.value_and_gradient(&c.x, &mut c.grad);
            c.value = value;
            let verdict = judge(&c.x, value, &c.grad, floor());
            let ok = verdict == Verdict::Feasible;
            c.diverged = !ok;
            opt.evaluations += 1;
            opt.diverged = after_restart(opt.diverged, was_diverged, ok);
            if ok {
                let x = opt.chains.as_ref()[chain].x;
                opt.record(chain, &x, value)?;
            } else if verdict == Verdict::Unbounded {
                return Err(Error::UnboundedBelow {
                    chain,
                    value: value.to_f64(),
                });
            }
            Ok(true)
        })
    }

    /// Makes `(x, value)` chain `chain`'s best when lower, at the current
    /// iteration, and the global best when lowest: the path of every value
    /// found outside a step. A value below the floor is refused.
    fn record(&mut self, chain: usize, x: &[F; D], value: F) -> Result<(), Error> {
        if value < floor() {
            return Err(Error::UnboundedBelow {
                chain,
                value: value.to_f64(),
            });
        }
        if value < self.chains.as_ref()[chain].best.value {
            let k = self.iteration;
            let target = &mut self.chains.as_mut()[chain].best;
            target.x = *x;
            target.value = value;
            target.iteration = k;
            if value < self.best().value {
                self.best = chain;
            }
        }
        Ok(())
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
    /// adapts to the run, such as [`Tempering`](crate::Tempering)).
    pub fn schedule_mut(&mut self) -> &mut C {
        &mut self.schedule
    }

    /// The chain that holds the global running best.
    pub fn best_chain(&self) -> usize {
        self.best
    }

    /// The global running best.
    pub fn best(&self) -> &Best<F, D> {
        &self.chains.as_ref()[self.best].best
    }

    /// The index and current value of the live chain with the lowest `U(x_k)`
    /// (the paper's "best chain at iterate k", not running); `None` when
    /// every chain has diverged.
    pub fn current_best(&self) -> Option<(usize, F)> {
        let mut best: Option<(usize, F)> = None;
        for (i, c) in self.chains.as_ref().iter().enumerate() {
            if !c.diverged && best.is_none_or(|(_, v)| c.value < v) {
                best = Some((i, c.value));
            }
        }
        best
    }

    /// The chains, in order.
    pub fn chains(&self) -> &[Chain<F, D, R>] {
        self.chains.as_ref()
    }

    /// Gives the chain storage back.
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

/// Steps on an [`Executor`]: the chains of every step in parts, on threads
/// if the executor has them, with the same bits as
/// [`step`](Optimizer::step) and [`run`](Optimizer::run) for any executor.
impl<F, P, S, C, St, const D: usize, R, B> Optimizer<F, P, S, C, St, D, R, B>
where
    F: Float,
    P: Potential<F, D> + Sync,
    S: Sampler<F>,
    S::Kernel: Sync,
    C: Schedule<F>,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
    R: Rng + Send + 'static,
    B: Domain<F, D> + Sync,
{
    /// [`step`](Optimizer::step), the chains stepped by `executor`.
    pub fn step_on<E: Executor>(&mut self, executor: &E) -> Result<(), Error> {
        self.advance_by(|cx, chains| in_parts(executor, cx, chains))
            .map(drop)
    }

    /// [`run`](Optimizer::run), the chains of every step stepped by
    /// `executor`.
    pub fn run_on<E: Executor>(&mut self, executor: &E) -> Result<Report<F>, Error> {
        if self.stop.is_empty() {
            return Err(Error::NoStoppingRule);
        }
        self.run_with_on(executor, 0, |_| ControlFlow::Continue(()))
    }

    /// [`run_with`](Optimizer::run_with), the chains of every step stepped
    /// by `executor`; the observer runs on the calling thread.
    pub fn run_with_on<E, O>(
        &mut self,
        executor: &E,
        every: u64,
        observer: O,
    ) -> Result<Report<F>, Error>
    where
        E: Executor,
        O: FnMut(&Progress<'_, F, D>) -> ControlFlow<()>,
    {
        self.run_by(every, observer, &|cx, chains| {
            in_parts(executor, cx, chains)
        })
    }
}

/// One step of `chains`, in the executor's parts.
fn in_parts<E, F, K, P, B, R, const D: usize>(
    executor: &E,
    cx: &Context<'_, K, P, B, F>,
    chains: &mut [Chain<F, D, R>],
) -> Sweep<F>
where
    E: Executor,
    F: Float,
    K: Kernel<F> + Sync,
    P: Potential<F, D> + Sync,
    B: Domain<F, D> + Sync,
    R: Rng + Send + 'static,
{
    executor
        .fold_parts(chains, |first, part| sweep(cx, part, first), Sweep::then)
        .unwrap_or(Sweep::NOTHING)
}

//! Algorithm 1 for a dimension known at run time: the chains in flat
//! slices the caller owns ([`FlatChains`]), stepped by the same kernels,
//! confined by the same reflection and judged by the same rule as
//! [`Chain`](crate::Chain)s, and evaluated through the batch seam
//! ([`BatchPotential`]): a whole step's chains in one call, or groups of
//! the size the potential asks for.
//!
//! A run of dimension `d` given as [`Dyn`](crate::Dyn)`(d)` or as
//! [`Const`](crate::Const)`<d>` gives the bits of the same run over
//! `Chain<F, d, R>`s: each chain draws the same words and does the same
//! float operations in the same order.
//!
//! The storage is chain-major: every per-chain vector is a contiguous run
//! of `d` floats, chain `c`'s at `c d..(c + 1) d`. A kernel steps one chain
//! at a time, coordinate after coordinate, from its own generator; a
//! potential reads one chain's point without a gather; and a step's points
//! are one `(n, d)` row-major block, the layout of a NumPy array or a GPU
//! buffer, which the batch seam hands over whole. (Coordinate-major
//! storage would need a gather and a scatter per evaluation.)

use core::any::{Any, TypeId};
use core::cell::Cell;
use core::marker::PhantomData;
use core::ops::ControlFlow;

use rand_core::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::executor::{Executor, Split};
use super::report::Report;
use super::stop::{Stop, Termination};
use super::sweep::{LOCKSTEP_F64_FROM, Sweep, Verdict, judge};
use crate::dim::Dim;
use crate::domain::SliceDomain;
use crate::error::{Error, floor};
use crate::float::Float;
use crate::lanes;
use crate::lockstep::{LANES, Xoshiro256Lanes};
use crate::polish::{LbfgsIn, PolishEnd, PolishSettings, Polished};
use crate::potential::{BatchPotential, SlicePotential};
use crate::sampler::{ChainSlices, Kernel, Sampler};
use crate::schedule::Schedule;

/// `n` chains of dimension `d` in storage the caller owns: the positions,
/// velocities, gradients and best points (`n d` floats each, chain-major),
/// the values and best values (`n` each) in one float slice; the best
/// points' iterations, the divergence flags and the generators in three
/// more.
///
/// ```
/// use hrla::FlatChains;
/// use rand_xoshiro::Xoshiro256PlusPlus;
/// use rand_core::SeedableRng;
///
/// let (n, d) = (32, 17);
/// let mut floats = vec![0.0f64; FlatChains::<f64, Xoshiro256PlusPlus>::floats(n, d)];
/// let mut iterations = vec![0u64; n];
/// let mut diverged = vec![false; n];
/// let mut rngs: Vec<_> = (0..n).map(|_| Xoshiro256PlusPlus::seed_from_u64(0)).collect();
/// let chains = FlatChains::new(d, &mut floats, &mut iterations, &mut diverged, &mut rngs)?;
/// assert_eq!((chains.len(), chains.dim()), (n, d));
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Debug)]
pub struct FlatChains<'a, F, R> {
    pub(crate) d: usize,
    pub(crate) x: &'a mut [F],
    pub(crate) y: &'a mut [F],
    pub(crate) grad: &'a mut [F],
    pub(crate) best_x: &'a mut [F],
    pub(crate) value: &'a mut [F],
    pub(crate) best_value: &'a mut [F],
    pub(crate) best_iteration: &'a mut [u64],
    pub(crate) diverged: &'a mut [bool],
    pub(crate) rng: &'a mut [R],
}

impl<'a, F: Float, R> FlatChains<'a, F, R> {
    /// The floats that `n` chains of dimension `d` take: `n (4 d + 2)`.
    pub const fn floats(n: usize, d: usize) -> usize {
        n * (4 * d + 2)
    }

    /// `rngs.len()` chains of dimension `d >= 1` over `floats` (length
    /// [`floats(n, d)`](FlatChains::floats)), `iterations` and `diverged`
    /// (length `n` each). Their contents are overwritten when a run is
    /// built. Errors: [`Error::Zero`] for no chain or `d = 0`,
    /// [`Error::Length`] for a slice of the wrong length.
    pub fn new(
        d: usize,
        floats: &'a mut [F],
        iterations: &'a mut [u64],
        diverged: &'a mut [bool],
        rngs: &'a mut [R],
    ) -> Result<Self, Error> {
        let n = rngs.len();
        if n == 0 {
            return Err(Error::Zero { name: "chains" });
        }
        if d == 0 {
            return Err(Error::Zero { name: "dimension" });
        }
        let expected = n.checked_mul(4 * d + 2).ok_or(Error::Length {
            name: "floats",
            expected: usize::MAX,
            got: floats.len(),
        })?;
        for (name, expected, got) in [
            ("floats", expected, floats.len()),
            ("iterations", n, iterations.len()),
            ("diverged", n, diverged.len()),
        ] {
            if got != expected {
                return Err(Error::Length {
                    name,
                    expected,
                    got,
                });
            }
        }
        let (x, rest) = floats.split_at_mut(n * d);
        let (y, rest) = rest.split_at_mut(n * d);
        let (grad, rest) = rest.split_at_mut(n * d);
        let (best_x, rest) = rest.split_at_mut(n * d);
        let (value, best_value) = rest.split_at_mut(n);
        Ok(Self {
            d,
            x,
            y,
            grad,
            best_x,
            value,
            best_value,
            best_iteration: iterations,
            diverged,
            rng: rngs,
        })
    }

    /// The number of chains.
    pub fn len(&self) -> usize {
        self.rng.len()
    }

    /// Never: storage holds at least one chain.
    pub fn is_empty(&self) -> bool {
        self.rng.is_empty()
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.d
    }

    fn span(&self, c: usize) -> core::ops::Range<usize> {
        c * self.d..(c + 1) * self.d
    }

    /// Chain `c`'s position `x_k`.
    pub fn x(&self, c: usize) -> &[F] {
        &self.x[self.span(c)]
    }
    /// Chain `c`'s velocity `y_k`.
    pub fn y(&self, c: usize) -> &[F] {
        &self.y[self.span(c)]
    }
    /// `∇U` at chain `c`'s position.
    pub fn gradient(&self, c: usize) -> &[F] {
        &self.grad[self.span(c)]
    }
    /// `U` at chain `c`'s position.
    pub fn value(&self, c: usize) -> F {
        self.value[c]
    }
    /// Chain `c`'s running best.
    pub fn best(&self, c: usize) -> BestRef<'_, F> {
        BestRef {
            x: &self.best_x[self.span(c)],
            value: self.best_value[c],
            iteration: self.best_iteration[c],
        }
    }
    /// Whether chain `c` has diverged (see [`Chain::is_diverged`](crate::Chain::is_diverged)).
    pub fn is_diverged(&self, c: usize) -> bool {
        self.diverged[c]
    }
    /// Chain `c`'s generator.
    pub fn rng(&self, c: usize) -> &R {
        &self.rng[c]
    }
    /// Every chain's position, chain-major (`n d` floats).
    pub fn positions(&self) -> &[F] {
        self.x
    }
    /// Every chain's value.
    pub fn values(&self) -> &[F] {
        self.value
    }
    /// Every chain's best point, chain-major (`n d` floats).
    pub fn best_positions(&self) -> &[F] {
        self.best_x
    }
    /// Every chain's best value.
    pub fn best_values(&self) -> &[F] {
        self.best_value
    }
}

/// Consecutive chains, split as a slice splits: the parts of a step on an
/// [`Executor`](crate::Executor)'s threads.
impl<F: Float + Send, R: Send> Split for FlatChains<'_, F, R> {
    fn len(&self) -> usize {
        self.rng.len()
    }

    fn is_empty(&self) -> bool {
        self.rng.is_empty()
    }

    fn split_at(self, mid: usize) -> (Self, Self) {
        let d = self.d;
        let (x0, x1) = self.x.split_at_mut(mid * d);
        let (y0, y1) = self.y.split_at_mut(mid * d);
        let (g0, g1) = self.grad.split_at_mut(mid * d);
        let (b0, b1) = self.best_x.split_at_mut(mid * d);
        let (v0, v1) = self.value.split_at_mut(mid);
        let (w0, w1) = self.best_value.split_at_mut(mid);
        let (i0, i1) = self.best_iteration.split_at_mut(mid);
        let (d0, d1) = self.diverged.split_at_mut(mid);
        let (r0, r1) = self.rng.split_at_mut(mid);
        let part = |x, y, grad, best_x, value, best_value, best_iteration, diverged, rng| Self {
            d,
            x,
            y,
            grad,
            best_x,
            value,
            best_value,
            best_iteration,
            diverged,
            rng,
        };
        (
            part(x0, y0, g0, b0, v0, w0, i0, d0, r0),
            part(x1, y1, g1, b1, v1, w1, i1, d1, r1),
        )
    }
}

impl<F, R> FlatChains<'_, F, R> {
    /// The same chains, borrowed for a shorter time.
    fn reborrow(&mut self) -> FlatChains<'_, F, R> {
        FlatChains {
            d: self.d,
            x: &mut *self.x,
            y: &mut *self.y,
            grad: &mut *self.grad,
            best_x: &mut *self.best_x,
            value: &mut *self.value,
            best_value: &mut *self.best_value,
            best_iteration: &mut *self.best_iteration,
            diverged: &mut *self.diverged,
            rng: &mut *self.rng,
        }
    }
}

/// A chain's best point, in [`FlatChains`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BestRef<'a, F> {
    /// The position.
    pub x: &'a [F],
    /// `U(x)`.
    pub value: F,
    /// The iterate index `k` (0 is the initial point).
    pub iteration: u64,
}

/// What [`FlatOptimizer::run_with`]'s observer sees.
#[derive(Clone, Copy, Debug)]
pub struct FlatProgress<'a, F> {
    /// Steps done.
    pub iteration: u64,
    /// Potential evaluations so far.
    pub evaluations: u64,
    /// The global running best.
    pub best: BestRef<'a, F>,
    /// Whether this step improved the global running best.
    pub improved: bool,
    /// The inverse temperature of the last step.
    pub inverse_temperature: F,
    /// Chains diverged so far.
    pub diverged_chains: usize,
}

/// [`Optimizer`](crate::Optimizer) over [`FlatChains`], for a dimension
/// `Dm` known at compile time ([`Const`](crate::Const)) or at run time
/// ([`Dyn`](crate::Dyn)). Built by
/// [`Builder::build_flat`](crate::Builder::build_flat).
///
/// Each step moves the live chains, then evaluates their new points through
/// [`BatchPotential::values_and_gradients`]: all of them in one call, or in
/// groups of the size the potential asks for
/// ([`BatchPotential::chains_per_call`]).
#[derive(Debug)]
pub struct FlatOptimizer<'a, F: Float, P, S: Sampler<F>, C, Dm, R, B> {
    potential: P,
    domain: B,
    sampler: S,
    kernel: S::Kernel,
    schedule: C,
    chains: FlatChains<'a, F, R>,
    dim: Dm,
    best: usize,
    iteration: u64,
    evaluations: u64,
    stride: u64,
    stop: Stop<F>,
    diverged: usize,
    stall_value: F,
    stall_since: u64,
    failed: Option<Error>,
    rng: PhantomData<fn() -> R>,
}

impl<'a, F, P, S, C, Dm, R, B> FlatOptimizer<'a, F, P, S, C, Dm, R, B>
where
    F: Float,
    P: BatchPotential<F>,
    S: Sampler<F>,
    C: Schedule<F>,
    Dm: Dim,
    R: Rng + 'static,
    B: SliceDomain<F>,
{
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn assemble(
        potential: P,
        domain: B,
        sampler: S,
        kernel: S::Kernel,
        schedule: C,
        chains: FlatChains<'a, F, R>,
        dim: Dm,
        best: usize,
        evaluations: u64,
        stride: u64,
        stop: Stop<F>,
    ) -> Self {
        let stall_value = chains.best_value[best];
        Self {
            potential,
            domain,
            sampler,
            kernel,
            schedule,
            chains,
            dim,
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

    /// As [`Optimizer::step`](crate::Optimizer::step).
    pub fn step(&mut self) -> Result<(), Error> {
        self.advance().map(drop)
    }

    /// `work` unless the run has failed; poisoned while it runs, failed
    /// after if it fails for good (as the const optimiser's).
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

    /// One step; `true` when it improved the global best.
    fn advance(&mut self) -> Result<bool, Error> {
        self.advance_by(|cx, chains| sweep_flat(cx, chains, 0))
    }

    /// A step unless the run has failed, the chains stepped by
    /// `step_chains`.
    fn advance_by<T>(&mut self, step_chains: T) -> Result<bool, Error>
    where
        T: FnOnce(&FlatContext<'_, S::Kernel, P, B>, FlatChains<'_, F, R>) -> Sweep<F>,
    {
        self.guarded(|opt| opt.advance_live(step_chains))
    }

    fn advance_live<T>(&mut self, step_chains: T) -> Result<bool, Error>
    where
        T: FnOnce(&FlatContext<'_, S::Kernel, P, B>, FlatChains<'_, F, R>) -> Sweep<F>,
    {
        let n = self.chains.len();
        let a = self.schedule.inverse_temperature(self.iteration);
        if a != self.kernel.inverse_temperature() {
            self.kernel = self.sampler.at(a)?;
        }
        let k = self.iteration + 1;
        let before = self.chains.best_value[self.best];
        let cx = FlatContext {
            kernel: &self.kernel,
            potential: &self.potential,
            domain: &self.domain,
            d: self.dim.value(),
            k,
            record: k.is_multiple_of(self.stride),
        };
        let found = step_chains(&cx, self.chains.reborrow());
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

    /// As [`Optimizer::termination`](crate::Optimizer::termination).
    pub fn termination(&self) -> Option<Termination> {
        let live = (self.chains.len() - self.diverged) as u64;
        self.stop.holds(
            self.chains.best_value[self.best],
            self.iteration,
            self.evaluations,
            live,
            self.stall_since,
        )
    }

    /// As [`Optimizer::run`](crate::Optimizer::run).
    pub fn run(&mut self) -> Result<Report<F>, Error> {
        if self.stop.is_empty() {
            return Err(Error::NoStoppingRule);
        }
        self.run_with(0, |_| ControlFlow::Continue(()))
    }

    /// As [`Optimizer::run_with`](crate::Optimizer::run_with).
    pub fn run_with<O>(&mut self, every: u64, mut observer: O) -> Result<Report<F>, Error>
    where
        O: FnMut(&FlatProgress<'_, F>) -> ControlFlow<()>,
    {
        loop {
            if let Some(e) = self.failed {
                return Err(e);
            }
            if let Some(termination) = self.termination() {
                return Ok(self.report(termination));
            }
            let improved = self.advance()?;
            if improved || (every > 0 && self.iteration.is_multiple_of(every)) {
                let progress = FlatProgress {
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
            chains: self.chains.len(),
            termination,
        }
    }

    /// As [`Optimizer::polish`](crate::Optimizer::polish), with L-BFGS in
    /// caller storage of the run's dimension ([`Error::Length`] otherwise).
    pub fn polish(
        &mut self,
        chain: usize,
        lbfgs: &mut LbfgsIn<'_, F>,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        let n = self.chains.len();
        if chain >= n {
            return Err(Error::Index {
                name: "chain",
                index: chain,
                len: n,
            });
        }
        if let Some(e) = self.failed {
            return Err(e);
        }
        let d = self.chains.d;
        if lbfgs.dimension() != d {
            return Err(Error::Length {
                name: "L-BFGS dimension",
                expected: d,
                got: lbfgs.dimension(),
            });
        }
        let value = self.chains.best_value[chain];
        let left = self
            .stop
            .evaluations
            .map_or(u64::MAX, |b| b.saturating_sub(self.evaluations));
        let budget = settings.evaluations.min(left);
        if budget == 0 {
            return Ok(Polished {
                value,
                evaluations: 0,
                iterations: 0,
                end: PolishEnd::Budget,
            });
        }
        let settings = PolishSettings {
            evaluations: budget,
            ..settings
        };
        self.guarded(|opt| {
            let span = opt.chains.span(chain);
            // Counted here, so that a polish that fails counts what it
            // spent too.
            let counted = Counted {
                potential: &opt.potential,
                calls: Cell::new(0),
            };
            let (done, x) = lbfgs.minimize_from(
                &counted,
                &opt.domain,
                &opt.chains.best_x[span.clone()],
                settings,
            );
            opt.evaluations += counted.calls.get();
            let done = done.map_err(|e| match e {
                Error::UnboundedBelow { value, .. } => Error::UnboundedBelow { chain, value },
                e => e,
            })?;
            if done.value < floor() {
                return Err(Error::UnboundedBelow {
                    chain,
                    value: done.value.to_f64(),
                });
            }
            if done.value < opt.chains.best_value[chain] {
                opt.chains.best_x[span].copy_from_slice(x);
                opt.chains.best_value[chain] = done.value;
                opt.chains.best_iteration[chain] = opt.iteration;
                if done.value < opt.chains.best_value[opt.best] {
                    opt.best = chain;
                }
            }
            Ok(done)
        })
    }

    /// The chain that holds the global running best.
    pub fn best_chain(&self) -> usize {
        self.best
    }

    /// The global running best.
    pub fn best(&self) -> BestRef<'_, F> {
        self.chains.best(self.best)
    }

    /// The chains.
    pub fn chains(&self) -> &FlatChains<'a, F, R> {
        &self.chains
    }

    /// Gives the chain storage back.
    pub fn into_chains(self) -> FlatChains<'a, F, R> {
        self.chains
    }

    /// Steps done so far.
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
    pub fn dim(&self) -> Dm {
        self.dim
    }

    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }

    /// The sampler's kernel at the inverse temperature of the last step.
    pub fn kernel(&self) -> &S::Kernel {
        &self.kernel
    }

    /// The stopping rules.
    pub fn stop(&self) -> &Stop<F> {
        &self.stop
    }
}

/// Steps on an [`Executor`]: the chains of every step in parts, on
/// threads if the executor has them, with the same bits as
/// [`step`](FlatOptimizer::step) and [`run`](FlatOptimizer::run) for any
/// executor. Each part evaluates its own chains through the batch seam.
impl<F, P, S, C, Dm, R, B> FlatOptimizer<'_, F, P, S, C, Dm, R, B>
where
    F: Float + Send,
    P: BatchPotential<F> + Sync,
    S: Sampler<F>,
    S::Kernel: Sync,
    C: Schedule<F>,
    Dm: Dim,
    R: Rng + Send + 'static,
    B: SliceDomain<F> + Sync,
{
    /// [`step`](FlatOptimizer::step), the chains stepped by `executor`.
    pub fn step_on<E: Executor>(&mut self, executor: &E) -> Result<(), Error> {
        self.advance_by(|cx, chains| in_parts(executor, cx, chains))
            .map(drop)
    }

    /// [`run`](FlatOptimizer::run), the chains of every step stepped by
    /// `executor`.
    pub fn run_on<E: Executor>(&mut self, executor: &E) -> Result<Report<F>, Error> {
        if self.stop.is_empty() {
            return Err(Error::NoStoppingRule);
        }
        loop {
            if let Some(e) = self.failed {
                return Err(e);
            }
            if let Some(termination) = self.termination() {
                return Ok(self.report(termination));
            }
            self.advance_by(|cx, chains| in_parts(executor, cx, chains))?;
        }
    }
}

/// One step of `chains`, in the executor's parts.
fn in_parts<E, F, K, P, B, R>(
    executor: &E,
    cx: &FlatContext<'_, K, P, B>,
    chains: FlatChains<'_, F, R>,
) -> Sweep<F>
where
    E: Executor,
    F: Float + Send,
    K: Kernel<F> + Sync,
    P: BatchPotential<F> + Sync,
    B: SliceDomain<F> + Sync,
    R: Rng + Send + 'static,
{
    executor
        .fold_split(
            chains,
            |first, part| sweep_flat(cx, part, first),
            Sweep::then,
        )
        .unwrap_or(Sweep::NOTHING)
}

/// What every chain's step needs: the kernel, the potential, the domain,
/// the dimension, the new iterate's index and whether it is recorded.
pub(crate) struct FlatContext<'a, K, P, B> {
    kernel: &'a K,
    potential: &'a P,
    domain: &'a B,
    d: usize,
    k: u64,
    record: bool,
}

/// A potential whose evaluations are counted.
struct Counted<'a, P> {
    potential: &'a P,
    calls: Cell<u64>,
}

/// One point at a time through the batch seam: a batch of one.
impl<F: Float, P: BatchPotential<F>> SlicePotential<F> for Counted<'_, P> {
    #[inline]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        self.calls.set(self.calls.get() + 1);
        let mut value = [F::INFINITY];
        self.potential
            .values_and_gradients(x.len(), x, grad, &mut value, &[false]);
        value[0]
    }
}

/// One step of every live chain of `chains`, by groups of chains of the
/// size the potential asks for (a multiple of [`LANES`]): each group moved
/// (by [`LANES`] in lockstep where the const path would), confined, then
/// evaluated in one batch and judged in chain order.
fn sweep_flat<F, K, P, B, R>(
    cx: &FlatContext<'_, K, P, B>,
    mut chains: FlatChains<'_, F, R>,
    offset: usize,
) -> Sweep<F>
where
    F: Float,
    K: Kernel<F>,
    P: BatchPotential<F>,
    B: SliceDomain<F>,
    R: Rng + 'static,
{
    let (kernel, potential, d) = (cx.kernel, cx.potential, cx.d);
    let chains = &mut chains;
    let n = chains.len();
    let lockstep = lanes::VECTORS
        && TypeId::of::<R>() == TypeId::of::<Xoshiro256PlusPlus>()
        && (F::MANTISSA_DIGITS <= 24 || d >= LOCKSTEP_F64_FROM);
    let grouped = if lockstep { n / LANES * LANES } else { 0 };
    let per_call = potential
        .chains_per_call()
        .map_or(n, |g| g.max(1).next_multiple_of(LANES));
    let mut found = Sweep::NOTHING;
    let mut first = 0;
    while first < n {
        let end = n.min(first.saturating_add(per_call));
        let mut c = first;
        while c < end {
            if c + LANES <= grouped.min(end) {
                let live = chains.diverged[c..c + LANES].iter().all(|&v| !v);
                if !(live && step_group(kernel, chains, c, d)) {
                    for i in c..c + LANES {
                        step_one(kernel, chains, i, d);
                    }
                }
                c += LANES;
            } else {
                step_one(kernel, chains, c, d);
                c += 1;
            }
        }
        evaluate_group(cx, chains, first..end, offset, &mut found);
        first = end;
    }
    found
}

/// Confines the stepped chains `group`, evaluates them in one batch and
/// judges them in order, recording their bests.
#[inline(always)]
fn evaluate_group<F, K, P, B, R>(
    cx: &FlatContext<'_, K, P, B>,
    chains: &mut FlatChains<'_, F, R>,
    group: core::ops::Range<usize>,
    offset: usize,
    found: &mut Sweep<F>,
) where
    F: Float,
    P: BatchPotential<F>,
    B: SliceDomain<F>,
{
    let (potential, domain, d) = (cx.potential, cx.domain, cx.d);
    let points = group.start * d..group.end * d;
    for ((x, y), &dead) in chains.x[points.clone()]
        .chunks_exact_mut(d)
        .zip(chains.y[points.clone()].chunks_exact_mut(d))
        .zip(&chains.diverged[group.clone()])
    {
        if !dead {
            domain.confine(x, y);
        }
    }
    potential.values_and_gradients(
        d,
        &chains.x[points.clone()],
        &mut chains.grad[points],
        &mut chains.value[group.clone()],
        &chains.diverged[group.clone()],
    );
    for c in group {
        if chains.diverged[c] {
            continue;
        }
        let span = c * d..(c + 1) * d;
        let value = chains.value[c];
        found.evaluated += 1;
        match judge(
            &chains.x[span.clone()],
            value,
            &chains.grad[span.clone()],
            floor(),
        ) {
            Verdict::Feasible => {}
            verdict => {
                // Frozen, so that a non-finite value or one below the
                // floor never becomes the best.
                if verdict == Verdict::Unbounded {
                    found.unbounded.get_or_insert((offset + c, value));
                }
                chains.diverged[c] = true;
                found.diverged += 1;
                continue;
            }
        }
        if cx.record && value < chains.best_value[c] {
            chains.best_x[span.clone()].copy_from_slice(&chains.x[span]);
            chains.best_value[c] = value;
            chains.best_iteration[c] = cx.k;
            if found.best.is_none_or(|(b, _)| value < b) {
                found.best = Some((value, offset + c));
            }
        }
    }
}

/// Steps chain `c` unless it has diverged.
#[inline(always)]
fn step_one<F: Float, K: Kernel<F>, R: Rng>(
    kernel: &K,
    chains: &mut FlatChains<'_, F, R>,
    c: usize,
    d: usize,
) {
    if !chains.diverged[c] {
        let span = c * d..(c + 1) * d;
        kernel.step_slice(
            &mut chains.x[span.clone()],
            &mut chains.y[span.clone()],
            &chains.grad[span],
            &mut chains.rng[c],
        );
    }
}

/// Steps the live chains `c..c + LANES` in lockstep; `false` (nothing
/// stepped) if their generators are not xoshiro256++.
#[inline]
fn step_group<F, K, R>(kernel: &K, chains: &mut FlatChains<'_, F, R>, c: usize, d: usize) -> bool
where
    F: Float,
    K: Kernel<F>,
    R: 'static,
{
    let span = c * d..(c + LANES) * d;
    let mut xs = chains.x[span.clone()].chunks_exact_mut(d);
    let mut ys = chains.y[span.clone()].chunks_exact_mut(d);
    let mut gs = chains.grad[span].chunks_exact(d);
    let mut part = || -> Option<ChainSlices<'_, F>> {
        Some(ChainSlices {
            x: xs.next()?,
            y: ys.next()?,
            grad: gs.next()?,
        })
    };
    let (Some(p0), Some(p1), Some(p2), Some(p3)) = (part(), part(), part(), part()) else {
        return false;
    };
    let [r0, r1, r2, r3] = &mut chains.rng[c..c + LANES] else {
        return false;
    };
    let generators =
        [r0, r1, r2, r3].map(|r| (r as &mut dyn Any).downcast_mut::<Xoshiro256PlusPlus>());
    let [Some(g0), Some(g1), Some(g2), Some(g3)] = generators else {
        return false;
    };
    let mut lanes = Xoshiro256Lanes::load([&*g0, &*g1, &*g2, &*g3]);
    kernel.step_lanes_slice([p0, p1, p2, p3], &mut lanes);
    lanes.store([g0, g1, g2, g3]);
    true
}

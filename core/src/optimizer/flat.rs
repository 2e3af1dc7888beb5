//! Algorithm 1 for a dimension known at run time: the chains in flat
//! arrays the caller owns or lends ([`FlatChains`]), stepped by the same kernels,
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

use super::algorithm::{Origin, after_restart, diverged_start, on_chain, within_budget};
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
use crate::polish::{LbfgsIn, PolishSettings, Polished};
use crate::potential::{BatchPotential, SlicePotential};
use crate::sampler::{ChainSlices, Kernel, Sampler};
use crate::schedule::Schedule;

/// Storage of `T`s that [`FlatChains`] reads and writes: any
/// `AsRef<[T]> + AsMut<[T]>`, such as `&mut [T]` or `[T; N]` on firmware,
/// `Vec<T>` or `Box<[T]>` on a host.
pub trait FlatStorage<T>: AsRef<[T]> + AsMut<[T]> {}

impl<T, S: AsRef<[T]> + AsMut<[T]> + ?Sized> FlatStorage<T> for S {}

/// `n` chains of dimension `d` in storage the caller owns: the positions,
/// velocities, gradients and best points (`n d` floats each, chain-major),
/// the values and best values (`n` each) in one float array `Fs`; the best
/// points' iterations, the divergence flags and the generators in three
/// more (`Is`, `Ds`, `Rs`). Each is any [`FlatStorage`]: borrowed slices
/// ([`FlatSlices`]) where the caller keeps the arrays, owned vectors where
/// the chains (and the [`FlatOptimizer`] that holds them) must live on
/// their own.
///
/// ```
/// use hrla::{FlatChains, FlatSlices};
/// use rand_xoshiro::Xoshiro256PlusPlus;
/// use rand_core::SeedableRng;
///
/// let (n, d) = (32, 17);
/// // Borrowed: the caller keeps the arrays.
/// let mut floats = vec![0.0f64; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(n, d)];
/// let mut iterations = vec![0u64; n];
/// let mut diverged = vec![false; n];
/// let mut rngs: Vec<_> = (0..n).map(|_| Xoshiro256PlusPlus::seed_from_u64(0)).collect();
/// let chains = FlatChains::new(d, &mut floats, &mut iterations, &mut diverged, &mut rngs)?;
/// assert_eq!((chains.len(), chains.dim()), (n, d));
/// // Owned: the chains hold their arrays, and give them back.
/// let chains = FlatChains::new(d, floats, iterations, diverged, rngs)?;
/// let (floats, ..) = chains.into_storage();
/// assert_eq!(floats.len(), n * (4 * d + 2));
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Debug)]
pub struct FlatChains<F, R, Fs, Is, Ds, Rs> {
    d: usize,
    floats: Fs,
    iterations: Is,
    diverged: Ds,
    rngs: Rs,
    item: PhantomData<fn() -> (F, R)>,
}

/// [`FlatChains`] over slices the caller keeps.
pub type FlatSlices<'a, F, R> =
    FlatChains<F, R, &'a mut [F], &'a mut [u64], &'a mut [bool], &'a mut [R]>;

impl<F, R, Fs, Is, Ds, Rs> FlatChains<F, R, Fs, Is, Ds, Rs> {
    /// The floats that `n` chains of dimension `d` take: `n (4 d + 2)`,
    /// saturating at `usize::MAX`, a length no storage has.
    pub const fn floats(n: usize, d: usize) -> usize {
        n.saturating_mul(d.saturating_mul(4).saturating_add(2))
    }

    /// Gives the arrays back: floats, iterations, divergence flags,
    /// generators.
    pub fn into_storage(self) -> (Fs, Is, Ds, Rs) {
        (self.floats, self.iterations, self.diverged, self.rngs)
    }
}

impl<F, R, Fs, Is, Ds, Rs> FlatChains<F, R, Fs, Is, Ds, Rs>
where
    F: Float,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
{
    /// `rngs.len()` chains of dimension `d >= 1` over `floats` (length
    /// [`floats(n, d)`](FlatChains::floats)), `iterations` and `diverged`
    /// (length `n` each). Their contents are overwritten when a run is
    /// built. Errors: [`Error::Zero`] for no chain or `d = 0`,
    /// [`Error::Length`] for an array of the wrong length.
    pub fn new(
        d: usize,
        floats: Fs,
        iterations: Is,
        diverged: Ds,
        rngs: Rs,
    ) -> Result<Self, Error> {
        let n = rngs.as_ref().len();
        if n == 0 {
            return Err(Error::Zero { name: "chains" });
        }
        if d == 0 {
            return Err(Error::Zero { name: "dimension" });
        }
        for (name, expected, got) in [
            ("floats", Self::floats(n, d), floats.as_ref().len()),
            ("iterations", n, iterations.as_ref().len()),
            ("diverged", n, diverged.as_ref().len()),
        ] {
            if got != expected {
                return Err(Error::Length {
                    name,
                    expected,
                    got,
                });
            }
        }
        Ok(Self {
            d,
            floats,
            iterations,
            diverged,
            rngs,
            item: PhantomData,
        })
    }

    /// The number of chains.
    pub fn len(&self) -> usize {
        self.rngs.as_ref().len()
    }

    /// Never: storage holds at least one chain.
    pub fn is_empty(&self) -> bool {
        self.rngs.as_ref().is_empty()
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.d
    }

    /// The `n d` floats from field `k` of the layout (0: positions, 1:
    /// velocities, 2: gradients, 3: best points).
    fn block(&self, k: usize) -> &[F] {
        let nd = self.len() * self.d;
        &self.floats.as_ref()[k * nd..(k + 1) * nd]
    }

    fn span(&self, c: usize) -> core::ops::Range<usize> {
        c * self.d..(c + 1) * self.d
    }

    /// Chain `c`'s position `x_k`.
    pub fn x(&self, c: usize) -> &[F] {
        &self.positions()[self.span(c)]
    }
    /// Chain `c`'s velocity `y_k`.
    pub fn y(&self, c: usize) -> &[F] {
        &self.block(1)[self.span(c)]
    }
    /// `∇U` at chain `c`'s position.
    pub fn gradient(&self, c: usize) -> &[F] {
        &self.block(2)[self.span(c)]
    }
    /// `U` at chain `c`'s position.
    pub fn value(&self, c: usize) -> F {
        self.values()[c]
    }
    /// Chain `c`'s running best.
    pub fn best(&self, c: usize) -> BestRef<'_, F> {
        BestRef {
            x: &self.best_positions()[self.span(c)],
            value: self.best_values()[c],
            iteration: self.iterations.as_ref()[c],
        }
    }
    /// Whether chain `c` has diverged (see [`Chain::is_diverged`](crate::Chain::is_diverged)).
    pub fn is_diverged(&self, c: usize) -> bool {
        self.diverged.as_ref()[c]
    }
    /// Chain `c`'s generator.
    pub fn rng(&self, c: usize) -> &R {
        &self.rngs.as_ref()[c]
    }
    /// Every chain's position, chain-major (`n d` floats).
    pub fn positions(&self) -> &[F] {
        self.block(0)
    }
    /// Every chain's value.
    pub fn values(&self) -> &[F] {
        let (n, nd) = (self.len(), self.len() * self.d);
        &self.floats.as_ref()[4 * nd..4 * nd + n]
    }
    /// Every chain's best point, chain-major (`n d` floats).
    pub fn best_positions(&self) -> &[F] {
        self.block(3)
    }
    /// Every chain's best value.
    pub fn best_values(&self) -> &[F] {
        let (n, nd) = (self.len(), self.len() * self.d);
        &self.floats.as_ref()[4 * nd + n..]
    }

    /// The arrays cut into the fields of the layout, to be written.
    pub(crate) fn parts(&mut self) -> Parts<'_, F, R> {
        let (d, n) = (self.d, self.len());
        let (x, rest) = self.floats.as_mut().split_at_mut(n * d);
        let (y, rest) = rest.split_at_mut(n * d);
        let (grad, rest) = rest.split_at_mut(n * d);
        let (best_x, rest) = rest.split_at_mut(n * d);
        let (value, best_value) = rest.split_at_mut(n);
        Parts {
            d,
            x,
            y,
            grad,
            best_x,
            value,
            best_value,
            best_iteration: self.iterations.as_mut(),
            diverged: self.diverged.as_mut(),
            rng: self.rngs.as_mut(),
        }
    }
}

/// [`FlatChains`]' arrays cut into their fields: what a step writes.
pub(crate) struct Parts<'a, F, R> {
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

impl<F, R> Parts<'_, F, R> {
    fn len(&self) -> usize {
        self.rng.len()
    }
}

/// Consecutive chains, split as a slice splits: the parts of a step on an
/// [`Executor`](crate::Executor)'s threads.
impl<F: Float + Send, R: Send> Split for Parts<'_, F, R> {
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
/// [`Builder::build_flat`](crate::Builder::build_flat). It holds the
/// chains, so it borrows what they borrow: over [`FlatSlices`] it lives
/// as long as the slices, over owned arrays (`Vec`s on a host) as long as
/// its owner wants.
///
/// Each step moves the live chains, then evaluates their new points through
/// [`BatchPotential::values_and_gradients`]: all of them in one call, or in
/// groups of the size the potential asks for
/// ([`BatchPotential::chains_per_call`]).
#[derive(Debug)]
pub struct FlatOptimizer<F: Float, P, S: Sampler<F>, C, Dm, R, B, Fs, Is, Ds, Rs> {
    potential: P,
    domain: B,
    sampler: S,
    kernel: S::Kernel,
    schedule: C,
    chains: FlatChains<F, R, Fs, Is, Ds, Rs>,
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
}

impl<F, P, S, C, Dm, R, B, Fs, Is, Ds, Rs> FlatOptimizer<F, P, S, C, Dm, R, B, Fs, Is, Ds, Rs>
where
    F: Float,
    P: BatchPotential<F>,
    S: Sampler<F>,
    C: Schedule<F>,
    Dm: Dim,
    R: Rng + 'static,
    B: SliceDomain<F>,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
{
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn assemble(
        potential: P,
        domain: B,
        sampler: S,
        kernel: S::Kernel,
        schedule: C,
        chains: FlatChains<F, R, Fs, Is, Ds, Rs>,
        dim: Dm,
        best: usize,
        evaluations: u64,
        stride: u64,
        stop: Stop<F>,
    ) -> Self {
        let stall_value = chains.best_values()[best];
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
        T: FnOnce(&FlatContext<'_, S::Kernel, P, B>, Parts<'_, F, R>) -> Sweep<F>,
    {
        self.guarded(|opt| opt.advance_live(step_chains))
    }

    fn advance_live<T>(&mut self, step_chains: T) -> Result<bool, Error>
    where
        T: FnOnce(&FlatContext<'_, S::Kernel, P, B>, Parts<'_, F, R>) -> Sweep<F>,
    {
        let n = self.chains.len();
        let a = self.schedule.inverse_temperature(self.iteration);
        if a != self.kernel.inverse_temperature() {
            self.kernel = self.sampler.at(a)?;
        }
        let k = self.iteration + 1;
        let before = self.chains.best_values()[self.best];
        let cx = FlatContext {
            kernel: &self.kernel,
            potential: &self.potential,
            domain: &self.domain,
            d: self.dim.value(),
            k,
            record: k.is_multiple_of(self.stride),
        };
        let found = step_chains(&cx, self.chains.parts());
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
            self.chains.best_values()[self.best],
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
    pub fn run_with<O>(&mut self, every: u64, observer: O) -> Result<Report<F>, Error>
    where
        O: FnMut(&FlatProgress<'_, F>) -> ControlFlow<()>,
    {
        self.run_by(every, observer, &|cx, chains| sweep_flat(cx, chains, 0))
    }

    /// The loop of [`run_with`](FlatOptimizer::run_with), the chains of
    /// each step stepped by `step_chains`.
    fn run_by<O, T>(
        &mut self,
        every: u64,
        mut observer: O,
        step_chains: &T,
    ) -> Result<Report<F>, Error>
    where
        O: FnMut(&FlatProgress<'_, F>) -> ControlFlow<()>,
        T: Fn(&FlatContext<'_, S::Kernel, P, B>, Parts<'_, F, R>) -> Sweep<F>,
    {
        loop {
            if let Some(e) = self.failed {
                return Err(e);
            }
            if let Some(termination) = self.termination() {
                return Ok(self.report(termination));
            }
            let improved = self.advance_by(step_chains)?;
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
        self.local_search(chain, Origin::Best, lbfgs, settings)
    }

    /// As [`Optimizer::quench`](crate::Optimizer::quench): L-BFGS from a
    /// copy of chain `chain`'s current position, in caller storage of the
    /// run's dimension ([`Error::Length`] otherwise).
    pub fn quench(
        &mut self,
        chain: usize,
        lbfgs: &mut LbfgsIn<'_, F>,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        self.local_search(chain, Origin::Current, lbfgs, settings)
    }

    /// L-BFGS from chain `chain`'s best or current point, within what is
    /// left of the evaluation budget; records the result when lower.
    fn local_search(
        &mut self,
        chain: usize,
        from: Origin,
        lbfgs: &mut LbfgsIn<'_, F>,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        self.chain_at(chain)?;
        if let Some(e) = self.failed {
            return Err(e);
        }
        let d = self.chains.dim();
        if lbfgs.dimension() != d {
            return Err(Error::Length {
                name: "L-BFGS dimension",
                expected: d,
                got: lbfgs.dimension(),
            });
        }
        let c = &self.chains;
        if from == Origin::Current && c.is_diverged(chain) {
            return Err(diverged_start(
                c.x(chain),
                c.gradient(chain),
                c.value(chain),
            ));
        }
        let value = match from {
            Origin::Best => c.best_values()[chain],
            Origin::Current => c.value(chain),
        };
        let settings = match within_budget(settings, self.evaluations_left(), value) {
            Ok(settings) => settings,
            Err(nothing) => return Ok(nothing),
        };
        self.guarded(|opt| {
            // Counted here, so that a search that fails counts what it
            // spent too.
            let counted = Counted {
                potential: &opt.potential,
                calls: Cell::new(0),
            };
            let start = match from {
                Origin::Best => opt.chains.best(chain).x,
                Origin::Current => opt.chains.x(chain),
            };
            let (done, x) = lbfgs.minimize_from(&counted, &opt.domain, start, settings);
            opt.evaluations += counted.calls.get();
            let done = done.map_err(|e| on_chain(e, chain))?;
            opt.record(chain, Some(x), done.value)?;
            Ok(done)
        })
    }

    /// As [`Optimizer::restart`](crate::Optimizer::restart), with `x` of
    /// the run's dimension ([`Error::Length`] otherwise). The point is
    /// evaluated through the batch seam, as a batch of one.
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
            let p = opt.chains.parts();
            let span = chain * d..(chain + 1) * d;
            let was_diverged = p.diverged[chain];
            let (xc, yc) = (&mut p.x[span.clone()], &mut p.y[span.clone()]);
            xc.copy_from_slice(x);
            yc.fill(F::ZERO);
            opt.domain.confine(xc, yc);
            opt.potential.values_and_gradients(
                d,
                xc,
                &mut p.grad[span.clone()],
                &mut p.value[chain..=chain],
                &[false],
            );
            let value = p.value[chain];
            let verdict = judge(&p.x[span.clone()], value, &p.grad[span], floor());
            let ok = verdict == Verdict::Feasible;
            p.diverged[chain] = !ok;
            opt.evaluations += 1;
            opt.diverged = after_restart(opt.diverged, was_diverged, ok);
            if ok {
                opt.record(chain, None, value)?;
            } else if verdict == Verdict::Unbounded {
                return Err(Error::UnboundedBelow {
                    chain,
                    value: value.to_f64(),
                });
            }
            Ok(true)
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

    /// Makes `value` at `x` (`None`: the chain's position) chain `chain`'s
    /// best when lower, at the current iteration, and the global best when
    /// lowest: the path of every value found outside a step. A value below
    /// the floor is refused.
    fn record(&mut self, chain: usize, x: Option<&[F]>, value: F) -> Result<(), Error> {
        if value < floor() {
            return Err(Error::UnboundedBelow {
                chain,
                value: value.to_f64(),
            });
        }
        let (k, global) = (self.iteration, self.chains.best_values()[self.best]);
        let p = self.chains.parts();
        if value < p.best_value[chain] {
            let span = chain * p.d..(chain + 1) * p.d;
            p.best_x[span.clone()].copy_from_slice(x.unwrap_or(&p.x[span]));
            p.best_value[chain] = value;
            p.best_iteration[chain] = k;
            if value < global {
                self.best = chain;
            }
        }
        Ok(())
    }

    /// As [`Optimizer::set_sampler`](crate::Optimizer::set_sampler).
    pub fn set_sampler(&mut self, sampler: S) -> Result<(), Error> {
        let a = self.schedule.inverse_temperature(self.iteration);
        self.kernel = sampler.at(a)?;
        self.sampler = sampler;
        Ok(())
    }

    /// As [`Optimizer::schedule_mut`](crate::Optimizer::schedule_mut).
    pub fn schedule_mut(&mut self) -> &mut C {
        &mut self.schedule
    }

    /// The chain that holds the global running best.
    pub fn best_chain(&self) -> usize {
        self.best
    }

    /// The global running best.
    pub fn best(&self) -> BestRef<'_, F> {
        self.chains.best(self.best)
    }

    /// As [`Optimizer::current_best`](crate::Optimizer::current_best).
    pub fn current_best(&self) -> Option<(usize, F)> {
        let c = &self.chains;
        let mut best: Option<(usize, F)> = None;
        for (i, &value) in c.values().iter().enumerate() {
            if !c.is_diverged(i) && best.is_none_or(|(_, v)| value < v) {
                best = Some((i, value));
            }
        }
        best
    }

    /// The chains.
    pub fn chains(&self) -> &FlatChains<F, R, Fs, Is, Ds, Rs> {
        &self.chains
    }

    /// Gives the chain storage back.
    pub fn into_chains(self) -> FlatChains<F, R, Fs, Is, Ds, Rs> {
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

    /// The domain of the chains.
    pub fn domain(&self) -> &B {
        &self.domain
    }

    /// The sampler.
    pub fn sampler(&self) -> &S {
        &self.sampler
    }

    /// The sampler's kernel at the inverse temperature of the last step.
    pub fn kernel(&self) -> &S::Kernel {
        &self.kernel
    }

    /// The schedule.
    pub fn schedule(&self) -> &C {
        &self.schedule
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
impl<F, P, S, C, Dm, R, B, Fs, Is, Ds, Rs> FlatOptimizer<F, P, S, C, Dm, R, B, Fs, Is, Ds, Rs>
where
    F: Float + Send,
    P: BatchPotential<F> + Sync,
    S: Sampler<F>,
    S::Kernel: Sync,
    C: Schedule<F>,
    Dm: Dim,
    R: Rng + Send + 'static,
    B: SliceDomain<F> + Sync,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
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
        self.run_with_on(executor, 0, |_| ControlFlow::Continue(()))
    }

    /// [`run_with`](FlatOptimizer::run_with), the chains of every step
    /// stepped by `executor`; the observer runs on the calling thread.
    pub fn run_with_on<E, O>(
        &mut self,
        executor: &E,
        every: u64,
        observer: O,
    ) -> Result<Report<F>, Error>
    where
        E: Executor,
        O: FnMut(&FlatProgress<'_, F>) -> ControlFlow<()>,
    {
        self.run_by(every, observer, &|cx, chains| {
            in_parts(executor, cx, chains)
        })
    }
}

/// One step of `chains`, in the executor's parts.
fn in_parts<E, F, K, P, B, R>(
    executor: &E,
    cx: &FlatContext<'_, K, P, B>,
    chains: Parts<'_, F, R>,
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
    mut chains: Parts<'_, F, R>,
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
    chains: &mut Parts<'_, F, R>,
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
    chains: &mut Parts<'_, F, R>,
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
fn step_group<F, K, R>(kernel: &K, chains: &mut Parts<'_, F, R>, c: usize, d: usize) -> bool
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

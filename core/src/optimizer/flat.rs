//! Algorithm 1 for a dimension known at run time: the chains in flat
//! arrays the caller owns or lends ([`FlatChains`]), stepped by the same kernels,
//! confined by the same reflection and judged by the same rule as
//! [`Chain`](crate::Chain)s, and evaluated through the batch seam
//! ([`BatchPotential`]): a whole step's chains in one call, or groups of
//! the size the potential asks for.
//!
//! A run of dimension `d` gives the bits of the same run over
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

use rand_core::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::executor::{Executor, Split};
use super::store::{
    Best, Counted, IntoStore, Origin, Origins, Searches, Starts, Steps, StepsOn, Store,
};
use super::stream::chain_seed;
use super::sweep::{Context, LOCKSTEP_F64_FROM, Sweep, Verdict, judge, settle_point};
use crate::domain::Domain;
use crate::error::{Error, check_lengths, floor};
use crate::float::Float;
use crate::lanes;
use crate::lockstep::{LANES, Xoshiro256Lanes};
use crate::polish::{LbfgsIn, PolishSettings, Polished};
use crate::potential::traits::one_point;
use crate::potential::{BatchPotential, SlicePotential};
use crate::sampler::{ChainState, Kernel};
use crate::start::Start;

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
/// the chains (and the [`Optimizer`](crate::Optimizer) that holds them)
/// must live on their own.
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

/// A copy of the chains; [`clone_from`](Clone::clone_from) copies into
/// this storage (a `Vec` of the same length keeps its buffer).
impl<F, R, Fs: Clone, Is: Clone, Ds: Clone, Rs: Clone> Clone for FlatChains<F, R, Fs, Is, Ds, Rs> {
    fn clone(&self) -> Self {
        Self {
            d: self.d,
            floats: self.floats.clone(),
            iterations: self.iterations.clone(),
            diverged: self.diverged.clone(),
            rngs: self.rngs.clone(),
            item: PhantomData,
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.d = source.d;
        self.floats.clone_from(&source.floats);
        self.iterations.clone_from(&source.iterations);
        self.diverged.clone_from(&source.diverged);
        self.rngs.clone_from(&source.rngs);
    }
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
        check_lengths([
            ("floats", Self::floats(n, d), floats.as_ref().len()),
            ("iterations", n, iterations.as_ref().len()),
            ("diverged", n, diverged.as_ref().len()),
        ])?;
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
    pub fn best(&self, c: usize) -> Best<'_, F> {
        Best {
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

impl<F, R, Fs, Is, Ds, Rs> IntoStore<F, Self> for FlatChains<F, R, Fs, Is, Ds, Rs>
where
    F: Float,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
{
    type Store = Self;
    fn into_store(self) -> Self {
        self
    }
}

impl<F, R, Fs, Is, Ds, Rs> Store<F> for FlatChains<F, R, Fs, Is, Ds, Rs>
where
    F: Float,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
{
    fn len(&self) -> usize {
        self.rngs.as_ref().len()
    }
    fn dim(&self) -> usize {
        self.d
    }
    fn point(&self, c: usize) -> (&[F], &[F], F) {
        (self.x(c), self.gradient(c), self.value(c))
    }
    fn is_diverged(&self, c: usize) -> bool {
        self.diverged.as_ref()[c]
    }
    fn set_diverged(&mut self, c: usize, diverged: bool) {
        self.diverged.as_mut()[c] = diverged;
    }
    fn best(&self, c: usize) -> Best<'_, F> {
        FlatChains::best(self, c)
    }
    fn set_best(&mut self, c: usize, x: Option<&[F]>, value: F, k: u64) {
        let p = self.parts();
        let span = c * p.d..(c + 1) * p.d;
        p.best_x[span.clone()].copy_from_slice(x.unwrap_or(&p.x[span]));
        p.best_value[c] = value;
        p.best_iteration[c] = k;
    }
}

impl<F, R, Fs, Is, Ds, Rs, P, B> Steps<F, P, B> for FlatChains<F, R, Fs, Is, Ds, Rs>
where
    F: Float,
    R: Rng + 'static,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
    P: BatchPotential<F>,
    B: Domain<F>,
{
    fn sweep<K: Kernel<F>>(&mut self, cx: &Context<'_, K, P, B, F>) -> Sweep<F> {
        sweep_flat(cx, self.parts(), 0)
    }

    /// Evaluated through the batch seam, as a batch of one.
    fn place(&mut self, c: usize, x: &[F], potential: &P, domain: &B) -> Result<F, Error> {
        let d = self.d;
        let p = self.parts();
        let span = c * d..(c + 1) * d;
        let (xc, yc) = (&mut p.x[span.clone()], &mut p.y[span.clone()]);
        xc.copy_from_slice(x);
        yc.fill(F::ZERO);
        domain.confine(xc, yc);
        let grad = &mut p.grad[span];
        match potential.values_and_gradients(d, xc, grad, &mut p.value[c..=c], &[false]) {
            ControlFlow::Continue(()) => Ok(p.value[c]),
            ControlFlow::Break(()) => Err(Error::Stopped),
        }
    }
}

/// Each part evaluates its own chains through the batch seam.
impl<F, R, Fs, Is, Ds, Rs, P, B> StepsOn<F, P, B> for FlatChains<F, R, Fs, Is, Ds, Rs>
where
    F: Float + Send,
    R: Rng + Send + 'static,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
    P: BatchPotential<F> + Sync,
    B: Domain<F> + Sync,
{
    fn sweep_on<K: Kernel<F> + Sync, E: Executor>(
        &mut self,
        executor: &E,
        cx: &Context<'_, K, P, B, F>,
    ) -> Sweep<F> {
        executor
            .fold_split(
                self.parts(),
                |first, part| sweep_flat(cx, part, first),
                Sweep::then,
            )
            .unwrap_or(Sweep::NOTHING)
    }
}

/// The initial points are evaluated in one batch (redraws one by one).
impl<F, R, Fs, Is, Ds, Rs, P, B, Sd> Starts<F, P, B, Sd> for FlatChains<F, R, Fs, Is, Ds, Rs>
where
    F: Float,
    R: Rng + SeedableRng + 'static,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
    P: BatchPotential<F>,
    B: Domain<F>,
    Sd: Start<F>,
{
    fn check(&self, from: &Origins<'_, P, B, Sd>) -> [(&'static str, Option<usize>); 3] {
        [
            ("box sides", from.domain.dimension()),
            ("start", from.start.dimension()),
            ("potential", from.potential.batch_dimension()),
        ]
    }

    fn start(&mut self, from: Origins<'_, P, B, Sd>, spare: &mut u64) -> Result<u64, Error> {
        let Origins {
            potential,
            domain,
            start,
            seed,
        } = from;
        let n = self.len();
        let mut evaluations = n as u64;
        let Parts {
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
        } = self.parts();
        for (c, ((x, y), rng)) in x
            .chunks_exact_mut(d)
            .zip(y.chunks_exact_mut(d))
            .zip(rng.iter_mut())
            .enumerate()
        {
            *rng = R::seed_from_u64(chain_seed(seed, c as u64));
            start.initial_point(c, rng, x);
            y.fill(F::ZERO);
            domain.confine(x, y);
        }
        diverged.fill(false);
        if potential
            .values_and_gradients(d, x, grad, value, diverged)
            .is_break()
        {
            return Err(Error::Stopped);
        }
        let stopped = Cell::new(false);
        for c in 0..n {
            let span = c * d..(c + 1) * d;
            let (xc, yc) = (&mut x[span.clone()], &mut y[span.clone()]);
            let rng = &mut rng[c];
            value[c] = settle_point(
                c,
                xc,
                &mut grad[span],
                value[c],
                spare,
                &mut evaluations,
                |xc, grad| {
                    start.initial_point(c, rng, xc);
                    yc.fill(F::ZERO);
                    domain.confine(xc, yc);
                    // A stop reads as -inf, below the floor: the redraws
                    // end at once.
                    one_point(potential, xc, grad, &stopped)
                },
            )
            .map_err(|e| if stopped.get() { Error::Stopped } else { e })?;
        }
        best_x.copy_from_slice(x);
        best_value.copy_from_slice(value);
        best_iteration.fill(0);
        Ok(evaluations)
    }
}

/// L-BFGS in caller storage of the run's dimension ([`Error::Length`]
/// otherwise).
impl<F, R, Fs, Is, Ds, Rs, P, B> Searches<F, P, B, LbfgsIn<'_, F>>
    for FlatChains<F, R, Fs, Is, Ds, Rs>
where
    F: Float,
    Fs: FlatStorage<F>,
    Is: FlatStorage<u64>,
    Ds: FlatStorage<bool>,
    Rs: FlatStorage<R>,
    P: BatchPotential<F>,
    B: Domain<F>,
{
    fn fits(&self, lbfgs: &LbfgsIn<'_, F>) -> Result<(), Error> {
        if lbfgs.dimension() == self.d {
            Ok(())
        } else {
            Err(Error::Length {
                name: "L-BFGS dimension",
                expected: self.d,
                got: lbfgs.dimension(),
            })
        }
    }

    fn search(
        &mut self,
        c: usize,
        from: Origin,
        lbfgs: &mut LbfgsIn<'_, F>,
        potential: &P,
        domain: &B,
        settings: PolishSettings<F>,
        k: u64,
        calls: &Cell<u64>,
    ) -> Result<Polished<F>, Error> {
        let counted = Counted::new(potential, calls);
        let start = match from {
            Origin::Best => FlatChains::best(self, c).x,
            Origin::Current => self.x(c),
        };
        let (done, x) = lbfgs.minimize_from(&counted, domain, start, settings);
        if counted.stopped.get() {
            return Err(Error::Stopped);
        }
        let done = done?;
        self.offer(c, Some(x), done.value, k);
        Ok(done)
    }
}

/// One point at a time through the batch seam ([`one_point`]): a stop ends
/// the search at once, and its caller reports [`Error::Stopped`].
impl<F: Float, P: BatchPotential<F>> SlicePotential<F> for Counted<'_, P> {
    #[inline]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        self.calls.set(self.calls.get() + 1);
        one_point(self.potential, x, grad, &self.stopped)
    }
}

/// One step of every live chain of `chains`, by groups of chains of the
/// size the potential asks for (a multiple of [`LANES`]): each group moved
/// (by [`LANES`] in lockstep where the const path would), confined, then
/// evaluated in one batch and judged in chain order.
fn sweep_flat<F, K, P, B, R>(
    cx: &Context<'_, K, P, B, F>,
    mut chains: Parts<'_, F, R>,
    offset: usize,
) -> Sweep<F>
where
    F: Float,
    K: Kernel<F>,
    P: BatchPotential<F>,
    B: Domain<F>,
    R: Rng + 'static,
{
    let (kernel, potential, d) = (cx.kernel, cx.potential, chains.d);
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
        if found.stopped {
            break;
        }
        first = end;
    }
    found
}

/// Confines the stepped chains `group`, evaluates them in one batch and
/// judges them in order, recording their bests.
#[inline(always)]
fn evaluate_group<F, K, P, B, R>(
    cx: &Context<'_, K, P, B, F>,
    chains: &mut Parts<'_, F, R>,
    group: core::ops::Range<usize>,
    offset: usize,
    found: &mut Sweep<F>,
) where
    F: Float,
    P: BatchPotential<F>,
    B: Domain<F>,
{
    let (potential, domain, d) = (cx.potential, cx.domain, chains.d);
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
    let asked = potential.values_and_gradients(
        d,
        &chains.x[points.clone()],
        &mut chains.grad[points],
        &mut chains.value[group.clone()],
        &chains.diverged[group.clone()],
    );
    if asked.is_break() {
        found.stopped = true;
        return;
    }
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
    let mut part = || -> Option<ChainState<'_, [F]>> {
        Some(ChainState {
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

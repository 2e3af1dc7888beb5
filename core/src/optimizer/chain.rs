//! The const-generic chain store: one [`Chain`] per chain, its dimension
//! `D` in the type, in any container the caller owns ([`Chains`]).

use core::any::{Any, TypeId};
use core::cell::Cell;
use core::marker::PhantomData;
use core::ops::{Deref, DerefMut};

use rand_core::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::executor::Executor;
use super::store::{
    Best, Counted, IntoStore, Origin, Origins, Searches, Starts, Steps, StepsOn, Store,
};
use super::stream::chain_seed;
use super::sweep::{Context, LOCKSTEP_F64_FROM, Sweep, Verdict, draw_point, judge};
use crate::domain::Domain;
use crate::error::Error;
use crate::float::Float;
use crate::lanes;
use crate::lockstep::{LANES, Xoshiro256Lanes};
use crate::polish::{Arrays, Lbfgs, PolishSettings, Polished};
use crate::potential::Potential;
use crate::sampler::{ChainState, Kernel};
use crate::start::Start;

/// A chain's best point, kept in the chain: one block, as the step writes
/// it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Kept<F, const D: usize> {
    pub(crate) x: [F; D],
    pub(crate) value: F,
    pub(crate) iteration: u64,
}

/// One chain: its state `(x, y)`, the potential and gradient at `x`, its
/// own running best, and its own random generator `R`.
///
/// Storage for the optimiser: make as many as the run has chains (their
/// contents are overwritten when the run is built), in whatever container
/// suits the target.
///
/// ```
/// use hrla::Chain;
///
/// // On a host: on the heap, any number.
/// let chains: Vec<Chain<f64, 10>> = (0..10_000).map(|_| Chain::new()).collect();
/// // On firmware: an array (or a `static`), with a 32-bit generator.
/// let small: [Chain<f32, 2, rand_xoshiro::Xoshiro128PlusPlus>; 16] =
///     core::array::from_fn(|_| Chain::default());
/// # assert_eq!(chains.len() + small.len(), 10_016);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Chain<F, const D: usize, R = Xoshiro256PlusPlus> {
    pub(crate) x: [F; D],
    pub(crate) y: [F; D],
    pub(crate) value: F,
    pub(crate) grad: [F; D],
    pub(crate) best: Kept<F, D>,
    pub(crate) diverged: bool,
    pub(crate) rng: R,
}

impl<F: Float, const D: usize> Chain<F, D> {
    /// An empty chain with the default generator, `Xoshiro256PlusPlus`.
    pub fn new() -> Self {
        Self::default()
    }
}

impl<F: Float, const D: usize, R: SeedableRng> Default for Chain<F, D, R> {
    /// An empty chain, to be filled by [`Builder::build`](crate::Builder::build).
    fn default() -> Self {
        Self {
            x: [F::ZERO; D],
            y: [F::ZERO; D],
            value: F::INFINITY,
            grad: [F::ZERO; D],
            best: Kept {
                x: [F::ZERO; D],
                value: F::INFINITY,
                iteration: 0,
            },
            diverged: false,
            rng: R::seed_from_u64(0),
        }
    }
}

impl<F: Float, const D: usize, R> Chain<F, D, R> {
    /// Current position `x_k`.
    pub fn x(&self) -> &[F; D] {
        &self.x
    }
    /// Current velocity `y_k` (zero throughout for samplers without one).
    pub fn y(&self) -> &[F; D] {
        &self.y
    }
    /// `U(x_k)`; for a diverged chain, the value at the step that stopped it
    /// (non-finite, or finite beside a non-finite position or gradient).
    pub fn value(&self) -> F {
        self.value
    }
    /// `∇U(x_k)`.
    pub fn gradient(&self) -> &[F; D] {
        &self.grad
    }
    /// The chain's running best over its recorded iterates.
    pub fn best(&self) -> Best<'_, F> {
        Best {
            x: &self.best.x,
            value: self.best.value,
            iteration: self.best.iteration,
        }
    }
    /// `true` once the position, the potential or its gradient went
    /// non-finite: the chain is then frozen (no more steps, no more random
    /// draws) and excluded from the best.
    pub fn is_diverged(&self) -> bool {
        self.diverged
    }
    /// The chain's own generator, in its current state.
    pub fn rng(&self) -> &R {
        &self.rng
    }
}

/// [`Chain`]s of dimension `D` in a container `St` the caller owns (an
/// array, a slice, a `heapless::Vec`, a `Vec`): the store an
/// [`Optimizer`](crate::Optimizer) runs over when
/// [`Builder::build`](crate::Builder::build) is given such a container. It
/// reads as the slice of its chains.
#[derive(Clone, Debug)]
pub struct Chains<F, St, const D: usize, R = Xoshiro256PlusPlus> {
    chains: St,
    item: PhantomData<fn() -> (F, R)>,
}

impl<F, St, const D: usize, R> Chains<F, St, D, R> {
    /// Gives the container back.
    pub fn into_inner(self) -> St {
        self.chains
    }
}

impl<F, St: AsRef<[Chain<F, D, R>]>, const D: usize, R> Deref for Chains<F, St, D, R> {
    type Target = [Chain<F, D, R>];
    fn deref(&self) -> &Self::Target {
        self.chains.as_ref()
    }
}

impl<F, St: AsMut<[Chain<F, D, R>]> + AsRef<[Chain<F, D, R>]>, const D: usize, R> DerefMut
    for Chains<F, St, D, R>
{
    fn deref_mut(&mut self) -> &mut Self::Target {
        self.chains.as_mut()
    }
}

impl<'a, F, St: AsRef<[Chain<F, D, R>]>, const D: usize, R> IntoIterator
    for &'a Chains<F, St, D, R>
{
    type Item = &'a Chain<F, D, R>;
    type IntoIter = core::slice::Iter<'a, Chain<F, D, R>>;
    fn into_iter(self) -> Self::IntoIter {
        self.chains.as_ref().iter()
    }
}

impl<F, St, const D: usize, R> IntoStore<F, Chain<F, D, R>> for St
where
    F: Float,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
{
    type Store = Chains<F, St, D, R>;
    fn into_store(self) -> Self::Store {
        Chains {
            chains: self,
            item: PhantomData,
        }
    }
}

impl<F, St, const D: usize, R> Store<F> for Chains<F, St, D, R>
where
    F: Float,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
{
    fn len(&self) -> usize {
        self.chains.as_ref().len()
    }
    fn dim(&self) -> usize {
        D
    }
    fn point(&self, c: usize) -> (&[F], &[F], F) {
        let chain = &self[c];
        (&chain.x, &chain.grad, chain.value)
    }
    fn is_diverged(&self, c: usize) -> bool {
        self[c].diverged
    }
    fn set_diverged(&mut self, c: usize, diverged: bool) {
        self[c].diverged = diverged;
    }
    fn best(&self, c: usize) -> Best<'_, F> {
        self[c].best()
    }
    fn set_best(&mut self, c: usize, x: Option<&[F]>, value: F, k: u64) {
        let chain = &mut self[c];
        match x {
            Some(x) => chain.best.x.copy_from_slice(x),
            None => chain.best.x = chain.x,
        }
        chain.best.value = value;
        chain.best.iteration = k;
    }
}

impl<F, St, const D: usize, R, P, B> Steps<F, P, B> for Chains<F, St, D, R>
where
    F: Float,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
    R: Rng + 'static,
    P: Potential<F, D>,
    B: Domain<F>,
{
    fn sweep<K: Kernel<F>>(&mut self, cx: &Context<'_, K, P, B, F>) -> Sweep<F> {
        sweep(cx, self, 0)
    }

    fn place(&mut self, c: usize, x: &[F], potential: &P, domain: &B) -> Result<F, Error> {
        let chain = &mut self[c];
        chain.x.copy_from_slice(x);
        chain.y = [F::ZERO; D];
        domain.confine(&mut chain.x, &mut chain.y);
        chain.value = potential.value_and_gradient(&chain.x, &mut chain.grad);
        Ok(chain.value)
    }
}

impl<F, St, const D: usize, R, P, B> StepsOn<F, P, B> for Chains<F, St, D, R>
where
    F: Float,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
    R: Rng + Send + 'static,
    P: Potential<F, D> + Sync,
    B: Domain<F> + Sync,
{
    fn sweep_on<K: Kernel<F> + Sync, E: Executor>(
        &mut self,
        executor: &E,
        cx: &Context<'_, K, P, B, F>,
    ) -> Sweep<F> {
        executor
            .fold_parts(self, |first, part| sweep(cx, part, first), Sweep::then)
            .unwrap_or(Sweep::NOTHING)
    }
}

impl<F, St, const D: usize, R, P, B, Sd> Starts<F, P, B, Sd> for Chains<F, St, D, R>
where
    F: Float,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
    R: Rng + SeedableRng + 'static,
    P: Potential<F, D>,
    B: Domain<F>,
    Sd: Start<F>,
{
    fn check(&self, from: &Origins<'_, P, B, Sd>) -> [(&'static str, Option<usize>); 3] {
        [
            ("box sides", from.domain.dimension()),
            ("start", from.start.dimension()),
            ("potential", None),
        ]
    }

    fn start(&mut self, from: Origins<'_, P, B, Sd>, spare: &mut u64) -> Result<u64, Error> {
        let Origins {
            potential,
            domain,
            start,
            seed,
        } = from;
        let mut evaluations = 0;
        for (c, chain) in self.iter_mut().enumerate() {
            chain.rng = R::seed_from_u64(chain_seed(seed, c as u64));
            draw_start(c, chain, potential, spare, &mut evaluations, |rng, x, y| {
                start.initial_point(c, rng, x.as_mut_slice());
                *y = [F::ZERO; D];
                domain.confine(x, y);
            })?;
            chain.best.x = chain.x;
            chain.best.value = chain.value;
            chain.best.iteration = 0;
            chain.diverged = false;
        }
        Ok(evaluations)
    }
}

impl<F, St, const D: usize, R, P, B, const M: usize> Searches<F, P, B, Lbfgs<F, D, M>>
    for Chains<F, St, D, R>
where
    F: Float,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
    P: Potential<F, D>,
    B: Domain<F>,
{
    fn search(
        &mut self,
        c: usize,
        from: Origin,
        lbfgs: &mut Lbfgs<F, D, M>,
        potential: &P,
        domain: &B,
        settings: PolishSettings<F>,
        k: u64,
        calls: &Cell<u64>,
    ) -> Result<Polished<F>, Error> {
        let chain = &self[c];
        let mut x = match from {
            Origin::Best => chain.best.x,
            Origin::Current => chain.x,
        };
        let counted = Counted::new(potential, calls);
        let done = lbfgs.minimize_in(&counted, domain, &mut x, settings)?;
        self.offer(c, Some(&x), done.value, k);
        Ok(done)
    }
}

impl<F: Float, P: Potential<F, D>, const D: usize> Potential<F, D> for Counted<'_, P> {
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        self.calls.set(self.calls.get() + 1);
        self.potential.value_and_gradient(x, grad)
    }
}

/// Draws chain `c`'s initial point with `place` (which writes `x` and `y`
/// from the chain's generator) and evaluates it, drawing again where the
/// point is infeasible: [`draw_point`] on the
/// chain's arrays.
pub(crate) fn draw_start<F, P, R, const D: usize>(
    c: usize,
    chain: &mut Chain<F, D, R>,
    potential: &P,
    spare: &mut u64,
    evaluations: &mut u64,
    mut place: impl FnMut(&mut R, &mut [F; D], &mut [F; D]),
) -> Result<(), Error>
where
    F: Float,
    P: Potential<F, D> + ?Sized,
{
    let Chain {
        x,
        y,
        grad,
        rng,
        value,
        ..
    } = chain;
    *value = draw_point(
        c,
        x,
        grad,
        rng,
        &Arrays::<_, D>(potential),
        spare,
        evaluations,
        |rng, x| {
            if let Ok(x) = <&mut [F; D]>::try_from(x) {
                place(rng, x, y);
            }
        },
    )?;
    Ok(())
}

/// Steps every live chain of `chains` (chain `first + i` of the run is
/// `chains[i]`) and evaluates it.
pub(crate) fn sweep<F, K, P, B, R, const D: usize>(
    cx: &Context<'_, K, P, B, F>,
    chains: &mut [Chain<F, D, R>],
    first: usize,
) -> Sweep<F>
where
    F: Float,
    K: Kernel<F>,
    P: Potential<F, D>,
    B: Domain<F>,
    R: Rng + 'static,
{
    let mut found = Sweep::NOTHING;
    let lockstep = lanes::VECTORS
        && TypeId::of::<R>() == TypeId::of::<Xoshiro256PlusPlus>()
        && (F::MANTISSA_DIGITS <= 24 || D >= LOCKSTEP_F64_FROM);
    let grouped = if lockstep {
        chains.len() / LANES * LANES
    } else {
        0
    };
    let (groups, rest) = chains.split_at_mut(grouped);
    for (g, group) in groups.chunks_exact_mut(LANES).enumerate() {
        let Ok(group) = <&mut [Chain<F, D, R>; LANES]>::try_from(group) else {
            continue;
        };
        if group.iter().any(|c| c.diverged) || !step_lockstep(cx.kernel, group) {
            for c in group.iter_mut().filter(|c| !c.diverged) {
                cx.kernel.step(&mut c.x, &mut c.y, &c.grad, &mut c.rng);
            }
        }
        let first = first + g * LANES;
        for (i, c) in group.iter_mut().enumerate() {
            if !c.diverged {
                evaluate(cx, c, first + i, &mut found);
            }
        }
    }
    let first = first + grouped;
    for (i, c) in rest.iter_mut().enumerate() {
        if !c.diverged {
            cx.kernel.step(&mut c.x, &mut c.y, &c.grad, &mut c.rng);
            evaluate(cx, c, first + i, &mut found);
        }
    }
    found
}

/// Steps a group of live chains in lockstep; `false` (nothing stepped) if
/// their generators are not xoshiro256++.
#[inline]
fn step_lockstep<F, K, R, const D: usize>(kernel: &K, group: &mut [Chain<F, D, R>; LANES]) -> bool
where
    F: Float,
    K: Kernel<F>,
    R: 'static,
{
    let generators = group
        .each_ref()
        .map(|c| (&c.rng as &dyn Any).downcast_ref::<Xoshiro256PlusPlus>());
    let [Some(g0), Some(g1), Some(g2), Some(g3)] = generators else {
        return false;
    };
    let mut rng = Xoshiro256Lanes::load([g0, g1, g2, g3]);
    kernel.step_lanes(
        group.each_mut().map(|c| ChainState {
            x: &mut c.x,
            y: &mut c.y,
            grad: &c.grad,
        }),
        &mut rng,
    );
    let generators = group
        .each_mut()
        .map(|c| (&mut c.rng as &mut dyn Any).downcast_mut::<Xoshiro256PlusPlus>());
    if let [Some(g0), Some(g1), Some(g2), Some(g3)] = generators {
        rng.store([g0, g1, g2, g3]);
    }
    true
}

/// Confines a stepped chain to the domain, evaluates `U` and `∇U` there and
/// updates its running best, or marks it diverged.
#[inline(always)]
fn evaluate<F, K, P, B, R, const D: usize>(
    cx: &Context<'_, K, P, B, F>,
    chain: &mut Chain<F, D, R>,
    c: usize,
    found: &mut Sweep<F>,
) where
    F: Float,
    P: Potential<F, D>,
    B: Domain<F>,
{
    cx.domain.confine(&mut chain.x, &mut chain.y);
    let value = cx.potential.value_and_gradient(&chain.x, &mut chain.grad);
    found.evaluated += 1;
    chain.value = value;
    match judge(&chain.x, value, &chain.grad, cx.floor) {
        Verdict::Feasible => {}
        verdict => {
            // Frozen, so that a non-finite value or one below the floor
            // never becomes the best.
            if verdict == Verdict::Unbounded {
                found.unbounded.get_or_insert((c, value));
            }
            chain.diverged = true;
            found.diverged += 1;
            return;
        }
    }
    if cx.record && value < chain.best.value {
        chain.best.x = chain.x;
        chain.best.value = value;
        chain.best.iteration = cx.k;
        if found.best.is_none_or(|(b, _)| value < b) {
            found.best = Some((value, c));
        }
    }
}

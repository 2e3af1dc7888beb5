//! What Algorithm 1 needs of the chains' storage, written once for every
//! store: the const-generic [`Chains`](super::Chains) (firmware, a
//! dimension in the type) and the flat [`FlatChains`](super::FlatChains)
//! (a dimension known at run time).
//!
//! The optimiser ([`Optimizer`](super::Optimizer)) holds the run's state
//! (iteration, budget, best chain, failure) and asks its store for the rest
//! through these traits. Each store keeps its own hot sweep ([`Steps`]),
//! so both run at the speed they ran at alone and give the same bits. The
//! traits live in a private module: they are sealed, implemented by the
//! two stores only.

use core::cell::Cell;

use super::executor::{Executor, Serial};
use super::sweep::{Context, Sweep};
use crate::error::Error;
use crate::float::Float;
use crate::polish::{PolishSettings, Polished};
use crate::sampler::Kernel;

/// A chain's best point, in any store.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Best<'a, F> {
    /// The position.
    pub x: &'a [F],
    /// `U(x)`, finite for every point the optimiser records.
    pub value: F,
    /// The iterate index `k` (0 is the initial point).
    pub iteration: u64,
}

/// Where a local search starts: a chain's best point or its current one.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// The chain's running best (a polish).
    Best,
    /// The chain's current position (a quench).
    Current,
}

/// Storage that becomes a store when a run is built: a container of
/// [`Chain`](super::Chain)s (`T` is the chain type), or the store itself.
pub trait IntoStore<F: Float, T> {
    /// The store.
    type Store: Store<F>;
    /// The store over this storage.
    fn into_store(self) -> Self::Store;
}

/// A chain store: what the optimiser reads and writes of the chains,
/// whatever the potential. Implemented by [`Chains`](crate::Chains) and
/// [`FlatChains`](crate::FlatChains); code generic over an
/// [`Optimizer`](crate::Optimizer)'s store names it to read the run
/// ([`Optimizer::best`](crate::Optimizer::best) and the other accessors).
pub trait Store<F: Float> {
    /// The number of chains.
    fn len(&self) -> usize;
    /// Whether there is no chain (never, in a built run).
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The dimension.
    fn dim(&self) -> usize;
    /// Chain `c`'s position, gradient and value.
    fn point(&self, c: usize) -> (&[F], &[F], F);
    /// Whether chain `c` has diverged.
    fn is_diverged(&self, c: usize) -> bool;
    /// Marks chain `c` diverged or alive.
    fn set_diverged(&mut self, c: usize, diverged: bool);
    /// Chain `c`'s running best.
    fn best(&self, c: usize) -> Best<'_, F>;
    /// Makes `value` at `x` (`None`: the chain's position) chain `c`'s
    /// best, found at iterate `k`.
    fn set_best(&mut self, c: usize, x: Option<&[F]>, value: F, k: u64);

    /// [`set_best`](Store::set_best) when `value` is below chain `c`'s
    /// best; whether it was.
    fn offer(&mut self, c: usize, x: Option<&[F]>, value: F, k: u64) -> bool {
        let lower = value < self.best(c).value;
        if lower {
            self.set_best(c, x, value, k);
        }
        lower
    }
}

/// A step of every live chain on one thread, and a chain moved to a point:
/// what needs the potential `P` and the domain `B`.
pub trait Steps<F: Float, P, B>: Store<F> {
    /// Steps every live chain and evaluates it at its new point.
    fn sweep<K: Kernel<F>>(&mut self, cx: &Context<'_, K, P, B, F>) -> Sweep<F>;
    /// Moves chain `c` to `x` (of the store's dimension; confined, zero
    /// velocity) and evaluates it there: its value, or
    /// [`Error::Stopped`] when the potential stopped the run.
    fn place(&mut self, c: usize, x: &[F], potential: &P, domain: &B) -> Result<F, Error>;
}

/// [`Steps::sweep`] in an executor's parts.
pub trait StepsOn<F: Float, P, B>: Steps<F, P, B> {
    /// Steps every live chain in the executor's parts.
    fn sweep_on<K: Kernel<F> + Sync, E: Executor>(
        &mut self,
        executor: &E,
        cx: &Context<'_, K, P, B, F>,
    ) -> Sweep<F>;
}

/// What a run's initial points come from: the potential, the domain, the
/// start law `Sd` and the seed.
pub struct Origins<'a, P, B, Sd> {
    /// The potential.
    pub potential: &'a P,
    /// The domain.
    pub domain: &'a B,
    /// The start law.
    pub start: &'a mut Sd,
    /// The run's seed.
    pub seed: u64,
}

/// The initial points, drawn from a start law `Sd`.
pub trait Starts<F: Float, P, B, Sd>: Store<F> {
    /// The dimensions the box, the start and the potential were made for,
    /// named, where they have one (the builder checks them against the
    /// store's).
    fn check(&self, from: &Origins<'_, P, B, Sd>) -> [(&'static str, Option<usize>); 3];
    /// Seeds every chain's generator from the seed, draws its initial
    /// point (redrawing an infeasible one within `spare`), evaluates it
    /// and makes it the chain's best: the evaluations spent.
    fn start(&mut self, from: Origins<'_, P, B, Sd>, spare: &mut u64) -> Result<u64, Error>;
}

/// A local search by an L-BFGS `L` over this store's dimension.
pub trait Searches<F: Float, P, B, L>: Store<F> {
    /// Whether `lbfgs` is made for this store's dimension
    /// ([`Error::Length`] otherwise).
    fn fits(&self, _lbfgs: &L) -> Result<(), Error> {
        Ok(())
    }
    /// L-BFGS from chain `c`'s best or current point within `domain`,
    /// each evaluation counted in `calls`; the point found is
    /// [`offered`](Store::offer) to the chain's best at iterate `k`.
    #[allow(clippy::too_many_arguments)]
    fn search(
        &mut self,
        c: usize,
        from: Origin,
        lbfgs: &mut L,
        potential: &P,
        domain: &B,
        settings: PolishSettings<F>,
        k: u64,
        calls: &Cell<u64>,
    ) -> Result<Polished<F>, Error>;
}

/// A potential whose evaluations a [`Searches::search`] counts in its
/// `calls`; each store makes it a potential of its own kind. `stopped`:
/// whether the potential stopped the run (a batch potential can).
pub(crate) struct Counted<'a, P> {
    pub potential: &'a P,
    pub calls: &'a Cell<u64>,
    pub stopped: Cell<bool>,
}

impl<'a, P> Counted<'a, P> {
    pub fn new(potential: &'a P, calls: &'a Cell<u64>) -> Self {
        Self {
            potential,
            calls,
            stopped: Cell::new(false),
        }
    }
}

/// Where a step's chains run: [`Serial`] on the calling thread, any
/// [`Executor`] in its parts. Chosen when the run is built.
pub trait RunsOn<F: Float, St, K, P, B> {
    /// One step of `chains`.
    fn sweep(&self, chains: &mut St, cx: &Context<'_, K, P, B, F>) -> Sweep<F>;
}

impl<F: Float, St: Steps<F, P, B>, K: Kernel<F>, P, B> RunsOn<F, St, K, P, B> for Serial {
    #[inline]
    fn sweep(&self, chains: &mut St, cx: &Context<'_, K, P, B, F>) -> Sweep<F> {
        chains.sweep(cx)
    }
}

impl<F, St, K, P, B, E> RunsOn<F, St, K, P, B> for E
where
    F: Float,
    St: StepsOn<F, P, B>,
    K: Kernel<F> + Sync,
    E: Executor,
{
    fn sweep(&self, chains: &mut St, cx: &Context<'_, K, P, B, F>) -> Sweep<F> {
        chains.sweep_on(self, cx)
    }
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

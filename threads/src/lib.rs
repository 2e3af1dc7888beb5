//! Threads for the [`hrla`] optimiser: [`Threads`], an
//! [`Executor`] that steps the chains of every step in
//! parts on rayon's thread pool.
//!
//! The kernel stays single-threaded and `no_std`; this crate is where a
//! host's threads come in. A run gives the same bits on any number of
//! threads and with any part size, and the same as
//! the default executor, [`Serial`](hrla::Serial), on one thread: every chain
//! draws only from its own generator, and the parts' findings (the new
//! running best, evaluations, diverged chains) are folded in chain order.
//!
//! ```
//! use hrla::{Builder, Chain, Gaussian, Hrla, Rastrigin, Stop};
//! use hrla_threads::Threads;
//!
//! let mut chains: Vec<Chain<f64, 10>> = (0..1000).map(|_| Chain::new()).collect();
//! let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, Gaussian::new([3.0; 10], 3.0)?)
//!     .seed(1)
//!     .stop(Stop::new().steps(100))
//!     // On every thread of rayon's global pool; `pool.install(|| ...)` for another.
//!     .executor(Threads::new())
//!     .build(&mut chains)?;
//! let report = opt.run()?;
//! assert_eq!(report.iterations, 100);
//! # Ok::<(), hrla::Error>(())
//! ```
//!
//! A potential that panics on one of the pool's threads stops the step
//! part-way: the panic reaches the caller, and the optimiser is poisoned
//! (every later call returns [`hrla::Error::Poisoned`]), so that no run
//! goes on from chains that no serial run would have.
//!
//! A step pays off on threads when it is long: with 1000 chains of 10-D
//! Rastrigin a step takes about 100 µs on one core, and the parts' hand-off
//! costs a few µs (see `docs/PERFORMANCE.md`). With an expensive potential
//! (a simulation, a model fit) a handful of chains is enough.

use hrla::{Executor, LANES, Split};
use rayon::prelude::*;

/// Steps the chains of every step in parts on rayon's current pool.
#[derive(Clone, Copy, Debug, Default)]
pub struct Threads {
    /// Chains per part; 0 for about four parts per thread.
    chains_per_part: usize,
}

impl Threads {
    /// About four parts per thread of the current pool, each a multiple of
    /// [`LANES`] chains (so that every part steps its chains in lockstep).
    pub fn new() -> Self {
        Self::default()
    }

    /// Parts of `chains` chains each (the last may be shorter); 0 is
    /// [`Threads::new`]'s choice. Results do not depend on it.
    pub fn chains_per_part(chains: usize) -> Self {
        Self {
            chains_per_part: chains,
        }
    }

    fn part_size(&self, items: usize) -> usize {
        if self.chains_per_part > 0 {
            return self.chains_per_part;
        }
        let parts = 4 * rayon::current_num_threads();
        items.div_ceil(parts).next_multiple_of(LANES).max(LANES)
    }
}

impl Executor for Threads {
    fn fold_parts<T, A, Part, Then>(&self, items: &mut [T], part: Part, then: Then) -> Option<A>
    where
        T: Send,
        A: Send,
        Part: Fn(usize, &mut [T]) -> A + Sync + Send,
        Then: Fn(A, A) -> A + Sync + Send,
    {
        let size = self.part_size(items.len());
        // `reduce_with` on an indexed iterator combines neighbours in
        // order, which is all that `then`'s associativity needs.
        items
            .par_chunks_mut(size)
            .enumerate()
            .map(|(j, chunk)| part(j * size, chunk))
            .reduce_with(then)
    }

    fn fold_split<T, A, Part, Then>(&self, items: T, part: Part, then: Then) -> Option<A>
    where
        T: Split,
        A: Send,
        Part: Fn(usize, T) -> A + Sync + Send,
        Then: Fn(A, A) -> A + Sync + Send,
    {
        let n = items.len();
        (n > 0).then(|| halves(items, 0, self.part_size(n), &part, &then))
    }
}

/// `items` (the first at index `first`) in parts of `size` (the last
/// shorter), halved at part boundaries and run on both sides of
/// `rayon::join`, the halves' results folded earlier first.
fn halves<T, A, Part, Then>(items: T, first: usize, size: usize, part: &Part, then: &Then) -> A
where
    T: Split,
    A: Send,
    Part: Fn(usize, T) -> A + Sync + Send,
    Then: Fn(A, A) -> A + Sync + Send,
{
    let parts = items.len().div_ceil(size);
    if parts <= 1 {
        return part(first, items);
    }
    let mid = parts / 2 * size;
    let (left, right) = items.split_at(mid);
    let (a, b) = rayon::join(
        || halves(left, first, size, part, then),
        || halves(right, first + mid, size, part, then),
    );
    then(a, b)
}

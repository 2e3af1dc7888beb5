//! Where the chains of one step run: [`Executor`].
//!
//! A step's chains are independent, so they can be cut into parts that run
//! anywhere, in any order: the kernel stays single-threaded and `no_std`,
//! and a host crate supplies the threads (`hrla-threads`, with rayon).
//! Whatever the cut and the threads, a step gives the same bits: each
//! chain draws only from its own generator, and the parts' findings are
//! combined in chain order by an associative rule.

/// Runs the parts of a step.
///
/// An implementation calls `part(first, chains)` on consecutive parts of
/// `items` (where `first` is the index of the part's first item) that
/// together cover every item exactly once, in any order and on any
/// threads, and folds the results of neighbouring parts with `then`
/// (earlier part first). `then` is associative, so any grouping of the fold
/// gives the same result; `None` only for no items.
pub trait Executor {
    /// The parts' results, folded in order.
    fn fold_parts<T, A, Part, Then>(&self, items: &mut [T], part: Part, then: Then) -> Option<A>
    where
        T: Send,
        A: Send,
        Part: Fn(usize, &mut [T]) -> A + Sync + Send,
        Then: Fn(A, A) -> A + Sync + Send;

    /// [`fold_parts`](Executor::fold_parts) for items that are not a
    /// slice but split like one ([`Split`]), such as chains in flat
    /// storage ([`FlatChains`](crate::FlatChains)' fields): the same contract.
    /// The default runs everything on the calling thread, as one part.
    fn fold_split<T, A, Part, Then>(&self, items: T, part: Part, _then: Then) -> Option<A>
    where
        T: Split,
        A: Send,
        Part: Fn(usize, T) -> A + Sync + Send,
        Then: Fn(A, A) -> A + Sync + Send,
    {
        (!items.is_empty()).then(|| part(0, items))
    }
}

/// Items that split in two at an index, as `split_at_mut` splits a slice:
/// what [`Executor::fold_split`] cuts into parts.
pub trait Split: Sized + Send {
    /// The number of items.
    fn len(&self) -> usize;
    /// Whether there are no items.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Items `..mid` and `mid..`; `mid <= len()`.
    fn split_at(self, mid: usize) -> (Self, Self);
}

/// Every chain on the calling thread, with no bound on the potential or
/// the generators: the optimiser's default, unless the builder is given
/// an [`Executor`] ([`Builder::executor`](crate::Builder::executor)).
#[derive(Clone, Copy, Debug, Default)]
pub struct Serial;

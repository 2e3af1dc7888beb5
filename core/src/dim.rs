//! The dimension of a run, known at compile time ([`Const`]) or at run
//! time ([`Dyn`]).
//!
//! Code generic over a [`Dim`] asks it for `value()`: for `Const<N>` that
//! is a constant the compiler folds into every loop, for `Dyn` a number
//! read once. Storage sized by a run-time dimension lives with the caller
//! ([`FlatChains`](crate::FlatChains), [`LbfgsIn`](crate::LbfgsIn)), so the
//! kernel stays allocation-free whatever the dimension.

use core::fmt::Debug;

/// A dimension: a number of coordinates.
pub trait Dim: Copy + Debug {
    /// The number of coordinates.
    fn value(self) -> usize;
}

/// A dimension known at compile time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Const<const N: usize>;

impl<const N: usize> Dim for Const<N> {
    #[inline(always)]
    fn value(self) -> usize {
        N
    }
}

/// A dimension known at run time.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Dyn(pub usize);

impl Dim for Dyn {
    #[inline(always)]
    fn value(self) -> usize {
        self.0
    }
}

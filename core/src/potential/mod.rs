//! Potentials `U: R^D -> R` to minimise: the [`Potential`] trait, a
//! potential from a closure ([`FnPotential`]), a gradient check for one's
//! own ([`check_gradient`]), and the built-in benchmarks, one file each.
//!
//! A new potential is one file here (a type, its
//! [`Potential::value_and_gradient`], and, when the minimum is known,
//! [`KnownMinimum`]) and its `mod` and `pub use` lines below; the crate
//! root re-exports everything this module does.

mod ackley;
mod check;
mod closure;
mod double_well;
mod levy;
mod quadratic;
mod rastrigin;
mod styblinski_tang;
pub(crate) mod traits;

pub use ackley::Ackley;
pub use check::{GradientCheck, check_gradient};
pub use closure::FnPotential;
pub use double_well::DoubleWell;
pub use levy::Levy;
pub use quadratic::Quadratic;
pub use rastrigin::Rastrigin;
pub use styblinski_tang::StyblinskiTang;
pub use traits::{BatchPotential, KnownMinimum, Potential, SlicePotential};

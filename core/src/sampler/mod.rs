//! Samplers: one Markov step of a chain, given the gradient at its position.
//!
//! A [`Sampler`] holds a method's parameters without the inverse
//! temperature; [`Sampler::at`] gives its [`Kernel`], the step at one `a`.
//! [`Hrla`] (the paper's method), [`Ula`] and [`Ola`] (its two baselines)
//! are built in, one file each, and [`AnySampler`] picks one at run time.
//!
//! A new sampler is one file here (its parameters, the [`Sampler`] and,
//! unless it reuses one, its [`Kernel`]) and its `mod` and `pub use` lines
//! below; the crate root re-exports everything this module does. To make it
//! one of [`AnySampler`]'s choices, add one line to the list in `any.rs`.

mod any;
mod hrla;
mod ola;
mod ou;
mod traits;
mod ula;

pub use any::{AnyKernel, AnySampler, SamplerKind};
pub use hrla::{Hrla, HrlaParams};
pub use ola::{Ola, OlaKernel, OlaParams};
pub use ou::{NoiseFactor, OuKernel};
pub use traits::{ChainState, Kernel, Sampler, StepMoments};
pub use ula::{Ula, UlaParams};

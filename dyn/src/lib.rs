//! The run-time layer of `hrla`: what every front end (Python, the wasm
//! page, the `repro` tool) needs between its own inputs and the kernel.
//!
//! The kernel is `no_std`, allocation-free and typed at compile time (the
//! dimension, the potential, the sampler). A front end reads names, numbers
//! and user functions at run time. This crate is the one translation:
//!
//! - [`Settings`]: a run as plain values: the potential by name or a
//!   user's batched function ([`PotentialSpec`]), the sampler, the
//!   schedule ([`Temperature`] by parameters, or the kernel's
//!   [`AnySchedule`](hrla::AnySchedule)), the start ([`StartSpec`]), the
//!   box ([`BoxSpec`], one interval per coordinate), the stopping rules,
//!   the seed, the chains and the dimension;
//! - [`BuiltinKind`]: the kernel's built-in potentials, declared once (the
//!   list in `potential.rs`); names parse and print from it, and every
//!   front end lists them from it;
//! - [`Engine`]: one run loop behind an object-safe trait, whatever the
//!   dimension, with the chains readable as flat slices or a [`Layout`];
//! - [`auto::solve`]: the kernel's default solver, [`hrla::Auto`], on the
//!   same settings;
//! - [`Ensemble`]: a gradient-free solver of values alone (an ensemble of
//!   Langevin particles driven by a quadratic model's gradient), which
//!   continues `Auto` when a front end has no gradient;
//! - [`termination_name`], [`termination_code`]: the one mapping of why a
//!   run ended.
//!
//! The dimension is a run-time `usize` everywhere in this API, any
//! `d >= 1`: the [`Engine`] runs the kernel's optimiser over flat storage
//! at a run-time dimension `d`, and [`auto::solve`] the kernel's [`hrla::Auto`]
//! over storage it lends, each with the bits of the const-generic path.
//! A user's function is called on batches ([`BatchFunction`]: points
//! `n x d` in, values and gradients out) through the kernel's batch seam.

#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod auto;
pub mod budget;
mod engine;
mod ensemble;
mod error;
mod linalg;
mod potential;
mod report;
mod settings;
mod user;

pub use engine::{Engine, Layout, storage_bytes};
pub use ensemble::{Ensemble, EnsembleEnd, EnsembleRules, EnsembleSolution};
pub use error::{Error, RanAway};
pub use potential::{Builtin, BuiltinKind, BuiltinSpec, UnknownPotential};
pub use report::{Progress, TERMINATIONS, termination_code, termination_name};
pub use settings::{
    AnyStart, BoxSpec, PointFunction, PotentialSpec, Settings, StartSpec, Temperature, dimension,
};
pub use user::{BatchFunction, UserBatch, UserError};

/// The L-BFGS memory of the samplers' polish (the kernel's `M`), and the
/// least of `Auto`'s quenches, which keep two pairs a coordinate up to 64.
pub const MEMORY: usize = 8;

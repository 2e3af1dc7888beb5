//! Python face of the `hrla` kernel, built by maturin as `hrla._hrla`.
//!
//! A thin PyO3 layer with no maths of its own: it translates its arguments
//! into the run-time layer's settings ([`hrla_dyn`]) and presents its
//! results, so every number a run computes is the kernel's, with the same
//! names ([`hrla::Builder`]'s pieces, [`hrla::Optimizer`], [`hrla::Auto`],
//! [`hrla::Lbfgs`]'s polish) and, for the same seed, the same bits. The
//! optimiser, `Auto` and the known minima run any dimension. Floats are
//! `f64`.
//!
//! Potentials come in two kinds: the kernel's built-ins, which run with the
//! GIL released and no Python in the loop, and a user's Python function,
//! called once per step for all live chains with an `(N, D)` array
//! (see `potential.rs`).

#![deny(unsafe_code)]

mod auto;
mod config;
mod engine;
mod ensemble;
mod errors;
mod observer;
mod potential;
mod views;

use pyo3::prelude::*;

/// The extension module `hrla._hrla`; `hrla/__init__.py` re-exports it.
#[pymodule]
fn _hrla(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    config::register(m)?;
    potential::register(m)?;
    engine::register(m)?;
    auto::register(m)?;
    ensemble::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

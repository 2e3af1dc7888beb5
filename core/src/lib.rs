//! Global optimisation by high-resolution Langevin sampling (HRLA), in
//! `no_std` Rust without allocation.
//!
//! To minimise a smooth nonconvex `U: R^D -> R`, run `N` independent chains
//! that sample the Gibbs law `exp(-a U)` and keep the best point visited
//! (Algorithm 1 of Cortild, Delplancke, Oudjane and Peypouquet, *Global
//! Optimization Algorithm through High-Resolution Sampling*, TMLR 2025). The
//! sampler, HRLA, discretises the high-resolution Langevin dynamics
//!
//! ```text
//! dX = (-beta ∇U(X) + Y) dt + sqrt(2 sx2) dB^x
//! dY = (-gamma ∇U(X) - alpha Y) dt + sqrt(2 sy2) dB^y
//! ```
//!
//! with `gamma = a/b`, `sx2 = beta/a`, `sy2 = alpha/b`, so that
//! `mu^{a,b}(x, y) ∝ exp(-a U(x) - b |y|^2 / 2)` is invariant by
//! construction. Over each step of length `h` the gradient is frozen and the
//! remaining linear SDE is integrated **exactly**: every coordinate moves to
//! a Gaussian with closed-form mean and 2x2 covariance. With `u = alpha h`,
//! `e = exp(-u)`, `phi1(u) = (1 - e)/u` and `phi2(u) = (e - 1 + u)/u^2`:
//!
//! ```text
//! mean_x = x + h phi1 y - (beta h + gamma h^2 phi2) g
//! mean_y = e y - gamma h phi1 g
//! Sxx = (sy2/alpha^3)(2u - e^2 + 4e - 3) + 2 sx2 h
//! Syy = sy2 (1 - e^2)/alpha,   Sxy = sy2 (1 - e)^2/alpha^2
//! ```
//!
//! The coefficients are evaluated without cancellation for every `u` from
//! 1e-8 to 50 in f32 and f64 (see [`Hrla`] and the spec, `docs/SPEC.md` in
//! the repository). ULA and OLA, the paper's baselines, share the
//! [`Sampler`] trait, and a [`Schedule`] gives `a` at every step, raising
//! it along the run for annealing.
//!
//! # Example
//!
//! Minimise 10-D Rastrigin with the paper's parameters:
//!
//! ```
//! use hrla::{Gaussian, Hrla, Optimizer, Rastrigin};
//! use rand_xoshiro::{Xoshiro256PlusPlus, rand_core::SeedableRng};
//!
//! let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
//! // The paper's setting (b = 10, alpha = beta = 1) at h = 0.01, at a = 4.
//! let sampler = Hrla::paper(0.01)?;
//! let mut start = Gaussian::new([3.0; 10], 10f64.sqrt())?;
//! let mut opt: Optimizer<f64, _, _, _, 10, 10> =
//!     Optimizer::new(Rastrigin, sampler, 4.0, 10, &mut start, &mut rng)?;
//! let report = opt.run(14_000, &mut rng)?;
//! assert!(report.best.value < 2.0);
//! # Ok::<(), hrla::Error>(())
//! ```
//!
//! # Inventory
//!
//! - Potentials: the [`Potential`] trait, and [`Rastrigin`] (the paper's
//!   form), [`Quadratic`], [`DoubleWell`], [`StyblinskiTang`], [`Levy`] and
//!   [`Ackley`], each with its [`KnownMinimum`].
//! - Samplers: [`Hrla`], [`Ula`], [`Ola`] (and [`AnySampler`] to pick one
//!   at run time, by [`SamplerKind`]); each gives its [`Kernel`] at an
//!   inverse temperature ([`OuKernel`], [`OlaKernel`]), with
//!   [`StepMoments`] the exact one-step mean and covariance and
//!   [`NoiseFactor`] its Cholesky factor.
//! - Schedules: a plain float (constant `a`), [`Constant`], [`Linear`],
//!   [`Geometric`], [`FnSchedule`], [`AnySchedule`].
//! - Randomness: [`StandardNormal`], exact normals for both float types.
//! - Starts: [`Gaussian`], [`Point`], [`FromFn`].
//! - Algorithm 1: [`Optimizer`], with [`Chain`], [`Best`], [`Report`].
//!
//! # Randomness and reproducibility
//!
//! Any [`rand_core::Rng`] drives the chains; `rand_xoshiro`'s
//! `Xoshiro256PlusPlus` is the default choice, and `Xoshiro128PlusPlus`
//! suits 32-bit microcontrollers (with it the `f32` normal sampler does
//! 32-bit arithmetic only: its pairs of normals take one `next_u64`, which
//! such a generator makes from two `next_u32`). Normals are exact (256-layer
//! Ziggurat). All maths goes through `libm`, never the platform's library,
//! and the kernel never fuses multiply-adds, so a seed gives bit-identical
//! results on x86_64, wasm32 and Cortex-M. The `micromath` feature swaps
//! the `f32` exponential and logarithm of the normal sampler's rare
//! branches (and the sine and cosine of [`Levy`]) for micromath's smaller
//! approximations: this changes some `f32` results and makes the normals
//! slightly inexact; the step coefficients and Rastrigin's polynomial sine
//! keep full accuracy.
//!
//! # Memory
//!
//! An optimiser holds its chains inline; each chain stores `4 D + 2` floats
//! (position, velocity, gradient, value, and its best point and value) plus
//! an iteration counter and a flag. From `core::mem::size_of` (checked
//! by a test):
//!
//! | optimiser | bytes |
//! |---|---|
//! | `Optimizer<f32, Rastrigin, Hrla<f32>, f32, 2, 16>` | 1 112 |
//! | `Optimizer<f64, Rastrigin, Hrla<f64>, f64, 10, 10>` | 3 952 |
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod error;
mod float;
mod lanes;
mod normal;
mod optimizer;
mod potential;
mod sampler;
mod schedule;
mod start;
mod ziggurat_tables;

pub use error::Error;
pub use float::Float;
pub use normal::StandardNormal;
pub use optimizer::{Best, Chain, Optimizer, Report, Status};
pub use potential::*;
pub use sampler::*;
pub use schedule::{AnySchedule, Constant, FnSchedule, Geometric, Linear, Schedule};
pub use start::{FromFn, Gaussian, Point, Start};

pub use rand_core;

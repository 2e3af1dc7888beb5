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
//! use hrla::{Builder, Chain, Gaussian, Hrla, Rastrigin, Stop};
//!
//! // The chains live where the caller puts them: here on the heap.
//! let mut chains: Vec<Chain<f64, 10>> = (0..10).map(|_| Chain::new()).collect();
//! let mut opt = Builder::new(
//!     Rastrigin,
//!     Hrla::paper(0.01)?,                     // b = 10, alpha = beta = 1, h = 0.01
//!     4.0,                                    // the schedule: a constant a = 4
//!     Gaussian::new([3.0; 10], 10f64.sqrt())?, // x_0 ~ N(3·1, 10 I)
//! )
//! .seed(1)
//! .stop(Stop::new().steps(14_000))
//! .build(&mut chains)?;
//! let report = opt.run()?;
//! println!("{report}");
//! assert!(report.value < 2.0);
//! println!("x* = {:?}", opt.best().x);
//! # Ok::<(), hrla::Error>(())
//! ```
//!
//! A potential of one's own is a closure ([`FnPotential`]) or a type
//! implementing [`Potential`], and [`check_gradient`] compares its gradient
//! with finite differences:
//!
//! ```
//! use hrla::{Builder, Chain, FnPotential, Gaussian, Linear, Ola, Stop, check_gradient};
//!
//! // Himmelblau's function: four global minima, U* = 0.
//! let himmelblau = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| {
//!     let (p, q) = (x[0] * x[0] + x[1] - 11.0, x[0] + x[1] * x[1] - 7.0);
//!     *g = [4.0 * x[0] * p + 2.0 * q, 2.0 * p + 4.0 * x[1] * q];
//!     p * p + q * q
//! });
//! assert!(check_gradient(&himmelblau, &[1.0, -2.0])?.error < 1e-8);
//!
//! let mut chains: Vec<Chain<f64, 2>> = (0..32).map(|_| Chain::new()).collect();
//! let mut opt = Builder::new(
//!     &himmelblau,                       // a reference is a potential too
//!     Ola::paper(1e-3)?,
//!     Linear::new(0.1, 100.0, 20_000)?,  // annealing; its length is the step budget
//!     Gaussian::new([0.0; 2], 3.0)?,
//! )
//! .stop(Stop::new().target(1e-4))        // or earlier, at the target
//! .build(&mut chains)?;
//! let report = opt.run()?;
//! assert!(report.value < 1e-2, "{report}");
//! # Ok::<(), hrla::Error>(())
//! ```
//!
//! # Inventory
//!
//! - Potentials: the [`Potential`] trait, [`FnPotential`] for closures,
//!   [`check_gradient`], and [`Rastrigin`] (the paper's form),
//!   [`Quadratic`], [`DoubleWell`], [`StyblinskiTang`], [`Levy`] and
//!   [`Ackley`], each with its [`KnownMinimum`].
//! - Samplers: [`Hrla`], [`Ula`], [`Ola`] (and [`AnySampler`] to pick one
//!   at run time, by [`SamplerKind`]); each gives its [`Kernel`] at an
//!   inverse temperature ([`OuKernel`], [`OlaKernel`]), with
//!   [`StepMoments`] the exact one-step mean and covariance and
//!   [`NoiseFactor`] its Cholesky factor.
//! - Schedules: a plain float (constant `a`), [`Constant`], [`Linear`],
//!   [`Geometric`], [`FnSchedule`], [`AnySchedule`].
//! - Starts: [`Gaussian`], [`Point`], [`FromFn`].
//! - Domains: [`Unbounded`], [`Interval`] (the same interval in every
//!   coordinate) and [`Bounds`] (one per coordinate), each reflecting
//!   every coordinate into its interval.
//! - Dimension at run time: chains in flat storage the caller owns or
//!   lends, [`FlatChains`] (over any [`FlatStorage`]; [`FlatSlices`] for
//!   borrowed slices), run by the same [`Optimizer`] with the same
//!   [`Domain`] and [`Start`]; the potential's slice form,
//!   [`SlicePotential`]; the batch seam, [`BatchPotential`]; L-BFGS in
//!   caller storage, [`LbfgsIn`].
//! - Algorithm 1: [`Builder`] and [`Optimizer`], over [`Chain`]s (in
//!   [`Chains`]) or [`FlatChains`], with [`Stop`] rules, [`Progress`]
//!   (what a step did) for an observer called as [`Observe`] says, the
//!   running [`Best`], and a [`Report`] whose [`Termination`] says why the
//!   run ended; failures are [`Error`]s.
//! - The default solver: [`Auto`], with [`AutoProgress`] for its observer
//!   and a [`Solution`]; L-BFGS: [`Lbfgs`].
//! - Randomness: [`chain_seed`], one stream per chain; [`StandardNormal`],
//!   exact normals for both float types; [`Xoshiro256Lanes`], [`LANES`]
//!   chains' generators stepped in lockstep.
//! - Speed and scale: [`Kernel::step_lanes`], the seam where a wide backend
//!   steps a block of chains; [`Executor`] and [`Builder::executor`],
//!   where a host's threads come in (the `hrla-threads` crate; [`Serial`]
//!   is the default).
//!
//! # Validity
//!
//! Every constructor checks its numbers and returns a typed [`Error`]; no
//! public function panics on bad input. The exact step is documented and
//! tested for `alpha h` in `[1e-8, 50]` and inverse temperatures in
//! `[1e-6, 1e6]`, and refuses values outside ([`Error::OutOfRange`]). A run
//! whose chains all diverged ([`Error::AllDiverged`]) or whose potential
//! looks unbounded below ([`Error::UnboundedBelow`]: a value under
//! `-sqrt(MAX)` at a start, a step, a polish, a quench or a restart) ends
//! with an error, never with a report; so does a run whose potential
//! panicked ([`Error::Poisoned`]). A [`Report`] or [`Solution`] says why
//! the run ended and how many chains diverged.
//!
//! A point where `U` or its gradient is NaN or `+inf` (or whose position
//! is not finite) is infeasible, not fatal:
//!
//! - **At a start**, the chain draws again from the start law, up to
//!   [`START_TRIES`] points, each counted in the evaluation budget; a run
//!   whose initial points are all feasible draws each once, so its bits
//!   are those of a run without redraws. [`Error::NonFiniteStart`] says
//!   how many were tried when none was feasible.
//! - **During a run**, a chain that steps there diverges: it is frozen (no
//!   more steps, no more draws) and kept out of the best, and the others
//!   go on; [`Optimizer::restart`] revives it at a feasible point.
//! - [`Auto`] rejects a proposal that meets such a point (the chain stays
//!   in its basin), and a quench that meets one treats it as `+inf`: its
//!   best point is always one where `U` and `∇U` were finite.
//!
//! # Randomness and reproducibility
//!
//! Each chain has its own generator, `R::seed_from_u64(chain_seed(seed, c))`
//! for chain `c` of a run seeded with `seed`, and draws its initial point
//! and every step's normals from it alone: chain `c`'s trajectory depends
//! on `(seed, c)` only, not on the order or number of chains stepped with
//! it. `rand_xoshiro`'s `Xoshiro256PlusPlus` is the default generator, and
//! `Xoshiro128PlusPlus` suits 32-bit microcontrollers (with it the `f32`
//! normal sampler does 32-bit arithmetic only: its pairs of normals take
//! one `next_u64`, which such a generator makes from two `next_u32`).
//! Normals are exact (256-layer Ziggurat). All maths goes through `libm`,
//! never the platform's library, and the kernel never fuses multiply-adds,
//! so a seed gives bit-identical results on x86_64, wasm32 and Cortex-M.
//! The `micromath` feature swaps the `f32` exponential and logarithm of
//! the normal sampler's rare branches (and the sine and cosine of [`Levy`])
//! for micromath's smaller approximations: this changes some `f32` results
//! and makes the normals slightly inexact; the step coefficients and
//! Rastrigin's polynomial sine keep full accuracy.
//!
//! # Lanes, threads and machines
//!
//! Chains are independent, and chain `c`'s trajectory is a pure function of
//! `(seed, c)`; everything that makes a run faster keeps it so:
//!
//! - **Vector lanes.** On targets with float vectors, the optimiser steps
//!   groups of [`LANES`] live chains whose generator is the default
//!   `Xoshiro256PlusPlus` in lockstep where that measured faster (`f32`
//!   always; `f64` from `D = 16` in AVX-512 builds, `D = 8` in others): their generators advance in one
//!   vector per state word ([`Xoshiro256Lanes`]), the Ziggurat's fast path
//!   runs in all lanes at once, and a lane the fast path rejects finishes
//!   from its own stream. Each chain draws exactly the words it draws
//!   alone; on Cortex-M, RISC-V and plain wasm32 chains step one by one.
//!   [`Kernel::step_lanes`] is the seam: a backend for wider hardware (a
//!   GPU, 512-bit vectors) steps a block of chains, structure-of-arrays
//!   inside, and must give each chain the words of its own generator in
//!   the order [`Kernel::step`] draws them, with the same float operations
//!   in the same order (no fused multiply-add), so that its results are
//!   the same bits.
//! - **Threads.** An optimiser built with an [`Executor`]
//!   ([`Builder::executor`]) cuts each step's chains into parts for it; the parts' findings fold
//!   in chain order by an associative rule, so 1, 2, 3 or 7 threads give
//!   the serial bits. The kernel has no threads of its own; the
//!   `hrla-threads` crate runs the parts on rayon's pool.
//! - **Machines.** Runs seeded by their index split across processes; the
//!   reproduction tool's `--shard i/n` and `--merge` (a SLURM job array in
//!   `tools/repro/slurm/`) give the tables of one process, byte for byte.
//!
//! # Dimension known at run time
//!
//! The const-generic API fixes `D` at compile time, which firmware wants.
//! A host that learns the dimension at run time (a Python or JavaScript
//! caller, a 17-parameter fit, a 10 000-D problem) builds the same run
//! over [`FlatChains`], arrays it owns or lends, given to the same
//! [`Builder::build`]: one [`Optimizer`] runs either. Both go through the same
//! per-coordinate code (the kernels' draws and updates, the reflection,
//! the judgement of a point, L-BFGS), so a run gives the same bits either
//! way. Each step over [`FlatChains`] moves every live chain, then
//! evaluates all the new points in one [`BatchPotential`] call: a
//! potential that is cheaper per batch (vectorised, on a GPU, in another
//! language) evaluates the whole `(n, d)` block at once.
//!
//! ```
//! use hrla::{Bounds, Builder, FlatChains, FlatSlices, Hrla, LbfgsIn, PolishSettings, Rastrigin, Stop};
//! use rand_core::SeedableRng;
//! use rand_xoshiro::Xoshiro256PlusPlus;
//!
//! let (n, d) = (8, 24);
//! // Owned arrays: the optimiser below borrows nothing of its caller's
//! // and can live in a long-lived object. (`&mut` slices work the same.)
//! let floats = vec![0.0; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(n, d)];
//! let (iterations, diverged) = (vec![0; n], vec![false; n]);
//! let rngs: Vec<_> = (0..n).map(|_| Xoshiro256PlusPlus::seed_from_u64(0)).collect();
//! let chains = FlatChains::new(d, floats, iterations, diverged, rngs)?;
//! // A box per coordinate: the first half in [-1, 1], the rest in [-5, 5].
//! let lo: Vec<f64> = (0..d).map(|i| if i < d / 2 { -1.0 } else { -5.0 }).collect();
//! let hi: Vec<f64> = lo.iter().map(|l| -l).collect();
//! let bounds = Bounds::new(&lo[..], &hi[..])?;
//! let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, bounds)
//!     .domain(bounds)
//!     .stop(Stop::new().steps(2_000))
//!     .build(chains)?;
//! let sampled = opt.run()?;
//! let mut storage = vec![0.0; LbfgsIn::<f64>::floats(d, 8)];
//! let mut lbfgs = LbfgsIn::new(d, 8, &mut storage)?;
//! let polished = opt.polish(opt.best_chain(), &mut lbfgs, PolishSettings::new(1_000))?;
//! assert!(polished.value <= sampled.value);
//! # Ok::<(), hrla::Error>(())
//! ```
//!
//! # Memory
//!
//! The caller owns the chains: any `AsRef<[Chain]> + AsMut<[Chain]>`, such
//! as an array or a `heapless::Vec` on firmware (the crate re-exports
//! [`heapless`]) or a `Vec` on a host, so their number and size are limited
//! by the storage, never by a stack. Each chain stores `4 D + 2` floats
//! (position, velocity, gradient, value, and its best point and value), an
//! iteration counter, a flag and its generator; the optimiser itself holds
//! no array of size `D` or `N`. From `core::mem::size_of` (checked by a
//! test):
//!
//! | type | bytes |
//! |---|---|
//! | `Chain<f32, 2, Xoshiro128PlusPlus>` | 72 |
//! | `Chain<f64, 10>` (`Xoshiro256PlusPlus`) | 384 |
//!
//! ```
//! use hrla::{Builder, Chain, Gaussian, Hrla, Rastrigin, Stop, heapless};
//! use rand_xoshiro::Xoshiro128PlusPlus;
//!
//! // 16 chains of 2-D Rastrigin in f32, without allocation.
//! let mut chains: heapless::Vec<Chain<f32, 2, Xoshiro128PlusPlus>, 16> =
//!     (0..16).map(|_| Chain::default()).collect();
//! let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, Gaussian::new([3.0; 2], 3.0)?)
//!     .stop(Stop::new().steps(2_000))
//!     .build(&mut chains)?;
//! opt.run()?;
//! # Ok::<(), hrla::Error>(())
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod auto;
mod domain;
mod error;
mod float;
mod lanes;
mod lockstep;
mod normal;
mod optimizer;
mod polish;
mod potential;
mod sampler;
mod schedule;
mod start;
mod ziggurat_tables;

pub use auto::{Auto, AutoProgress, AutoStorage, MAX_STEPS, Parts, Problem, Sampling, Solution};
pub use domain::{Bounds, Domain, Interval, Sides, Unbounded};
pub use error::Error;
pub use float::Float;
pub use lockstep::{LANES, Xoshiro256Lanes};
pub use normal::StandardNormal;
pub use optimizer::*;
pub use polish::{Lbfgs, LbfgsIn, PolishEnd, PolishSettings, Polished};
pub use potential::*;
pub use sampler::*;
pub use schedule::{AnySchedule, Constant, FnSchedule, Geometric, Linear, Schedule};
pub use start::{FromFn, Gaussian, Point, Start};

pub use heapless;
pub use rand_core;

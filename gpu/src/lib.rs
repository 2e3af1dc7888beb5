//! Millions of chains of HRLA, ULA and OLA on a GPU, with the kernel's
//! coefficients, streams and Ziggurat: the GPU backend of `hrla`.
//!
//! An [`Ensemble`] holds N independent chains of Algorithm 1 on one device
//! ([`Gpu`]). One invocation steps one chain; it keeps the chain's
//! position, velocity, gradient, value, running best and generator in
//! registers for many steps per dispatch, writing back only an improved
//! running best's point and, at the end of the dispatch, the state. Algorithm
//! 1's best ([`Ensemble::best`]) and the paper's empirical probability
//! ([`Ensemble::probability`]) are reduced on the device.
//!
//! ```no_run
//! use hrla::{Hrla, Linear};
//! use hrla_gpu::{DevicePotential, EnsembleBuilder, Gpu, Start};
//!
//! let gpu = Gpu::new()?;
//! // 10^6 chains of 10-D Rastrigin, linear annealing 0.1 -> 4 over 14 000 steps.
//! let mut ensemble = EnsembleBuilder::new(
//!     DevicePotential::Rastrigin,
//!     Hrla::paper(0.01)?,
//!     Linear::new(0.1, 4.0, 14_000)?,
//!     Start::paper(10),
//! )
//! .chains(1_000_000)
//! .build(&gpu)?;
//! ensemble.run(14_000)?;
//! println!("{:?}", ensemble.best()?);
//! # Ok::<(), hrla_gpu::GpuError>(())
//! ```
//!
//! # The same method, the same streams
//!
//! - **Coefficients.** The step's coefficients at each `a_k` come from the
//!   kernel's own sampler types ([`hrla::Hrla`], [`hrla::Ula`],
//!   [`hrla::Ola`], [`hrla::AnySampler`]) on the host, through their public
//!   moments ([`DeviceKernel`]): on an `f32` device, an `f64` sampler's
//!   are the kernel's f64 values rounded once, an `f32` sampler's the CPU
//!   `f32` optimiser's bits; on an `f64` device, an `f64` sampler's are
//!   the CPU `f64` optimiser's.
//! - **Streams.** Chain `c` draws from
//!   `Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c))`, the words
//!   the CPU kernel's chain `c` draws with that generator, through the
//!   kernel's 256-layer Ziggurat (its tables read from the kernel's source)
//!   with fdlibm's `expf` and `logf` (`exp` and `log` in `f64`) in its
//!   rare branches, as the `libm` crate computes them.
//! - **Arithmetic.** The step and the built-in potentials use the kernel's
//!   operations in the kernel's order. WGSL does not promise IEEE rounding
//!   of every operation: a driver may fuse a multiply and an add, and its
//!   division need not be correctly rounded. Where it does neither (the
//!   crate's tests check it on lavapipe), the states after K steps are the
//!   CPU kernel's bits, in `f32` and `f64`; elsewhere the tests check the
//!   law (moments against the closed form, a two-sample test against the
//!   CPU kernel). [`Arithmetic`] says how the program keeps the kernel's
//!   roundings against a compiler that fuses or reorders.
//!
//! # Why wgpu (and not CubeCL)
//!
//! wgpu runs one WGSL program on Vulkan, Metal, DX12 and, in the browser,
//! WebGPU, and its compiler (naga) reports a user's WGSL errors as values,
//! which a user potential given as source needs. CubeCL would let the step
//! be written once in Rust, but its portable runtime is itself wgpu (its
//! CUDA and ROCm runtimes serve one vendor each), its kernels carry no
//! user source to compile at run time, and it cannot place the kernel's
//! Ziggurat, fdlibm functions and order of operations more precisely than
//! hand-written WGSL. On lavapipe the WGSL kernel runs at the figures of
//! `docs/PERFORMANCE.md` (GPU section); a CubeCL kernel would go through
//! the same compiler to the same SPIR-V there.
//!
//! # Precision
//!
//! The device computes in `f32` ([`Precision::F32`], the default) or, where
//! the adapter has `SHADER_F64` (lavapipe and NVIDIA's data-centre cards
//! do; Apple GPUs and the browser do not), in `f64` ([`Precision::F64`]).
//! In `f64` the chains are those of the CPU kernel's `f64` optimiser over
//! `Chain<f64, D, Xoshiro128PlusPlus>`: the same 64-bit Ziggurat words
//! (two of the generator's each), fdlibm's `exp` and `log` ported to WGSL
//! (Vulkan has none in `f64`, and WGSL no bits of an `f64`: the port
//! takes numbers apart by exact arithmetic), and Rastrigin's six-term
//! polynomials. Ackley and Levy, which need the device's `sin`, `cos` and
//! `exp`, run in `f32` only.
//!
//! # Without wgpu
//!
//! The default feature `device` brings in wgpu and everything that runs on
//! a device ([`Gpu`], [`Ensemble`]). Without it (`default-features =
//! false`) the crate is what needs no device, and builds for
//! `wasm32-unknown-unknown`: the WGSL program ([`Program`]), the
//! potentials, starts and step coefficients it is made from. A web page
//! that drives WebGPU itself takes its program from there.
//!
//! # Without a GPU
//!
//! A software Vulkan runs everything: Debian's `mesa-vulkan-drivers`
//! (lavapipe) with the loader `libvulkan1`. [`Gpu::new`] fails with
//! [`GpuError::NoAdapter`] when no adapter at all is found.
#![forbid(unsafe_code)]
#![deny(missing_docs)]

#[cfg(feature = "device")]
mod device;
#[cfg(feature = "device")]
mod ensemble;
mod error;
mod potential;
mod precision;
mod shader;
mod start;
mod step;

#[cfg(feature = "device")]
pub use device::Gpu;
#[cfg(feature = "device")]
pub use ensemble::{
    BestPoint, ChainSnapshot, Ensemble, EnsembleBuilder, GroupBest, MAX_DIM, MAX_EPS, Probability,
};
pub use error::GpuError;
pub use potential::DevicePotential;
pub use precision::Precision;
pub use shader::{Arithmetic, Compiler, Program};
pub use start::Start;
pub use step::{DeviceKernel, StepCoefficients, StepKind};
#[cfg(feature = "device")]
pub use wgpu;

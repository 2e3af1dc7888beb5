//! What the page's WebGPU path takes from the kernel: the WGSL program of
//! the `hrla-gpu` crate for the page's 2-D landscapes (its [`Program`],
//! written for Chromium's compiler), the step's coefficients as the kernel
//! computes them in f64 (rounded once to the device's f32), the kernel's
//! Ziggurat tables, and each chain's xoshiro128++ generator seeded from
//! `chain_seed`, as `hrla-gpu` seeds it. The page drives the device itself
//! (web/js/gpu.js).
//!
//! The constants buffer (`gpu_tables`) has the layout of `hrla-gpu`'s
//! `Layout` for `D = 2`: the Ziggurat's `X` at `[0, 257)` and `F` at
//! `[257, 514)`, the start's mean at 514 and 515, its standard deviation at
//! 516, `U*` at 517, then from [`GPU_COEF_OFFSET`] the eight coefficients
//! of each step of a dispatch.

use hrla::{AnySampler, SamplerKind};
use hrla::{Sampler as _, StandardNormal, chain_seed};
use hrla_gpu::{Compiler, DeviceKernel as _, DevicePotential, Program, Start, StepKind};
use rand_xoshiro::Xoshiro128PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;
use wasm_bindgen::prelude::*;

use crate::error::Error;
use crate::read;

// The kernel's own tables, from its source file (no copy to drift).
#[allow(dead_code)]
#[path = "../../core/src/ziggurat_tables.rs"]
mod ziggurat_tables;

/// The most chains the page runs on a device.
pub const GPU_MAX_CHAINS: u32 = 1_000_000;
/// The most steps of one dispatch (the coefficients' table holds this many).
pub const GPU_MAX_STEPS: u32 = 64;
/// Where the step coefficients start in the constants buffer.
pub const GPU_COEF_OFFSET: u32 = 520;
/// The page's landscapes are planar.
const D: usize = 2;

/// A setting the device path refuses, as a JS `Error` with the kernel's or
/// this module's message.
fn refuse(message: impl core::fmt::Display) -> JsError {
    JsError::new(&message.to_string())
}

fn sampler_kind(name: &str) -> Result<SamplerKind, JsError> {
    name.parse::<SamplerKind>().map_err(refuse)
}

/// The kernel's step at `h` and `a`: its coefficients in f64, in the order
/// of `hrla-gpu`'s constants buffer ([`hrla_gpu::StepCoefficients`]). The
/// sampler's other parameters are the paper's.
fn step_coefficients(sampler: SamplerKind, h: f64, a: f64) -> Result<[f64; 8], hrla::Error> {
    let kernel = AnySampler::<f64>::paper(sampler, h)?.at(a)?;
    Ok(kernel.coefficients().to_device())
}

/// The kernel's step coefficients of `sampler` (`"hrla"`, `"ula"`,
/// `"ola"`) at step `h` and inverse temperature `a`, in f64 (see the
/// module's layout); an `Error` with the kernel's message when it refuses
/// `h` or `a`.
#[wasm_bindgen]
pub fn coefficients(sampler: &str, h: f64, a: f64) -> Result<Vec<f64>, JsError> {
    let kind = sampler_kind(sampler)?;
    Ok(step_coefficients(kind, h, a).map_err(refuse)?.to_vec())
}

/// Refuses a start `N(centre, spread^2 I)` that is not finite in f32.
fn check_start(centre_x: f64, centre_y: f64, spread: f64) -> Result<(), JsError> {
    for (name, v) in [("cx", centre_x), ("cy", centre_y)] {
        if !(v as f32).is_finite() {
            return Err(refuse(format!("{name} must be a finite number, not {v}")));
        }
    }
    if !(spread >= 0.0 && (spread as f32).is_finite()) {
        return Err(refuse(format!(
            "spread must be a finite number at least 0, not {spread}"
        )));
    }
    Ok(())
}

/// The constants buffer of a run (see the module's layout), in f32: the
/// Ziggurat's tables rounded as the kernel's f32 normals round them, the
/// start `N(centre, spread^2 I)`, and [`GPU_MAX_STEPS`] copies of the
/// step's coefficients at constant `a`, each the kernel's f64 value
/// rounded once.
#[wasm_bindgen]
pub fn gpu_tables(
    sampler: &str,
    h: f64,
    a: f64,
    centre_x: f64,
    centre_y: f64,
    spread: f64,
) -> Result<Vec<f32>, JsError> {
    let kind = sampler_kind(sampler)?;
    let coefficients = step_coefficients(kind, h, a).map_err(refuse)?;
    check_start(centre_x, centre_y, spread)?;
    // The kernel's f64 coefficients may be finite where f32 is not (OLA's
    // drift at h = 1e39): the device would step by infinity.
    if let Some(c) = coefficients.iter().find(|&&c| !(c as f32).is_finite()) {
        return Err(refuse(format!(
            "at h = {h} and a = {a} the step's coefficient {c:e} exceeds f32, the device's float"
        )));
    }
    let mut t = Vec::with_capacity((GPU_COEF_OFFSET + 8 * GPU_MAX_STEPS) as usize);
    t.extend(ziggurat_tables::X.iter().map(|&v| v as f32));
    t.extend(ziggurat_tables::F.iter().map(|&v| v as f32));
    t.extend([centre_x as f32, centre_y as f32, spread as f32, 0.0]);
    t.resize(GPU_COEF_OFFSET as usize, 0.0);
    for _ in 0..GPU_MAX_STEPS {
        t.extend(coefficients.iter().map(|&v| v as f32));
    }
    Ok(t)
}

/// The chains `first .. first + count` of a run of `seed`, read as `new
/// Optimizer` reads them: the seed a whole JS number up to `2^53 - 1` or a
/// BigInt below `2^64`, the counts whole JS numbers; chains beyond
/// [`GPU_MAX_CHAINS`] refused.
fn chains(seed: &JsValue, first: &JsValue, count: &JsValue) -> Result<(u64, u32, u32), JsValue> {
    let max = GPU_MAX_CHAINS;
    let read = || -> Result<_, Error> {
        Ok((
            read::seed(seed)?,
            read::count(first, "first", 0, max.into())?,
            read::count(count, "count", 0, max.into())?,
        ))
    };
    let (seed, first, count) = read().map_err(|e| e.to_js())?;
    match (u32::try_from(first), u32::try_from(count)) {
        (Ok(first), Ok(count)) if first + count <= max => Ok((seed, first, count)),
        _ => Err(refuse(format!("chains beyond {max}")).into()),
    }
}

/// The words of [`gpu_generators`], from what it has read.
fn generators(seed: u64, first: u32, count: u32) -> Vec<u32> {
    let mut words = Vec::with_capacity(4 * count as usize);
    for c in first..first + count {
        let state = Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, u64::from(c))).state();
        words.extend(
            state
                .chunks_exact(4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        );
    }
    words
}

/// The generators of chains `first .. first + count` of a run of `seed`
/// (a whole number or a BigInt, as `new Optimizer` takes it; `first` and
/// `count` whole numbers, the chains within [`GPU_MAX_CHAINS`]): four
/// 32-bit words each, chain `c`'s
/// `Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c))` as `hrla-gpu`
/// seeds it (its state's bytes read as little-endian words).
#[wasm_bindgen]
pub fn gpu_generators(
    seed: &JsValue,
    first: &JsValue,
    count: &JsValue,
) -> Result<Vec<u32>, JsValue> {
    let (seed, first, count) = chains(seed, first, count)?;
    Ok(generators(seed, first, count))
}

/// The start of `count` chains from `N(centre, spread^2 I)`, drawn from
/// the generators `words` (four words each) as the kernel draws it in f32
/// on the CPU, coordinate-major.
fn kernel_starts(words: &[u32], centre: [f32; 2], spread: f32) -> Vec<f32> {
    let n = words.len() / 4;
    let mut out = vec![0.0f32; 2 * n];
    for (k, w) in words.chunks_exact(4).enumerate() {
        let mut state = [0u8; 16];
        for (bytes, word) in state.chunks_exact_mut(4).zip(w) {
            bytes.copy_from_slice(&word.to_le_bytes());
        }
        let mut rng = Xoshiro128PlusPlus::from_seed(state);
        for (i, mi) in centre.iter().enumerate() {
            out[i * n + k] = mi + spread * f32::standard_normal(&mut rng);
        }
    }
    out
}

/// The start of chains `first .. first + count` of a run of `seed` (read
/// as [`gpu_generators`] reads them) from `N(centre, spread^2 I)`, as the
/// kernel draws it in f32 on the CPU from the generators of
/// [`gpu_generators`]: `centre_i + spread * z` with the kernel's
/// `f32::standard_normal`, coordinate-major (`x1` of the `k`-th chain at
/// `k`, `x2` at `count + k`). The device's `init` draws the same numbers;
/// the browser tests compare the two bit for bit.
#[wasm_bindgen]
pub fn gpu_kernel_starts(
    seed: &JsValue,
    first: &JsValue,
    count: &JsValue,
    centre_x: f64,
    centre_y: f64,
    spread: f64,
) -> Result<Vec<f32>, JsValue> {
    check_start(centre_x, centre_y, spread)?;
    let (seed, first, count) = chains(seed, first, count)?;
    let words = generators(seed, first, count);
    Ok(kernel_starts(
        &words,
        [centre_x as f32, centre_y as f32],
        spread as f32,
    ))
}

/// The most chains the page's device path runs.
#[wasm_bindgen]
pub fn gpu_max_chains() -> u32 {
    GPU_MAX_CHAINS
}

/// The most steps of one dispatch.
#[wasm_bindgen]
pub fn gpu_max_steps() -> u32 {
    GPU_MAX_STEPS
}

/// Where the coefficients start in the constants buffer.
#[wasm_bindgen]
pub fn gpu_coef_offset() -> u32 {
    GPU_COEF_OFFSET
}

/// The landscapes the device runs (the page's built-in ones).
const POTENTIALS: [&str; 6] = [
    "rastrigin",
    "ackley",
    "levy",
    "styblinski-tang",
    "double-well",
    "quadratic",
];

/// Whether the device path runs landscape `name` (a visitor's formula runs
/// on the CPU only).
#[wasm_bindgen]
pub fn gpu_supports(name: &str) -> bool {
    POTENTIALS.contains(&name)
}

/// The device's potential for landscape `name`.
fn device_potential(name: &str) -> Option<DevicePotential> {
    Some(match name {
        "rastrigin" => DevicePotential::Rastrigin,
        "ackley" => DevicePotential::Ackley,
        "levy" => DevicePotential::Levy,
        "styblinski-tang" => DevicePotential::StyblinskiTang,
        "double-well" => DevicePotential::DoubleWell,
        // The page's bowl: `|x|^2 / 2`, stiffness 1 about the origin.
        "quadratic" => DevicePotential::Quadratic {
            stiffness: 1.0,
            centre: vec![0.0; D],
        },
        _ => return None,
    })
}

/// The WGSL program of `hrla-gpu` (f32, IEEE products, a Gaussian start)
/// for landscape `name` in 2-D and `sampler`'s step: entry points `init`
/// and `step` of `hrla-gpu`'s `chains.wgsl`, over its bindings 0 to 6.
/// It is written for Chromium's compiler, which would warn on the
/// visitor's console about the `return` that naga asks for.
#[wasm_bindgen]
pub fn gpu_program(name: &str, sampler: &str) -> Result<String, JsError> {
    let step = match sampler_kind(sampler)? {
        SamplerKind::Ola => StepKind::Ola,
        _ => StepKind::Ou,
    };
    let potential = device_potential(name)
        .ok_or_else(|| refuse(format!("{name} does not run on the device")))?;
    // Only the start's kind and dimension are in the program; its mean and
    // spread are in the constants buffer (`gpu_tables`).
    let start = Start::paper(D);
    Ok(Program::new(&potential, &start)
        .map_err(refuse)?
        .step(step)
        .compiler(Compiler::Tint)
        .wgsl())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients_are_the_kernels_moments() {
        // OLA at h, a: drift alpha h, noise sqrt(2 alpha h / a) (alpha = 1).
        let c = step_coefficients(SamplerKind::Ola, 0.01, 4.0).unwrap();
        assert_eq!(c[0], 0.01);
        assert!((c[1] - (2.0f64 * 0.01 / 4.0).sqrt()).abs() < 1e-15);
        // The OU step's e is exp(-alpha h) with the paper's alpha = 1.
        let c = step_coefficients(SamplerKind::Hrla, 0.01, 4.0).unwrap();
        assert!((c[1] - (-0.01f64).exp()).abs() < 1e-15, "{c:?}");
        assert!(step_coefficients(SamplerKind::Hrla, -1.0, 4.0).is_err());
        assert!(step_coefficients(SamplerKind::Ula, 0.01, f64::NAN).is_err());
    }

    #[test]
    fn tables_have_the_layout() {
        let t = gpu_tables("hrla", 0.01, 4.0, 3.0, -2.0, 0.5).unwrap();
        assert_eq!(t.len(), (GPU_COEF_OFFSET + 8 * GPU_MAX_STEPS) as usize);
        assert_eq!(t[0], ziggurat_tables::X[0] as f32);
        assert_eq!(t[257 + 256], 1.0);
        assert_eq!(&t[514..517], &[3.0, -2.0, 0.5]);
        let c = step_coefficients(SamplerKind::Hrla, 0.01, 4.0).unwrap();
        let at = GPU_COEF_OFFSET as usize;
        assert_eq!(t[at + 8 * 63 + 1], c[1] as f32);
    }

    #[test]
    fn generators_are_chain_seeds() {
        let w = generators(7, 3, 2);
        let s = Xoshiro128PlusPlus::seed_from_u64(chain_seed(7, 4)).state();
        assert_eq!(w[4], u32::from_le_bytes([s[0], s[1], s[2], s[3]]));
        assert_eq!(w.len(), 8);
    }

    #[test]
    fn kernel_starts_are_the_kernels_gaussian_draws() {
        let x = kernel_starts(&generators(5, 10, 3), [3.0, -1.0], 0.5);
        let mut rng = Xoshiro128PlusPlus::seed_from_u64(chain_seed(5, 11));
        let x1 = 3.0f32 + 0.5 * f32::standard_normal(&mut rng);
        let x2 = -1.0f32 + 0.5 * f32::standard_normal(&mut rng);
        assert_eq!((x[1], x[3 + 1]), (x1, x2));
    }

    #[test]
    fn every_page_landscape_has_a_program() {
        for name in POTENTIALS {
            for sampler in ["hrla", "ula", "ola"] {
                let p = gpu_program(name, sampler).unwrap();
                assert!(p.contains("fn step(") && !p.contains("STEP_CHAIN"));
                let unreachable = "    }\n    return 0.0;\n}\n";
                assert!(!p.contains(unreachable), "normal_slow's unreachable return");
            }
        }
    }
}

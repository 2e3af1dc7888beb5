//! What the page's WebGPU path takes from the kernel: the WGSL program of
//! the `hrla-gpu` crate for the page's 2-D landscapes (the same `.wgsl`
//! sources, embedded), the step's coefficients as the kernel computes them
//! in f64 (rounded once to the device's f32), the kernel's Ziggurat tables,
//! and each chain's xoshiro128++ generator seeded from `chain_seed`, as
//! `hrla-gpu` seeds it. The page drives the device itself (web/js/gpu.js).
//!
//! The constants buffer (`gpu_tables`) has the layout of `hrla-gpu`'s
//! `Layout` for `D = 2`: the Ziggurat's `X` at `[0, 257)` and `F` at
//! `[257, 514)`, the start's mean at 514 and 515, its standard deviation at
//! 516, `U*` at 517, then from [`GPU_COEF_OFFSET`] the eight coefficients
//! of each step of a dispatch.

use hrla::{AnyKernel, AnySampler, Float, Kernel, OlaKernel, OuKernel, SamplerKind};
use hrla::{Sampler as _, StandardNormal, chain_seed};
use rand_xoshiro::Xoshiro128PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;
use wasm_bindgen::prelude::*;

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
/// Invocations per workgroup (`hrla-gpu`'s).
const WORKGROUP: u32 = 64;
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
/// of `hrla-gpu`'s constants buffer.
///
/// HRLA and ULA (the exact OU step): `[c_xy, e, c_xg, c_yg, l_xy, l_xx,
/// l_yy, 0]`, with `y' = e y - c_yg g + l_yy z1` and `x' = x + c_xy y -
/// c_xg g + l_xy z1 + l_xx z2`. OLA: `[drift, noise, 0, ...]`, with `x' = x
/// - drift g + noise z`. The sampler's other parameters are the paper's.
fn step_coefficients(sampler: SamplerKind, h: f64, a: f64) -> Result<[f64; 8], hrla::Error> {
    let kernel = AnySampler::<f64>::paper(sampler, h)?.at(a)?;
    Ok(match kernel {
        AnyKernel::Hrla(k) | AnyKernel::Ula(k) => ou(&k),
        AnyKernel::Ola(k) => ola(&k),
    })
}

/// `hrla-gpu`'s reading of an OU kernel: its means are affine in
/// `(x, y, g)` with exact zeros and ones, so these evaluations return the
/// coefficients themselves, bit for bit.
fn ou<F: Float>(k: &OuKernel<F>) -> [f64; 8] {
    let (zero, one) = (F::ZERO, F::ONE);
    let velocity = k.moments(zero, one, zero);
    let gradient = k.moments(zero, zero, one);
    let noise = k.noise_factor();
    [
        velocity.mean_x.to_f64(),
        velocity.mean_y.to_f64(),
        -gradient.mean_x.to_f64(),
        -gradient.mean_y.to_f64(),
        noise.xy.to_f64(),
        noise.xx.to_f64(),
        noise.yy.to_f64(),
        0.0,
    ]
}

/// OLA's drift and noise scale (the square root of the kernel's rounded
/// variance gives its scale back: see `hrla-gpu`'s `step.rs`).
fn ola<F: Float>(k: &OlaKernel<F>) -> [f64; 8] {
    let m = k.moments(F::ZERO, F::ZERO, F::ONE);
    [
        -m.mean_x.to_f64(),
        m.var_x.sqrt().to_f64(),
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ]
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

/// The generators of chains `first .. first + count` of a run of `seed`:
/// four 32-bit words each, chain `c`'s
/// `Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c))` as `hrla-gpu`
/// seeds it (its state's bytes read as little-endian words).
#[wasm_bindgen]
pub fn gpu_generators(seed: u64, first: u32, count: u32) -> Result<Vec<u32>, JsError> {
    let end = first
        .checked_add(count)
        .filter(|&e| e <= GPU_MAX_CHAINS)
        .ok_or_else(|| refuse(format!("chains beyond {GPU_MAX_CHAINS}")))?;
    let mut words = Vec::with_capacity(4 * count as usize);
    for c in first..end {
        let state = Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, u64::from(c))).state();
        words.extend(
            state
                .chunks_exact(4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        );
    }
    Ok(words)
}

/// The start of chains `first .. first + count` of a run of `seed` from
/// `N(centre, spread^2 I)`, as the kernel draws it in f32 on the CPU from
/// the generators of [`gpu_generators`]: `centre_i + spread * z` with the
/// kernel's `f32::standard_normal`, coordinate-major (`x1` of the `k`-th
/// chain at `k`, `x2` at `count + k`). The device's `init` draws the same
/// numbers; the browser tests compare the two bit for bit.
#[wasm_bindgen]
pub fn gpu_kernel_starts(
    seed: u64,
    first: u32,
    count: u32,
    centre_x: f64,
    centre_y: f64,
    spread: f64,
) -> Result<Vec<f32>, JsError> {
    check_start(centre_x, centre_y, spread)?;
    let words = gpu_generators(seed, first, count)?;
    let (m, s) = ([centre_x as f32, centre_y as f32], spread as f32);
    let n = count as usize;
    let mut out = vec![0.0f32; 2 * n];
    for (k, w) in words.chunks_exact(4).enumerate() {
        let mut state = [0u8; 16];
        for (bytes, word) in state.chunks_exact_mut(4).zip(w) {
            bytes.copy_from_slice(&word.to_le_bytes());
        }
        let mut rng = Xoshiro128PlusPlus::from_seed(state);
        for (i, mi) in m.iter().enumerate() {
            out[i * n + k] = mi + s * f32::standard_normal(&mut rng);
        }
    }
    Ok(out)
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

/// `hrla-gpu`'s potential source for `name` and its constants.
fn potential_source(name: &str) -> Option<(&'static str, Vec<(&'static str, f64)>)> {
    use core::f64::consts::{E, PI};
    Some(match name {
        "rastrigin" => (
            include_str!("../../gpu/src/wgsl/potential/rastrigin.wgsl"),
            vec![],
        ),
        "ackley" => (
            include_str!("../../gpu/src/wgsl/potential/ackley.wgsl"),
            vec![("ACKLEY_PI", PI), ("ACKLEY_E", E)],
        ),
        "levy" => (
            include_str!("../../gpu/src/wgsl/potential/levy.wgsl"),
            vec![("LEVY_PI", PI)],
        ),
        "styblinski-tang" => (
            include_str!("../../gpu/src/wgsl/potential/styblinski_tang.wgsl"),
            vec![],
        ),
        "double-well" => (
            include_str!("../../gpu/src/wgsl/potential/double_well.wgsl"),
            vec![],
        ),
        // The page's bowl: `|x|^2 / 2`, stiffness 1 about the origin.
        "quadratic" => (
            include_str!("../../gpu/src/wgsl/potential/quadratic.wgsl"),
            vec![("QUADRATIC_STIFFNESS", 1.0)],
        ),
        _ => return None,
    })
}

/// `v` as a WGSL f32 literal with the same bits (hexadecimal, so that no
/// decimal rounding intervenes), as `hrla-gpu` writes them.
fn lit(v: f64) -> String {
    let v = v as f32;
    if v == 0.0 {
        return if v.is_sign_negative() {
            "-0.0f"
        } else {
            "0.0f"
        }
        .to_string();
    }
    if !v.is_normal() {
        return format!("bitcast<f32>({:#010x}u)", v.to_bits());
    }
    let bits = v.to_bits();
    let sign = if bits >> 31 == 1 { "-" } else { "" };
    let exponent = ((bits >> 23) & 0xff) as i32 - 127;
    let mantissa = (bits & 0x7f_ffff) << 1;
    format!("{sign}0x1.{mantissa:06x}p{exponent}f")
}

/// fdlibm's `expf` and `logf` constants (`hrla-gpu`'s `FDLIBM`).
#[allow(clippy::excessive_precision)]
const FDLIBM: [(&str, f32); 11] = [
    ("EXPF_LN2_HI", 6.9314575195e-01),
    ("EXPF_LN2_LO", 1.4286067653e-06),
    ("EXPF_INV_LN2", 1.4426950216e+00),
    ("EXPF_P1", 1.6666625440e-1),
    ("EXPF_P2", -2.7667332906e-3),
    ("LOGF_LN2_HI", 6.9313812256e-01),
    ("LOGF_LN2_LO", 9.0580006145e-06),
    ("LOGF_LG1", 0.66666662693),
    ("LOGF_LG2", 0.40000972152),
    ("LOGF_LG3", 0.28498786688),
    ("LOGF_LG4", 0.24279078841),
];

/// fdlibm's `__kernel_sin` and `__kernel_cos` coefficients, the four that
/// the f32 Rastrigin uses (`hrla-gpu`'s `SIN`, `COS`).
const SIN: [u64; 4] = [
    0xBFC5_5555_5555_5549,
    0x3F81_1111_1110_F8A6,
    0xBF2A_01A0_19C1_61D5,
    0x3EC7_1DE3_57B1_FE7D,
];
const COS: [u64; 4] = [
    0x3FA5_5555_5555_554C,
    0xBF56_C16C_16C1_5177,
    0x3EFA_01A0_19CB_1590,
    0xBE92_7E4F_809C_52AD,
];

/// The end of `normal_slow` in `normal32.wgsl`.
const UNREACHABLE: &str = "    }\n    return 0.0;\n}\n";

/// The OU step of HRLA and ULA (`hrla-gpu`'s `OU_STEP`).
const OU_STEP: &str = "
        let c_xy = coef(s, 0u);
        let e = coef(s, 1u);
        let c_xg = coef(s, 2u);
        let c_yg = coef(s, 3u);
        let l_xy = coef(s, 4u);
        let l_xx = coef(s, 5u);
        let l_yy = coef(s, 6u);
        for (var i = 0u; i < D; i++) {
            let z = normal_pair();
            let mx = x[i] + mul(c_xy, y[i]) - mul(c_xg, g[i]);
            let my = mul(e, y[i]) - mul(c_yg, g[i]);
            x[i] = mx + mul(l_xy, z.x) + mul(l_xx, z.y);
            y[i] = my + mul(l_yy, z.x);
        }";

/// OLA's Euler–Maruyama step (`hrla-gpu`'s `OLA_STEP`).
const OLA_STEP: &str = "
        let drift = coef(s, 0u);
        let noise = coef(s, 1u);
        for (var i = 0u; i < D; i++) {
            x[i] = x[i] - mul(drift, g[i]) + mul(noise, normal());
        }";

/// The WGSL program of `hrla-gpu` (f32, IEEE products, a Gaussian start)
/// for landscape `name` in 2-D and `sampler`'s step: entry points `init`
/// and `step` of `hrla-gpu`'s `chains.wgsl`, over its bindings 0 to 6.
#[wasm_bindgen]
pub fn gpu_program(name: &str, sampler: &str) -> Result<String, JsError> {
    let kind = sampler_kind(sampler)?;
    let (potential, constants) = potential_source(name)
        .ok_or_else(|| refuse(format!("{name} does not run on the device")))?;
    let mut src = String::from(potential);
    for (n, v) in constants {
        src.push_str(&format!("const {n}: Real = {};\n", lit(v)));
    }
    if name == "quadratic" {
        src.push_str("const QUADRATIC_CENTRE = array<Real, 2>(0.0f, 0.0f);\n");
    }
    src.push_str("\n// ---- hrla-gpu ----\nalias Real = f32;\n");
    src.push_str(
        "fn rounded(s: Real) -> Real {\n    return bitcast<f32>(bitcast<u32>(s) ^ params.zero);\n}\n\
         fn mul(a: Real, b: Real) -> Real {\n    return rounded(a * b);\n}\n\
         fn finite(v: Real) -> bool {\n    return (bitcast<u32>(v) & 0x7f800000u) != 0x7f800000u;\n}\n\
         fn none() -> Real {\n    return Real(bitcast<f32>(0x7f800000u | params.zero));\n}\n",
    );
    let max = f64::from(f32::MAX);
    src.push_str(&format!("const REAL_MAX: Real = {};\n", lit(max)));
    src.push_str(&format!("const D: u32 = {D}u;\n"));
    src.push_str("const START_IN_BEST: bool = true;\n");
    src.push_str(&format!(
        "const START_TRIES: u32 = {}u;\n",
        hrla::START_TRIES
    ));
    src.push_str("alias Point = array<Real, D>;\n");
    src.push_str(&format!("const WORKGROUP: u32 = {WORKGROUP}u;\n"));
    src.push_str("const U_STAR_AT: u32 = 517u;\n");
    src.push_str(&format!("const FLOOR: Real = {};\n", lit(-max.sqrt())));
    src.push_str(&format!(
        "const RASTRIGIN_TAU: Real = {};\nconst RASTRIGIN_PI: Real = {};\n",
        lit(core::f64::consts::TAU),
        lit(core::f64::consts::PI)
    ));
    for (i, (&s, &c)) in SIN.iter().zip(&COS).enumerate() {
        src.push_str(&format!(
            "const RASTRIGIN_S{i}: Real = {};\nconst RASTRIGIN_C{i}: Real = {};\n",
            lit(f64::from_bits(s)),
            lit(f64::from_bits(c))
        ));
    }
    src.push_str(include_str!("../../gpu/src/wgsl/random.wgsl"));
    src.push_str(&format!(
        "const RASTRIGIN_FAST_LIMIT: Real = {};\n",
        lit(1_048_576.0)
    ));
    src.push_str(&format!(
        "const ZIG_R: Real = {};\n",
        lit(ziggurat_tables::R)
    ));
    for (n, v) in FDLIBM {
        src.push_str(&format!("const {n}: f32 = {};\n", lit(f64::from(v))));
    }
    // `normal_slow` ends in a loop that only returns, after which
    // hrla-gpu's source has a `return` that naga asks for and Chromium's
    // compiler warns about as unreachable (on the visitor's console).
    src.push_str(&include_str!("../../gpu/src/wgsl/normal32.wgsl").replacen(
        UNREACHABLE,
        "    }\n}\n",
        1,
    ));
    let step = match kind {
        SamplerKind::Ola => OLA_STEP,
        _ => OU_STEP,
    };
    src.push_str(
        &include_str!("../../gpu/src/wgsl/chains.wgsl")
            .replace(
                "START_COORDINATE",
                "x[i] = tables[514u + i] + mul(tables[516u], normal());",
            )
            .replace("STEP_CHAIN", step),
    );
    Ok(src)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_read_back() {
        for v in [1.0f32, -2.5, 0.1, core::f32::consts::PI, 1e-30, 6e37] {
            let s = lit(f64::from(v));
            let body = s.trim_end_matches('f');
            let (neg, body) = match body.strip_prefix('-') {
                Some(b) => (true, b),
                None => (false, body),
            };
            let (m, e) = body.trim_start_matches("0x1.").split_once('p').unwrap();
            let m = u32::from_str_radix(m, 16).unwrap() >> 1;
            let e: i32 = e.parse().unwrap();
            let bits = (u32::from(neg) << 31) | (((e + 127) as u32) << 23) | m;
            assert_eq!(f32::from_bits(bits), v, "{s}");
        }
    }

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
        let w = gpu_generators(7, 3, 2).unwrap();
        let s = Xoshiro128PlusPlus::seed_from_u64(chain_seed(7, 4)).state();
        assert_eq!(w[4], u32::from_le_bytes([s[0], s[1], s[2], s[3]]));
        assert_eq!(w.len(), 8);
    }

    #[test]
    fn kernel_starts_are_the_kernels_gaussian_draws() {
        let x = gpu_kernel_starts(5, 10, 3, 3.0, -1.0, 0.5).unwrap();
        let mut rng = Xoshiro128PlusPlus::seed_from_u64(chain_seed(5, 11));
        let x1 = 3.0f32 + 0.5 * f32::standard_normal(&mut rng);
        let x2 = -1.0f32 + 0.5 * f32::standard_normal(&mut rng);
        assert_eq!((x[1], x[3 + 1]), (x1, x2));
    }

    /// The pieces of `hrla-gpu`'s `shader.rs` that this module repeats
    /// (that crate runs on wgpu, which the page's wasm does not link): its
    /// steps word for word, its fdlibm constants and sine and cosine
    /// coefficients, checked against its source so that the two cannot
    /// drift apart.
    #[test]
    fn the_repeated_pieces_are_hrla_gpus() {
        let shader = include_str!("../../gpu/src/shader.rs");
        assert!(shader.contains(OU_STEP), "OU_STEP");
        assert!(shader.contains(OLA_STEP), "OLA_STEP");
        assert!(shader.contains("pub(crate) const WORKGROUP: u32 = 64;"));
        for bits in SIN.iter().chain(&COS) {
            let hex = format!("{bits:016X}");
            let written = format!(
                "0x{}_{}_{}_{},",
                &hex[0..4],
                &hex[4..8],
                &hex[8..12],
                &hex[12..16]
            );
            assert!(shader.contains(&written), "{written}");
        }
        for (name, value) in FDLIBM {
            let head = format!("(\"{name}\", ");
            let at = shader.find(&head).expect(name) + head.len();
            let end = at + shader[at..].find(')').unwrap();
            let theirs: f32 = shader[at..end].parse().unwrap();
            assert_eq!(theirs.to_bits(), value.to_bits(), "{name}");
        }
        // The Gaussian start and the layout of the constants buffer.
        assert!(shader.contains("u_star: (514 + dim + 1) as u32"));
        assert!(shader.contains("\"x[i] = tables[{m}u + i] + mul(tables[{s}u], normal());\""));
    }

    #[test]
    fn every_page_landscape_has_a_program() {
        for name in POTENTIALS {
            for sampler in ["hrla", "ula", "ola"] {
                let p = gpu_program(name, sampler).unwrap();
                assert!(p.contains("fn step(") && !p.contains("STEP_CHAIN"));
                assert!(!p.contains(UNREACHABLE), "normal_slow's unreachable return");
            }
        }
    }
}

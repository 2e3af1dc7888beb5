//! The WGSL program of one problem: the potential's source, the constants
//! (dimension, Ziggurat, fdlibm, the potential's own) as exact hexadecimal
//! literals, the generator and normals, and the chains' kernels with the
//! sampler's step spliced in.

use crate::potential::{DevicePotential, PotentialSource};
use crate::start::Start;

/// Invocations per workgroup.
pub(crate) const WORKGROUP: u32 = 64;

/// `v` as a WGSL f32 literal with the same bits: hexadecimal for normal
/// numbers, so that no decimal rounding (single or double) intervenes.
pub(crate) fn f32_literal(v: f32) -> String {
    if v == 0.0 {
        return if v.is_sign_negative() {
            "-0.0f"
        } else {
            "0.0f"
        }
        .to_string();
    }
    if !v.is_normal() {
        // Infinities, NaN and subnormals have no exact literal.
        return format!("bitcast<f32>({:#010x}u)", v.to_bits());
    }
    let bits = v.to_bits();
    let sign = if bits >> 31 == 1 { "-" } else { "" };
    let exponent = ((bits >> 23) & 0xff) as i32 - 127;
    let mantissa = (bits & 0x7f_ffff) << 1;
    format!("{sign}0x1.{mantissa:06x}p{exponent}f")
}

/// The kernel's Ziggurat tables (layer edges `X`, densities `F`, tail start
/// `R`), read from the kernel's own source so that the two can never
/// drift apart, and rounded to f32 as the kernel rounds them.
pub(crate) struct Ziggurat {
    pub x: Vec<f32>,
    pub f: Vec<f32>,
    pub r: f32,
}

const ZIGGURAT_SOURCE: &str = include_str!("../../core/src/ziggurat_tables.rs");

impl Ziggurat {
    pub(crate) fn from_kernel() -> Self {
        Self {
            x: table("X"),
            f: table("F"),
            r: number_after("pub(crate) const R: f64 =") as f32,
        }
    }
}

/// A `[f64; 257]` table of the kernel's source, by name.
fn table(name: &str) -> Vec<f32> {
    let head = format!("pub(crate) static {name}: [f64; 257] =");
    let start = ZIGGURAT_SOURCE
        .find(&head)
        .expect("table in the kernel's source")
        + head.len();
    let body = &ZIGGURAT_SOURCE[start..];
    let open = body.find('[').expect("table opens") + 1;
    let close = body.find(']').expect("table closes");
    body[open..close]
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>().expect("a number") as f32)
        .collect()
}

fn number_after(head: &str) -> f64 {
    let start = ZIGGURAT_SOURCE
        .find(head)
        .expect("constant in the kernel's source")
        + head.len();
    let end = start + ZIGGURAT_SOURCE[start..].find(';').expect("constant ends");
    ZIGGURAT_SOURCE[start..end]
        .trim()
        .parse()
        .expect("a number")
}

/// fdlibm's `expf` and `logf` constants, verbatim as the `libm` crate
/// writes them (Rust parses them to the same f32 bits as it did there; the
/// unit test checks the bit patterns fdlibm gives beside them).
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

/// Rastrigin's `π` and `2π` in f32, as the kernel rounds them.
const RASTRIGIN: [(&str, f32); 2] = [
    ("RASTRIGIN_PI", core::f32::consts::PI),
    ("RASTRIGIN_TAU", core::f64::consts::TAU as f32),
];

/// fdlibm's `__kernel_sin` and `__kernel_cos` coefficients, the first four
/// of each, as bit patterns, rounded to f32 (the kernel's Rastrigin in f32).
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

/// How the device may round the kernel's sums and products.
///
/// WGSL lets a driver contract `a * b + c` into one fused multiply-add (one
/// rounding instead of two) and reassociate sums: lavapipe (Mesa 22.3)
/// turns `(a - b) + 2.5` into another order of additions, and GPU drivers
/// fuse multiply-adds. The kernel does neither, so for its bits the program
/// writes every product that an addition takes as `mul(a, b)`, and every
/// sum that a constant is then added to as `rounded(s)`: in
/// [`Arithmetic::Ieee`] both pass the value through an integer
/// exclusive-or with a zero that the compiler cannot see (a uniform): no
/// floating-point rule (contraction, reassociation, factoring) sees
/// through it. (A multiplication by an unseen 1.0 does not do: a compiler
/// factors `a * one + b * one` into `(a + b) * one`.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Arithmetic {
    /// Every product rounded before it is added, as the kernel computes:
    /// the kernel's bits on a device whose division and square root are
    /// correctly rounded (lavapipe's are). One more integer operation per
    /// product and fenced sum.
    #[default]
    Ieee,
    /// The driver fuses as it likes: the same law, not the same bits, and
    /// fewer instructions.
    Fused,
}

/// Which sampler's step the kernel runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum StepKind {
    /// The exact OU step of HRLA and ULA.
    Ou,
    /// OLA's Euler–Maruyama step.
    Ola,
}

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

const OLA_STEP: &str = "
        let drift = coef(s, 0u);
        let noise = coef(s, 1u);
        for (var i = 0u; i < D; i++) {
            x[i] = x[i] - mul(drift, g[i]) + mul(noise, normal());
        }";

/// Where the start, `U*` and the eps values sit in the constants buffer.
pub(crate) struct Layout {
    /// Index of `U*`; the eps values follow it.
    pub u_star: u32,
}

impl Layout {
    pub(crate) fn new(dim: usize) -> Self {
        // X (257), F (257), the start's mean (dim) and standard deviation.
        Self {
            u_star: (514 + dim + 1) as u32,
        }
    }
    pub(crate) fn start_mean(&self) -> u32 {
        514
    }
}

/// The whole program. The potential's source comes first, so that the
/// line numbers of a user's compile errors are those of the user's text.
pub(crate) fn program(
    dim: usize,
    potential: &DevicePotential,
    start: &Start,
    step: StepKind,
    arithmetic: Arithmetic,
) -> String {
    let z = Ziggurat::from_kernel();
    let layout = Layout::new(dim);
    let mut src = String::new();
    match potential.source() {
        PotentialSource::Builtin(text, constants) => {
            src.push_str(text);
            for (name, value) in constants {
                src.push_str(&format!("const {name}: f32 = {};\n", f32_literal(value)));
            }
            if let Some(centre) = potential.centre() {
                let items: Vec<String> = centre.iter().map(|&v| f32_literal(v as f32)).collect();
                src.push_str(&format!(
                    "const QUADRATIC_CENTRE = array<f32, {dim}>({});\n",
                    items.join(", ")
                ));
            }
        }
        PotentialSource::Wgsl(text) => src.push_str(text),
    }
    src.push_str("\n// ---- hrla-gpu ----\n");
    src.push_str("alias Real = f32;\n");
    src.push_str(match arithmetic {
        Arithmetic::Ieee => {
            "fn mul(a: f32, b: f32) -> f32 {\n    return rounded(a * b);\n}\n\
             fn rounded(s: f32) -> f32 {\n    return bitcast<f32>(bitcast<u32>(s) ^ params.zero);\n}\n"
        }
        Arithmetic::Fused => {
            "fn mul(a: f32, b: f32) -> f32 {\n    return a * b;\n}\n\
             fn rounded(s: f32) -> f32 {\n    return s;\n}\n"
        }
    });
    src.push_str(&format!("const D: u32 = {dim}u;\n"));
    src.push_str("alias Point = array<Real, D>;\n");
    src.push_str(&format!("const WORKGROUP: u32 = {WORKGROUP}u;\n"));
    src.push_str(&format!("const ZIG_R: f32 = {};\n", f32_literal(z.r)));
    src.push_str(&format!(
        "const FLOOR: f32 = {};\n",
        f32_literal(-(f32::MAX.sqrt()))
    ));
    src.push_str(&format!("const U_STAR_AT: u32 = {}u;\n", layout.u_star));
    for (name, value) in FDLIBM.into_iter().chain(RASTRIGIN) {
        src.push_str(&format!("const {name}: f32 = {};\n", f32_literal(value)));
    }
    for (i, (&s, &c)) in SIN.iter().zip(&COS).enumerate() {
        let (s, c) = (f64::from_bits(s) as f32, f64::from_bits(c) as f32);
        src.push_str(&format!(
            "const RASTRIGIN_S{i}: f32 = {};\n",
            f32_literal(s)
        ));
        src.push_str(&format!(
            "const RASTRIGIN_C{i}: f32 = {};\n",
            f32_literal(c)
        ));
    }
    // The polynomial path's limit, 2^20 in f32 (the kernel's `fast_limit`).
    src.push_str(&format!(
        "const RASTRIGIN_FAST_LIMIT: f32 = {};\n",
        f32_literal((1u64 << (f32::MANTISSA_DIGITS - 4)) as f32)
    ));
    src.push_str(include_str!("wgsl/random.wgsl"));
    let start_coordinate = match start {
        Start::Gaussian { .. } => format!(
            "x[i] = tables[{m}u + i] + mul(tables[{s}u], normal());",
            m = layout.start_mean(),
            s = layout.start_mean() as usize + dim
        ),
        Start::Point(_) => format!("x[i] = tables[{}u + i];", layout.start_mean()),
    };
    let step_chain = match step {
        StepKind::Ou => OU_STEP,
        StepKind::Ola => OLA_STEP,
    };
    src.push_str(
        &include_str!("wgsl/chains.wgsl")
            .replace("START_COORDINATE", &start_coordinate)
            .replace("STEP_CHAIN", step_chain),
    );
    src
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_are_exact() {
        for v in [
            1.0f32,
            -2.5,
            0.1,
            core::f32::consts::PI,
            3.654_153,
            1e-30,
            6e37,
        ] {
            let s = f32_literal(v);
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
    fn fdlibm_constants_have_fdlibms_bits() {
        // From the comments of e_expf.c and e_logf.c.
        for (i, bits) in [
            (0, 0x3f31_7200),
            (1, 0x35bf_be8e),
            (2, 0x3fb8_aa3b),
            (5, 0x3f31_7180),
            (6, 0x3717_f7d1),
        ] {
            assert_eq!(FDLIBM[i].1.to_bits(), bits, "{}", FDLIBM[i].0);
        }
        // The polynomials' coefficients, given as hexadecimal fractions.
        let frac = |m: u32, e: i32| m as f32 * 2f32.powi(e);
        assert_eq!(FDLIBM[3].1, frac(0xaaaa8f, -26));
        assert_eq!(FDLIBM[4].1, -frac(0xb55215, -32));
        assert_eq!(FDLIBM[7].1, frac(0xaaaaaa, -24));
        assert_eq!(FDLIBM[8].1, frac(0xccce13, -25));
        assert_eq!(FDLIBM[9].1, frac(0x91e9ee, -25));
        assert_eq!(FDLIBM[10].1, frac(0xf89e26, -26));
    }

    #[test]
    fn kernel_tables_parse() {
        let z = Ziggurat::from_kernel();
        assert_eq!((z.x.len(), z.f.len()), (257, 257));
        // Edges decrease to 0, densities rise to 1, the tail starts at X[1].
        assert!(z.x.windows(2).all(|w| w[0] > w[1]));
        assert!(z.f.windows(2).all(|w| w[0] < w[1]));
        assert_eq!((z.x[256], z.f[256]), (0.0, 1.0));
        assert_eq!(z.r, z.x[1]);
    }
}

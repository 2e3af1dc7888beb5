//! The WGSL program of one problem: the potential's source, the constants
//! (dimension, Ziggurat, fdlibm, the potential's own) as exact hexadecimal
//! literals, the generator and normals, and the chains' kernels with the
//! sampler's step spliced in. It needs no device: a page that drives
//! WebGPU itself takes its program from here.

use std::borrow::Cow;

use crate::error::GpuError;
use crate::potential::{DevicePotential, PotentialSource};
use crate::precision::{Precision, f32_literal};
use crate::start::Start;
use crate::step::StepKind;

/// Invocations per workgroup.
pub(crate) const WORKGROUP: u32 = 64;

/// The kernel's Ziggurat tables (layer edges `X`, densities `F`, tail start
/// `R`), read from the kernel's own source so that the two can never
/// drift apart, and rounded to f32 as the kernel rounds them.
#[cfg_attr(not(feature = "device"), allow(dead_code))]
pub(crate) struct Ziggurat {
    pub x: Vec<f32>,
    pub f: Vec<f32>,
    pub r: f32,
    pub x64: Vec<f64>,
    pub f64: Vec<f64>,
    pub r64: f64,
}

const ZIGGURAT_SOURCE: &str = include_str!("../../core/src/ziggurat_tables.rs");

impl Ziggurat {
    pub(crate) fn from_kernel() -> Self {
        let (x64, f64, r64) = (
            table("X"),
            table("F"),
            number_after("pub(crate) const R: f64 ="),
        );
        Self {
            x: x64.iter().map(|&v| v as f32).collect(),
            f: f64.iter().map(|&v| v as f32).collect(),
            r: r64 as f32,
            x64,
            f64,
            r64,
        }
    }
}

/// A `[f64; 257]` table of the kernel's source, by name.
fn table(name: &str) -> Vec<f64> {
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
        .map(|s| s.parse::<f64>().expect("a number"))
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

/// fdlibm's `__kernel_sin` and `__kernel_cos` coefficients as bit
/// patterns: all six in f64, the first four rounded to f32 (the kernel's
/// Rastrigin in each type).
const SIN: [u64; 6] = [
    0xBFC5_5555_5555_5549,
    0x3F81_1111_1110_F8A6,
    0xBF2A_01A0_19C1_61D5,
    0x3EC7_1DE3_57B1_FE7D,
    0xBE5A_E5E6_8A2B_9CEB,
    0x3DE5_D93A_5ACF_D57C,
];
const COS: [u64; 6] = [
    0x3FA5_5555_5555_554C,
    0xBF56_C16C_16C1_5177,
    0x3EFA_01A0_19CB_1590,
    0xBE92_7E4F_809C_52AD,
    0x3E21_EE9E_BDB4_B1C4,
    0xBDA8_FAE9_BE88_38D4,
];

/// fdlibm's `exp` and `log` (e_exp.c, e_log.c) constants, as the bit
/// patterns fdlibm gives beside the decimals the `libm` crate writes (the
/// unit test checks that the two agree), and the bounds of their tests of
/// a high word, as the f64 whose high word is the bound.
const FDLIBM64: [(&str, u64); 23] = [
    ("EXP_LN2HI", 0x3fe6_2e42_fee0_0000),
    ("EXP_LN2LO", 0x3dea_39ef_3579_3c76),
    ("EXP_INVLN2", 0x3ff7_1547_652b_82fe),
    ("EXP_P1", 0x3FC5_5555_5555_553E),
    ("EXP_P2", 0xBF66_C16C_16BE_BD93),
    ("EXP_P3", 0x3F11_566A_AF25_DE2C),
    ("EXP_P4", 0xBEBB_BD41_C5D2_6BF1),
    ("EXP_P5", 0x3E66_3769_72BE_A4D0),
    ("LOG_LN2_HI", 0x3fe6_2e42_fee0_0000),
    ("LOG_LN2_LO", 0x3dea_39ef_3579_3c76),
    ("LOG_LG1", 0x3FE5_5555_5555_5593),
    ("LOG_LG2", 0x3FD9_9999_9997_FA04),
    ("LOG_LG3", 0x3FD2_4924_9422_9359),
    ("LOG_LG4", 0x3FCC_71C5_1D8E_78AF),
    ("LOG_LG5", 0x3FC7_4664_96CB_03DE),
    ("LOG_LG6", 0x3FC3_9A09_D078_C69F),
    ("LOG_LG7", 0x3FC2_F112_DF3E_5244),
    // |x| > 0.5 ln 2, |x| >= 1.5 ln 2, |x| > 2^-28 (e_exp.c) and the
    // reduction into [sqrt(2)/2, sqrt(2)) (e_log.c).
    ("EXP_HALF_LN2_BOUND", 0x3fd6_2e43_0000_0000),
    ("EXP_THREE_HALF_LN2_BOUND", 0x3ff0_a2b2_0000_0000),
    ("EXP_TINY_BOUND", 0x3e30_0001_0000_0000),
    ("LOG_REDUCE_BOUND", 0x3ff6_a09e_0000_0000),
    ("EXP_2_M51", 0x3cc0_0000_0000_0000),
    ("EXP_2_M53", 0x3ca0_0000_0000_0000),
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

/// The settings that [`Program`] and
/// [`EnsembleBuilder`](crate::EnsembleBuilder) share, with their defaults
/// in one place.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Settings {
    pub(crate) arithmetic: Arithmetic,
    pub(crate) precision: Precision,
    pub(crate) start_in_best: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            arithmetic: Arithmetic::Ieee,
            precision: Precision::F32,
            start_in_best: true,
        }
    }
}

/// The setters of [`Settings`], for a builder that holds them as its
/// `settings` field: [`Program`] and
/// [`EnsembleBuilder`](crate::EnsembleBuilder) take the same settings with
/// the same meaning, so they share one text of each setter and its
/// documentation.
macro_rules! settings_setters {
    () => {
        /// How the device may round products that additions take
        /// ([`Arithmetic::Ieee`](crate::Arithmetic::Ieee) by default: the
        /// kernel's bits where the device rounds as IEEE 754 does).
        pub fn arithmetic(mut self, arithmetic: crate::Arithmetic) -> Self {
            self.settings.arithmetic = arithmetic;
            self
        }

        /// The float type of the device
        /// ([`Precision::F32`](crate::Precision::F32) by default).
        /// [`Precision::F64`](crate::Precision::F64) needs an adapter with
        /// `SHADER_F64` ([`Gpu::supports_f64`](crate::Gpu::supports_f64))
        /// and a potential without `sin`, `cos` or `exp` (Vulkan has them
        /// in f32 only: not Ackley or Levy, whose program does not compile
        /// in f64).
        pub fn precision(mut self, precision: crate::Precision) -> Self {
            self.settings.precision = precision;
            self
        }

        /// Whether iterate 0 (the start) takes part in each chain's
        /// running best: `true` by default, as in
        /// [`hrla::Optimizer::best`]; `false` starts every running best at
        /// `+inf`, for a running best over `k = s, 2s, ...` only (the
        /// paper's tables).
        pub fn start_in_best(mut self, include: bool) -> Self {
            self.settings.start_in_best = include;
            self
        }
    };
}
#[cfg(feature = "device")]
pub(crate) use settings_setters;

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

/// Which WGSL compiler a program is written for. The two differ in one
/// place: a function whose last statement is a loop that only leaves by
/// `return`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Compiler {
    /// naga, wgpu's compiler, which asks for a `return` after such a loop
    /// (the backend's own ensembles).
    #[default]
    Naga,
    /// A compiler that follows the WGSL specification's analysis of
    /// behaviours (Chromium's Tint): it accepts the function without that
    /// `return` and warns about it as unreachable, on a page's console.
    Tint,
}

/// The end of the Ziggurat's slow path (`normal_slow` in `normal32.wgsl`,
/// `normal_slow64` in `normal64.wgsl`): a loop that only returns, and the
/// `return` after it that naga asks for.
const SLOW_PATH_END: &str = "    }\n    return 0.0;\n}\n";

impl Compiler {
    /// A file of normals (`normal32.wgsl`, `normal64.wgsl`) as this
    /// compiler takes it.
    fn normals(self, file: &'static str) -> Cow<'static, str> {
        match self {
            Self::Naga => Cow::Borrowed(file),
            Self::Tint => Cow::Owned(file.replacen(SLOW_PATH_END, "    }\n}\n", 1)),
        }
    }
}

/// The WGSL program of one problem, built up from its pieces; [`Program::wgsl`]
/// writes it.
///
/// The program's entry points (`init`, `step`, `argmin`, `groups`,
/// `census`, `normals`) and bindings are those the backend's ensembles
/// drive; a page that drives WebGPU itself takes the same text from here.
/// Its constants buffer holds the Ziggurat's `X` and `F` (257 floats each),
/// then from index 514 the start's mean (`D` floats) and standard
/// deviation, `U*`, the eps values and the step's coefficients.
///
/// ```
/// use hrla_gpu::{DevicePotential, Precision, Program, Start, StepKind};
///
/// let start = Start::paper(2);
/// let wgsl = Program::new(&DevicePotential::Rastrigin, &start)?
///     .step(StepKind::Ola)
///     .precision(Precision::F32)
///     .wgsl();
/// assert!(wgsl.contains("fn step("));
/// # Ok::<(), hrla_gpu::GpuError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Program<'a> {
    potential: &'a DevicePotential,
    start: &'a Start,
    step: StepKind,
    settings: Settings,
    compiler: Compiler,
}

impl<'a> Program<'a> {
    /// The program of `potential` from `start` (whose dimension is the
    /// program's `D`): by default HRLA's and ULA's step
    /// ([`StepKind::Ou`]), [`Arithmetic::Ieee`], [`Precision::F32`], the
    /// start counted in the best, for [`Compiler::Naga`].
    ///
    /// Errors: [`GpuError::Kernel`] with [`hrla::Error::Zero`] for a
    /// start of dimension 0, [`GpuError::Dimension`] for a potential whose
    /// own dimension (a quadratic's centre) is not the start's.
    pub fn new(potential: &'a DevicePotential, start: &'a Start) -> Result<Self, GpuError> {
        let dim = start.dimension();
        if dim == 0 {
            return Err(hrla::Error::Zero {
                name: "dimension D",
            }
            .into());
        }
        if let Some(d) = potential.dimension().filter(|&d| d != dim) {
            return Err(GpuError::Dimension {
                expected: dim,
                got: d,
                what: "potential",
            });
        }
        Ok(Self {
            potential,
            start,
            step: StepKind::Ou,
            settings: Settings::default(),
            compiler: Compiler::Naga,
        })
    }

    /// The sampler's kind of step.
    pub fn step(mut self, step: StepKind) -> Self {
        self.step = step;
        self
    }

    settings_setters!();

    /// All the shared settings at once, as an ensemble's builder holds them.
    #[cfg(feature = "device")]
    pub(crate) fn settings(mut self, settings: Settings) -> Self {
        self.settings = settings;
        self
    }

    /// The compiler the text is written for.
    pub fn compiler(mut self, compiler: Compiler) -> Self {
        self.compiler = compiler;
        self
    }

    /// The whole program. The potential's source comes first, so that the
    /// line numbers of a user's compile errors are those of the user's
    /// text.
    pub fn wgsl(&self) -> String {
        let Self {
            potential,
            start,
            step,
            settings:
                Settings {
                    arithmetic,
                    precision,
                    start_in_best,
                },
            compiler,
        } = *self;
        let dim = start.dimension();
        let z = Ziggurat::from_kernel();
        let layout = Layout::new(dim);
        let lit = |v: f64| precision.literal(v);
        let mut src = String::new();
        match potential.source(precision) {
            PotentialSource::Builtin(text, constants) => {
                src.push_str(text);
                for (name, value) in constants {
                    src.push_str(&format!("const {name}: Real = {};\n", lit(value)));
                }
                if let Some(centre) = potential.centre() {
                    let items: Vec<String> = centre.iter().map(|&v| lit(v)).collect();
                    src.push_str(&format!(
                        "const QUADRATIC_CENTRE = array<Real, {dim}>({});\n",
                        items.join(", ")
                    ));
                }
            }
            PotentialSource::Wgsl(text) => src.push_str(text),
        }
        src.push_str("\n// ---- hrla-gpu ----\n");
        let (real, max) = match precision {
            Precision::F32 => ("f32", f64::from(f32::MAX)),
            Precision::F64 => ("f64", f64::MAX),
        };
        src.push_str(&format!("alias Real = {real};\n"));
        // The fences of `Arithmetic::Ieee`: in f32, an integer exclusive-or
        // with an unseen 0. In f64, whose bits WGSL does not expose: a product
        // plus an unseen -0.0 (which leaves every value, -0.0 included, as it
        // is; at most it fuses into a multiply-add that rounds the product
        // alone), and a sum times an unseen 1.0 (an addition would join the
        // sums that a compiler reorders; factoring `(a + b) * 1 + (c + d) * 1`
        // into `(a + b + c + d) * 1` rounds as written).
        src.push_str(match (arithmetic, precision) {
            (Arithmetic::Ieee, Precision::F32) => {
                "fn rounded(s: Real) -> Real {\n    return bitcast<f32>(bitcast<u32>(s) ^ params.zero);\n}\n\
                 fn mul(a: Real, b: Real) -> Real {\n    return rounded(a * b);\n}\n"
            }
            (Arithmetic::Ieee, Precision::F64) => {
                "fn rounded(s: Real) -> Real {\n    return s * Real(params.one);\n}\n\
                 fn mul(a: Real, b: Real) -> Real {\n    return a * b + Real(params.negative_zero);\n}\n"
            }
            (Arithmetic::Fused, _) => {
                "fn rounded(s: Real) -> Real {\n    return s;\n}\n\
                 fn mul(a: Real, b: Real) -> Real {\n    return a * b;\n}\n"
            }
        });
        src.push_str(match precision {
            Precision::F32 => {
                "fn finite(v: Real) -> bool {\n    return (bitcast<u32>(v) & 0x7f800000u) != 0x7f800000u;\n}\n"
            }
            Precision::F64 => "fn finite(v: Real) -> bool {\n    return abs(v) <= REAL_MAX;\n}\n",
        });
        // +inf, out of the compiler's sight (WGSL refuses it as a constant).
        src.push_str(
            "fn none() -> Real {\n    return Real(bitcast<f32>(0x7f800000u | params.zero));\n}\n",
        );
        src.push_str(&format!("const REAL_MAX: Real = {};\n", lit(max)));
        src.push_str(&format!("const D: u32 = {dim}u;\n"));
        src.push_str(&format!("const START_IN_BEST: bool = {start_in_best};\n"));
        src.push_str(&format!(
            "const START_TRIES: u32 = {}u;\n",
            hrla::START_TRIES
        ));
        src.push_str("alias Point = array<Real, D>;\n");
        src.push_str(&format!("const WORKGROUP: u32 = {WORKGROUP}u;\n"));
        src.push_str(&format!("const U_STAR_AT: u32 = {}u;\n", layout.u_star));
        src.push_str(&format!("const FLOOR: Real = {};\n", lit(-max.sqrt())));
        src.push_str(&format!(
            "const RASTRIGIN_TAU: Real = {};\n",
            lit(core::f64::consts::TAU)
        ));
        src.push_str(&format!(
            "const RASTRIGIN_PI: Real = {};\n",
            lit(core::f64::consts::PI)
        ));
        let terms = match precision {
            Precision::F32 => 4,
            Precision::F64 => 6,
        };
        for (i, (&s, &c)) in SIN.iter().zip(&COS).take(terms).enumerate() {
            let (s, c) = (f64::from_bits(s), f64::from_bits(c));
            src.push_str(&format!("const RASTRIGIN_S{i}: Real = {};\n", lit(s)));
            src.push_str(&format!("const RASTRIGIN_C{i}: Real = {};\n", lit(c)));
        }
        src.push_str(include_str!("wgsl/random.wgsl"));
        match precision {
            Precision::F32 => {
                // The polynomial path's limit, 2^20 in f32 (the kernel's `fast_limit`).
                src.push_str(&format!(
                    "const RASTRIGIN_FAST_LIMIT: Real = {};\n",
                    lit(1048576.0)
                ));
                src.push_str(&format!("const ZIG_R: Real = {};\n", lit(f64::from(z.r))));
                for (name, value) in FDLIBM {
                    src.push_str(&format!("const {name}: f32 = {};\n", f32_literal(value)));
                }
                src.push_str(&compiler.normals(include_str!("wgsl/normal32.wgsl")));
            }
            Precision::F64 => {
                src.push_str(&format!(
                    "const RASTRIGIN_FAST_LIMIT: Real = {};\n",
                    lit((1u64 << 49) as f64)
                ));
                src.push_str(&format!("const ZIG_R: Real = {};\n", lit(z.r64)));
                for (name, bits) in FDLIBM64 {
                    src.push_str(&format!(
                        "const {name}: Real = {};\n",
                        lit(f64::from_bits(bits))
                    ));
                }
                src.push_str(&compiler.normals(include_str!("wgsl/normal64.wgsl")));
            }
        }
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
    #[allow(clippy::excessive_precision, clippy::approx_constant)]
    fn fdlibm64_bits_are_the_libm_crates_decimals() {
        // The decimals of the libm crate's exp.rs and log.rs.
        let decimals = [
            6.93147180369123816490e-01,
            1.90821492927058770002e-10,
            1.44269504088896338700e+00,
            1.66666666666666019037e-01,
            -2.77777777770155933842e-03,
            6.61375632143793436117e-05,
            -1.65339022054652515390e-06,
            4.13813679705723846039e-08,
            6.93147180369123816490e-01,
            1.90821492927058770002e-10,
            6.666666666666735130e-01,
            3.999999999940941908e-01,
            2.857142874366239149e-01,
            2.222219843214978396e-01,
            1.818357216161805012e-01,
            1.531383769920937332e-01,
            1.479819860511658591e-01,
        ];
        for ((name, bits), d) in FDLIBM64.iter().zip(decimals) {
            assert_eq!(*bits, f64::to_bits(d), "{name}");
        }
        assert_eq!(f64::from_bits(FDLIBM64[21].1), 2f64.powi(-51));
        assert_eq!(f64::from_bits(FDLIBM64[22].1), 2f64.powi(-53));
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

    /// The programs for naga and for Tint differ by the `return` after the
    /// Ziggurat's slow path, in each precision, and nothing else.
    #[test]
    fn tint_programs_lack_only_the_unreachable_return() {
        let start = Start::paper(3);
        for precision in [Precision::F32, Precision::F64] {
            let program = Program::new(&DevicePotential::Rastrigin, &start)
                .unwrap()
                .precision(precision);
            let naga = program.clone().compiler(Compiler::Naga).wgsl();
            let tint = program.compiler(Compiler::Tint).wgsl();
            assert_eq!(naga.matches(SLOW_PATH_END).count(), 1, "{precision:?}");
            assert_eq!(tint.matches(SLOW_PATH_END).count(), 0, "{precision:?}");
            assert_eq!(naga.replacen(SLOW_PATH_END, "    }\n}\n", 1), tint);
        }
    }

    #[test]
    fn programs_of_mismatched_pieces_are_refused() {
        let quadratic = DevicePotential::quadratic(1.0, vec![0.0; 2]).unwrap();
        assert!(matches!(
            Program::new(&quadratic, &Start::paper(3)),
            Err(GpuError::Dimension {
                expected: 3,
                got: 2,
                ..
            })
        ));
        assert!(matches!(
            Program::new(&DevicePotential::Rastrigin, &Start::paper(0)),
            Err(GpuError::Kernel(hrla::Error::Zero { .. }))
        ));
        assert!(Program::new(&quadratic, &Start::paper(2)).is_ok());
    }
}

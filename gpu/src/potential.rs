//! Potentials on the device: the kernel's built-in ones, ported to WGSL,
//! and a user's WGSL function.

use crate::error::GpuError;
use crate::precision::Precision;

/// A potential that runs on the device.
///
/// The built-ins compute what the kernel's types of the same name compute.
/// [`Rastrigin`](DevicePotential::Rastrigin), [`Quadratic`](DevicePotential::quadratic),
/// [`DoubleWell`](DevicePotential::DoubleWell) and
/// [`StyblinskiTang`](DevicePotential::StyblinskiTang) use additions and
/// multiplications only, in the kernel's order, so where the device rounds
/// each operation as IEEE 754 does (no fused multiply-add) they give the
/// kernel's bits, in `f32` and `f64`; [`Ackley`](DevicePotential::Ackley) and
/// [`Levy`](DevicePotential::Levy) use the device's `sin`, `cos` and `exp`,
/// which are accurate to a few ulps, not to the kernel's bits.
///
/// A user's potential is WGSL source ([`DevicePotential::wgsl`]) defining
///
/// ```text
/// fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real
/// ```
///
/// which writes `∇U(x)` into `grad` and returns `U(x)`; `Real` (`f32`, or
/// `f64` with [`Precision::F64`](crate::Precision)),
/// `D` (the dimension, a `u32`) and `Point` (`array<Real, D>`) are
/// declared by the backend, and so are `mul(a, b)` and `rounded(s)`, which
/// keep a product or a sum rounded as written when the ensemble's
/// [`Arithmetic`](crate::Arithmetic) is IEEE (the built-ins use them where
/// an addition takes a product). The source may declare its own helper
/// functions and constants; the backend's other names (constants in upper
/// case, `rng`, `next_u32`, `normal`, `normal_pair`, `finite`, `coef`,
/// `params`, `tables`, the entry points `init`, `step`, `argmin`,
/// `groups`, `census`, `normals`) are taken, and a clash is a compile
/// error like any other.
///
/// ```
/// use hrla_gpu::DevicePotential;
///
/// // Himmelblau's function (D = 2).
/// let himmelblau = DevicePotential::wgsl("
///     fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
///         let p = (*x)[0] * (*x)[0] + (*x)[1] - 11.0;
///         let q = (*x)[0] + (*x)[1] * (*x)[1] - 7.0;
///         (*grad)[0] = 4.0 * (*x)[0] * p + 2.0 * q;
///         (*grad)[1] = 2.0 * p + 4.0 * (*x)[1] * q;
///         return p * p + q * q;
///     }
/// ");
/// # let _ = himmelblau;
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum DevicePotential {
    /// Rastrigin in the paper's form ([`hrla::Rastrigin`]).
    Rastrigin,
    /// `U(x) = (k/2) |x - m|^2` ([`hrla::Quadratic`]); build it with
    /// [`DevicePotential::quadratic`].
    Quadratic {
        /// `k > 0`.
        stiffness: f64,
        /// `m`, one entry per coordinate.
        centre: Vec<f64>,
    },
    /// The separable double well ([`hrla::DoubleWell`]).
    DoubleWell,
    /// Styblinski–Tang ([`hrla::StyblinskiTang`]).
    StyblinskiTang,
    /// Ackley ([`hrla::Ackley`]).
    Ackley,
    /// Levy ([`hrla::Levy`]).
    Levy,
    /// A user's WGSL `value_and_gradient`; build it with
    /// [`DevicePotential::wgsl`].
    Wgsl(String),
}

/// What the program is made of: a built-in file with its constants, or a
/// user's text.
pub(crate) enum PotentialSource<'a> {
    Builtin(&'static str, Vec<(&'static str, f64)>),
    Wgsl(&'a str),
}

impl DevicePotential {
    /// The quadratic of stiffness `k` (finite, > 0) about `centre`
    /// (finite): its Gibbs law is `N(m, I / (a k))`.
    pub fn quadratic(stiffness: f64, centre: Vec<f64>) -> Result<Self, GpuError> {
        if !(stiffness.is_finite() && stiffness > 0.0 && (stiffness as f32) > 0.0) {
            return Err(hrla::Error::NotPositive {
                name: "stiffness",
                value: stiffness,
            }
            .into());
        }
        if let Some(&m) = centre
            .iter()
            .find(|m| !(m.is_finite() && (**m as f32).is_finite()))
        {
            return Err(hrla::Error::NotFinite {
                name: "centre",
                value: m,
            }
            .into());
        }
        Ok(Self::Quadratic { stiffness, centre })
    }

    /// A user's potential: WGSL source defining `value_and_gradient` (see
    /// the type's docs). It is compiled when an ensemble is built, which
    /// returns [`GpuError::Shader`] with the compiler's message if it
    /// does not compile.
    pub fn wgsl(source: impl Into<String>) -> Self {
        Self::Wgsl(source.into())
    }

    /// The dimension the potential fixes, if any (the quadratic's centre).
    pub(crate) fn dimension(&self) -> Option<usize> {
        match self {
            Self::Quadratic { centre, .. } => Some(centre.len()),
            _ => None,
        }
    }

    pub(crate) fn centre(&self) -> Option<&[f64]> {
        match self {
            Self::Quadratic { centre, .. } => Some(centre),
            _ => None,
        }
    }

    /// Whether the device can evaluate it in `precision`: Ackley and
    /// Levy need `sin`, `cos` and `exp`, which Vulkan has in f32 only.
    #[cfg_attr(not(feature = "device"), allow(dead_code))]
    pub(crate) fn supports(&self, precision: Precision) -> bool {
        precision == Precision::F32 || !matches!(self, Self::Ackley | Self::Levy)
    }

    pub(crate) fn source(&self, precision: Precision) -> PotentialSource<'_> {
        use core::f64::consts::{E, PI};
        let builtin = PotentialSource::Builtin;
        match self {
            Self::Rastrigin => builtin(
                match precision {
                    Precision::F32 => include_str!("wgsl/potential/rastrigin.wgsl"),
                    Precision::F64 => include_str!("wgsl/potential/rastrigin64.wgsl"),
                },
                vec![],
            ),
            Self::Quadratic { stiffness, .. } => builtin(
                include_str!("wgsl/potential/quadratic.wgsl"),
                vec![("QUADRATIC_STIFFNESS", *stiffness)],
            ),
            Self::DoubleWell => builtin(include_str!("wgsl/potential/double_well.wgsl"), vec![]),
            Self::StyblinskiTang => {
                builtin(include_str!("wgsl/potential/styblinski_tang.wgsl"), vec![])
            }
            Self::Ackley => builtin(
                include_str!("wgsl/potential/ackley.wgsl"),
                vec![("ACKLEY_PI", PI), ("ACKLEY_E", E)],
            ),
            Self::Levy => builtin(
                include_str!("wgsl/potential/levy.wgsl"),
                vec![("LEVY_PI", PI)],
            ),
            Self::Wgsl(text) => PotentialSource::Wgsl(text),
        }
    }
}

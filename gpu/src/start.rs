//! Initial points of the chains on the device.

use crate::error::GpuError;

/// Where the chains start (the velocity starts at 0), drawn on the device
/// from each chain's own generator as the kernel's starts draw them.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Start {
    /// Independent `x_0 ~ N(m, s^2 I)`, coordinates in order, one normal
    /// each ([`hrla::Gaussian`]); the paper's is `N(3·1, 10 I)`.
    Gaussian {
        /// `m`, one entry per coordinate.
        mean: Vec<f64>,
        /// `s >= 0`.
        std_dev: f64,
    },
    /// Every chain at the same point, no draws ([`hrla::Point`]).
    Point(Vec<f64>),
}

impl Start {
    /// `N(m, s^2 I)`: `m` finite, `s` finite and >= 0 (in f32 too).
    pub fn gaussian(mean: Vec<f64>, std_dev: f64) -> Result<Self, GpuError> {
        finite_point("mean", &mean)?;
        if !(std_dev.is_finite() && std_dev >= 0.0 && (std_dev as f32).is_finite()) {
            return Err(hrla::Error::Negative {
                name: "std_dev",
                value: std_dev,
            }
            .into());
        }
        Ok(Self::Gaussian { mean, std_dev })
    }

    /// The paper's start in `dim` dimensions, `N(3·1, 10 I)`.
    pub fn paper(dim: usize) -> Self {
        Self::Gaussian {
            mean: vec![3.0; dim],
            std_dev: 10f64.sqrt(),
        }
    }

    /// Every chain at `x` (finite, in f32 too).
    pub fn point(x: Vec<f64>) -> Result<Self, GpuError> {
        finite_point("initial point", &x)?;
        Ok(Self::Point(x))
    }

    pub(crate) fn dimension(&self) -> usize {
        match self {
            Self::Gaussian { mean, .. } => mean.len(),
            Self::Point(x) => x.len(),
        }
    }

    /// The mean (or point) and the standard deviation (0 for a point), in
    /// the order of the constants buffer.
    #[cfg_attr(not(feature = "device"), allow(dead_code))]
    pub(crate) fn constants(&self) -> Vec<f64> {
        let (m, s) = match self {
            Self::Gaussian { mean, std_dev } => (mean, *std_dev),
            Self::Point(x) => (x, 0.0),
        };
        m.iter().copied().chain([s]).collect()
    }
}

fn finite_point(name: &'static str, x: &[f64]) -> Result<(), GpuError> {
    match x
        .iter()
        .find(|v| !(v.is_finite() && (**v as f32).is_finite()))
    {
        Some(&v) => Err(hrla::Error::NotFinite { name, value: v }.into()),
        None => Ok(()),
    }
}

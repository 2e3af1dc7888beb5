//! A kernel's step as the device runs it: its coefficients, taken from the
//! kernel's own sampler types through their public moments, in the
//! kernel's float type, then rounded once to the device's.

use hrla::{AnyKernel, Float, Kernel, OlaKernel, OuKernel};

/// Which kind of step a sampler takes, and so which the program runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum StepKind {
    /// The exact Ornstein–Uhlenbeck step of HRLA and ULA.
    Ou,
    /// OLA's Euler–Maruyama step.
    Ola,
}

/// The coefficients of one step at one inverse temperature, as computed by
/// the kernel (exactly its bits, widened to f64).
///
/// The OU step of HRLA and ULA moves each coordinate by
///
/// ```text
/// y' = e y - c_yg g + l_yy z1
/// x' = x + c_xy y - c_xg g + l_xy z1 + l_xx z2
/// ```
///
/// (the kernel's `OuKernel`, in its order of operations), OLA's by
/// `x' = x - drift g + noise z`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum StepCoefficients {
    /// HRLA's and ULA's exact Ornstein–Uhlenbeck step.
    Ou {
        /// Weight of the velocity in the position's mean, `h phi1(alpha h)`.
        c_xy: f64,
        /// `exp(-alpha h)`.
        e: f64,
        /// Weight of the gradient in the position's mean.
        c_xg: f64,
        /// Weight of the gradient in the velocity's mean.
        c_yg: f64,
        /// The noise's Cholesky factor ([`hrla::NoiseFactor`]).
        l_xy: f64,
        /// See [`hrla::NoiseFactor`].
        l_xx: f64,
        /// See [`hrla::NoiseFactor`].
        l_yy: f64,
    },
    /// OLA's Euler–Maruyama step.
    Ola {
        /// `alpha h`.
        drift: f64,
        /// `sqrt(2 alpha h / a)`.
        noise: f64,
    },
}

impl StepCoefficients {
    /// The kind of step these are the coefficients of.
    pub fn kind(&self) -> StepKind {
        match self {
            Self::Ou { .. } => StepKind::Ou,
            Self::Ola { .. } => StepKind::Ola,
        }
    }

    /// The eight floats of one step in the constants buffer: HRLA's and
    /// ULA's `[c_xy, e, c_xg, c_yg, l_xy, l_xx, l_yy, 0]`, OLA's `[drift,
    /// noise, 0, 0, 0, 0, 0, 0]`.
    pub fn to_device(self) -> [f64; 8] {
        match self {
            Self::Ou {
                c_xy,
                e,
                c_xg,
                c_yg,
                l_xy,
                l_xx,
                l_yy,
            } => [c_xy, e, c_xg, c_yg, l_xy, l_xx, l_yy, 0.0],
            Self::Ola { drift, noise } => [drift, noise, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        }
    }
}

/// A kernel whose step the device can run: the kernel's [`OuKernel`]
/// (HRLA, ULA), [`OlaKernel`] (OLA) and [`AnyKernel`], in `f32` or `f64`.
///
/// On an `f32` device ([`Precision::F32`](crate::Precision)): with an
/// `f64` kernel, the coefficients are the kernel's f64 ones rounded once
/// to f32, the most accurate f32 values; with an
/// `f32` kernel they are exactly the CPU's `f32` optimiser's, which differ
/// from the former by up to 2 units in the last place (the paper's
/// settings, `h` from 0.001 to 0.1, `a` from 0.1 to 40): the choice of the
/// kernel's float type is the choice between the most accurate step and
/// the CPU's `f32` bits. On an `f64` device, an `f64` kernel's are exact.
pub trait DeviceKernel {
    /// The step's coefficients.
    fn coefficients(&self) -> StepCoefficients;
}

impl<F: Float> DeviceKernel for OuKernel<F> {
    fn coefficients(&self) -> StepCoefficients {
        // The means are affine in (x, y, g) with exact zeros and ones, so
        // these evaluations return the coefficients themselves, bit for bit.
        let (zero, one) = (F::ZERO, F::ONE);
        let velocity = self.moments(zero, one, zero);
        let gradient = self.moments(zero, zero, one);
        let noise = self.noise_factor();
        StepCoefficients::Ou {
            c_xy: velocity.mean_x.to_f64(),
            e: velocity.mean_y.to_f64(),
            c_xg: -gradient.mean_x.to_f64(),
            c_yg: -gradient.mean_y.to_f64(),
            l_xy: noise.xy.to_f64(),
            l_xx: noise.xx.to_f64(),
            l_yy: noise.yy.to_f64(),
        }
    }
}

impl<F: Float> DeviceKernel for OlaKernel<F> {
    fn coefficients(&self) -> StepCoefficients {
        let m = self.moments(F::ZERO, F::ZERO, F::ONE);
        // The variance is the square of the noise's scale, and a square
        // root of a rounded square gives the number back (binary floating
        // point, no underflow or overflow): the kernel's own scale.
        StepCoefficients::Ola {
            drift: -m.mean_x.to_f64(),
            noise: m.var_x.sqrt().to_f64(),
        }
    }
}

impl<F: Float> DeviceKernel for AnyKernel<F> {
    fn coefficients(&self) -> StepCoefficients {
        match self {
            AnyKernel::Hrla(k) | AnyKernel::Ula(k) => k.coefficients(),
            AnyKernel::Ola(k) => k.coefficients(),
        }
    }
}

#[cfg(test)]
mod tests {
    /// `sqrt(v * v) == v` in both float types, the fact that the OLA
    /// coefficients rest on, over scales from 1e-30 to 1e30.
    #[test]
    fn square_roots_of_squares_give_the_number_back() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..1_000_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let unit = (state >> 11) as f64 / (1u64 << 53) as f64;
            let v = 10f64.powf(unit * 60.0 - 30.0);
            assert_eq!((v * v).sqrt(), v);
            let w = v as f32;
            if (1e-18..1e18).contains(&w) {
                assert_eq!((w * w).sqrt(), w);
            }
        }
    }
}

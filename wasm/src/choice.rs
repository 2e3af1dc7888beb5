//! Run-time choices of sampler and schedule, by delegation to the kernel's
//! types: the kernel's `Optimizer` is generic over both, and the page picks
//! them at run time.

use hrla::rand_core::Rng;
use hrla::{
    Constant, Error, Hrla, HrlaParams, Linear, Ola, OlaParams, Sampler, Schedule, Ula, UlaParams,
};

use crate::settings::{SamplerKind, Temperature};

/// One of the kernel's three samplers, in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnySampler {
    /// [`Hrla`].
    Hrla(Hrla<f64>),
    /// [`Ula`].
    Ula(Ula<f64>),
    /// [`Ola`].
    Ola(Ola<f64>),
}

impl AnySampler {
    /// The sampler `kind` with the paper's parameters at inverse
    /// temperature `a` and step `h`.
    pub fn new(kind: SamplerKind, a: f64, h: f64) -> Result<Self, Error> {
        Ok(match kind {
            SamplerKind::Hrla => Self::Hrla(Hrla::new(HrlaParams::paper(a, h))?),
            SamplerKind::Ula => Self::Ula(Ula::new(UlaParams::paper(a, h))?),
            SamplerKind::Ola => Self::Ola(Ola::new(OlaParams::paper(a, h))?),
        })
    }
}

impl Sampler<f64> for AnySampler {
    fn inverse_temperature(&self) -> f64 {
        match self {
            Self::Hrla(s) => s.inverse_temperature(),
            Self::Ula(s) => s.inverse_temperature(),
            Self::Ola(s) => s.inverse_temperature(),
        }
    }

    fn set_inverse_temperature(&mut self, a: f64) -> Result<(), Error> {
        match self {
            Self::Hrla(s) => s.set_inverse_temperature(a),
            Self::Ula(s) => s.set_inverse_temperature(a),
            Self::Ola(s) => s.set_inverse_temperature(a),
        }
    }

    #[inline]
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [f64; D],
        y: &mut [f64; D],
        grad: &[f64; D],
        rng: &mut R,
    ) {
        match self {
            Self::Hrla(s) => s.step(x, y, grad, rng),
            Self::Ula(s) => s.step(x, y, grad, rng),
            Self::Ola(s) => s.step(x, y, grad, rng),
        }
    }
}

/// A constant or linearly annealed inverse temperature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnySchedule {
    /// [`Constant`].
    Constant(Constant<f64>),
    /// [`Linear`].
    Linear(Linear<f64>),
}

impl AnySchedule {
    /// Validates the schedule's parameters through the kernel.
    pub fn new(temperature: Temperature) -> Result<Self, Error> {
        Ok(match temperature {
            Temperature::Constant(a) => Self::Constant(Constant::new(a)?),
            Temperature::Linear {
                a_low,
                a_high,
                steps,
            } => Self::Linear(Linear::new(a_low, a_high, steps)?),
        })
    }
}

impl Schedule<f64> for AnySchedule {
    #[inline]
    fn inverse_temperature(&self, k: u64) -> f64 {
        match self {
            Self::Constant(s) => s.inverse_temperature(k),
            Self::Linear(s) => s.inverse_temperature(k),
        }
    }
}

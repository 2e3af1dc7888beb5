//! Samplers: one Markov step of a chain, given the gradient at its position.
//!
//! [`Hrla`] (the paper's method), [`Ula`] and [`Ola`] (its two baselines)
//! implement [`Sampler`], so [`Optimizer`](crate::Optimizer) takes any of them
//! and users can add their own.

use rand_core::Rng;

use crate::error::{Error, positive};
use crate::float::Float;
use crate::ou::{NoiseFactor, OuStep, StepMoments};

/// One step of a Langevin-type chain at inverse temperature `a`.
///
/// The chain's state is a position `x` and a velocity `y` (samplers without
/// a velocity leave `y` alone). The gradient of the potential at `x` is
/// passed in, so a step costs no potential evaluation of its own: the caller
/// evaluates the potential once, after the step, for both the running best
/// and the next step's gradient.
pub trait Sampler<F: Float> {
    /// The current inverse temperature `a`.
    fn inverse_temperature(&self) -> F;

    /// Moves to inverse temperature `a`, refreshing the coefficients that
    /// depend on it. Called by the optimiser whenever the schedule changes
    /// `a`, so it should be cheap. On error the sampler is unchanged.
    fn set_inverse_temperature(&mut self, a: F) -> Result<(), Error>;

    /// Advances `(x, y)` by one step, given `grad = ∇U(x)`.
    ///
    /// Must not fail: every check belongs in the constructor and in
    /// [`Sampler::set_inverse_temperature`].
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [F; D],
        y: &mut [F; D],
        grad: &[F; D],
        rng: &mut R,
    );
}

/// Parameters of [`Hrla`]: inverse temperatures `a` (of the position) and `b`
/// (of the velocity), friction `alpha`, gradient weight `beta` and step `h`.
///
/// The remaining coefficients of the dynamics are derived so that
/// `mu^{a,b}(x, y) ∝ exp(-a U(x) - b |y|^2 / 2)` is invariant by
/// construction: `gamma = a / b`, `sx2 = beta / a`, `sy2 = alpha / b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HrlaParams<F> {
    /// Inverse temperature of the position, `a > 0`.
    pub a: F,
    /// Inverse temperature of the velocity, `b > 0`.
    pub b: F,
    /// Friction `alpha > 0`.
    pub alpha: F,
    /// Weight of the gradient in the position equation, `beta > 0`.
    pub beta: F,
    /// Step size `h > 0`.
    pub h: F,
}

impl<F: Float> HrlaParams<F> {
    /// The paper's experimental setting (`alpha = beta = 1`, `b = 10`) at
    /// inverse temperature `a` and step `h`.
    pub fn paper(a: F, h: F) -> Self {
        Self {
            a,
            b: F::from_f64(10.0),
            alpha: F::ONE,
            beta: F::ONE,
            h,
        }
    }
}

/// High-resolution Langevin: the exact Gaussian step of
///
/// ```text
/// dX = (-beta ∇U(X) + Y) dt + sqrt(2 sx2) dB^x
/// dY = (-gamma ∇U(X) - alpha Y) dt + sqrt(2 sy2) dB^y
/// ```
///
/// with the gradient frozen over each step (the module docs of the crate give
/// the mean and covariance). Two standard normals per coordinate.
///
/// # Example
///
/// ```
/// use hrla::{Hrla, HrlaParams};
///
/// let hrla = Hrla::new(HrlaParams::paper(4.0_f64, 0.01))?;
/// let m = hrla.moments(1.0, 0.0, 0.5);
/// assert!(m.mean_x < 1.0 && m.var_x > 0.0);
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hrla<F> {
    params: HrlaParams<F>,
    ou: OuStep<F>,
}

impl<F: Float> Hrla<F> {
    /// Validates the parameters (each finite and > 0) and precomputes the
    /// step's coefficients.
    pub fn new(params: HrlaParams<F>) -> Result<Self, Error> {
        let beta = positive("beta", params.beta)?;
        let ou = OuStep::new(params.a, params.b, params.alpha, beta, params.h)?;
        Ok(Self { params, ou })
    }

    /// The parameters, with `a` the current inverse temperature.
    pub fn params(&self) -> HrlaParams<F> {
        self.params
    }

    /// `gamma = a / b` at the current temperature.
    pub fn gamma(&self) -> F {
        self.params.a / self.params.b
    }

    /// `sx2 = beta / a` at the current temperature.
    pub fn sx2(&self) -> F {
        self.params.beta / self.params.a
    }

    /// `sy2 = alpha / b`.
    pub fn sy2(&self) -> F {
        self.params.alpha / self.params.b
    }

    /// The conditional mean and covariance of one step of one coordinate
    /// from position `x`, velocity `y` and gradient component `g`.
    pub fn moments(&self, x: F, y: F, g: F) -> StepMoments<F> {
        self.ou.moments(x, y, g)
    }

    /// The factor that turns two standard normals into the step's noise.
    pub fn noise_factor(&self) -> NoiseFactor<F> {
        self.ou.noise_factor()
    }
}

impl<F: Float> Sampler<F> for Hrla<F> {
    fn inverse_temperature(&self) -> F {
        self.params.a
    }

    fn set_inverse_temperature(&mut self, a: F) -> Result<(), Error> {
        self.ou.set_a(a)?;
        self.params.a = a;
        Ok(())
    }

    #[inline]
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [F; D],
        y: &mut [F; D],
        grad: &[F; D],
        rng: &mut R,
    ) {
        ou_step(&self.ou, x, y, grad, rng);
    }
}

/// Draws in the documented order: per coordinate, the pair `(z1, z2)` of
/// [`Float::standard_normal_pair`].
#[inline(always)]
fn ou_step<F: Float, R: Rng + ?Sized, const D: usize>(
    ou: &OuStep<F>,
    x: &mut [F; D],
    y: &mut [F; D],
    grad: &[F; D],
    rng: &mut R,
) {
    // All the draws first, then the update: the update's loop then has no
    // branch and vectorises across coordinates (same stream either way).
    let mut z = [(F::ZERO, F::ZERO); D];
    for zi in &mut z {
        *zi = F::standard_normal_pair(rng);
    }
    for (((xi, yi), &gi), &(z1, z2)) in x.iter_mut().zip(y.iter_mut()).zip(grad).zip(&z) {
        ou.apply(xi, yi, gi, z1, z2);
    }
}

/// Parameters of [`Ula`]: `a`, `b`, `alpha`, `h` as for [`HrlaParams`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UlaParams<F> {
    /// Inverse temperature of the position, `a > 0`.
    pub a: F,
    /// Inverse temperature of the velocity, `b > 0`.
    pub b: F,
    /// Friction `alpha > 0`.
    pub alpha: F,
    /// Step size `h > 0`.
    pub h: F,
}

impl<F: Float> UlaParams<F> {
    /// The paper's setting (`alpha = 1`, `b = 10`) at `a` and `h`.
    pub fn paper(a: F, h: F) -> Self {
        Self {
            a,
            b: F::from_f64(10.0),
            alpha: F::ONE,
            h,
        }
    }
}

/// Underdamped Langevin with the exact OU step and frozen gradient:
/// `dX = Y dt`, `dY = (-gamma ∇U - alpha Y) dt + sqrt(2 sy2) dB`, which is
/// HRLA with `beta = 0` and `sx2 = 0`. Two standard normals per coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ula<F> {
    params: UlaParams<F>,
    ou: OuStep<F>,
}

impl<F: Float> Ula<F> {
    /// Validates the parameters (each finite and > 0) and precomputes the
    /// step's coefficients.
    pub fn new(params: UlaParams<F>) -> Result<Self, Error> {
        let ou = OuStep::new(params.a, params.b, params.alpha, F::ZERO, params.h)?;
        Ok(Self { params, ou })
    }

    /// The parameters, with `a` the current inverse temperature.
    pub fn params(&self) -> UlaParams<F> {
        self.params
    }

    /// The conditional mean and covariance of one step of one coordinate.
    pub fn moments(&self, x: F, y: F, g: F) -> StepMoments<F> {
        self.ou.moments(x, y, g)
    }

    /// The factor that turns two standard normals into the step's noise.
    pub fn noise_factor(&self) -> NoiseFactor<F> {
        self.ou.noise_factor()
    }
}

impl<F: Float> Sampler<F> for Ula<F> {
    fn inverse_temperature(&self) -> F {
        self.params.a
    }

    fn set_inverse_temperature(&mut self, a: F) -> Result<(), Error> {
        self.ou.set_a(a)?;
        self.params.a = a;
        Ok(())
    }

    #[inline]
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [F; D],
        y: &mut [F; D],
        grad: &[F; D],
        rng: &mut R,
    ) {
        ou_step(&self.ou, x, y, grad, rng);
    }
}

/// Parameters of [`Ola`]: inverse temperature `a`, rate `alpha`, step `h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OlaParams<F> {
    /// Inverse temperature, `a > 0`.
    pub a: F,
    /// Rate `alpha > 0` (the paper's code uses 1).
    pub alpha: F,
    /// Step size `h > 0`.
    pub h: F,
}

impl<F: Float> OlaParams<F> {
    /// The paper's setting (`alpha = 1`) at `a` and `h`.
    pub fn paper(a: F, h: F) -> Self {
        Self {
            a,
            alpha: F::ONE,
            h,
        }
    }
}

/// Overdamped Langevin, Euler–Maruyama:
/// `x' = x - alpha h ∇U(x) + sqrt(2 alpha h / a) xi`, `xi ~ N(0, I)`.
/// One standard normal per coordinate; the velocity is not used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ola<F> {
    params: OlaParams<F>,
    drift: F,
    noise: F,
}

impl<F: Float> Ola<F> {
    /// Validates the parameters (each finite and > 0).
    pub fn new(params: OlaParams<F>) -> Result<Self, Error> {
        positive("a", params.a)?;
        let alpha = positive("alpha", params.alpha)?;
        let h = positive("h", params.h)?;
        let drift = alpha * h;
        if !drift.is_finite() {
            return Err(Error::DegenerateCoefficients);
        }
        let mut ola = Self {
            params,
            drift,
            noise: F::ZERO,
        };
        ola.set_inverse_temperature(params.a)?;
        Ok(ola)
    }

    /// The parameters, with `a` the current inverse temperature.
    pub fn params(&self) -> OlaParams<F> {
        self.params
    }

    /// The conditional mean and covariance of one step of one coordinate
    /// (`y` is carried unchanged).
    pub fn moments(&self, x: F, y: F, g: F) -> StepMoments<F> {
        StepMoments {
            mean_x: x - self.drift * g,
            mean_y: y,
            var_x: self.noise * self.noise,
            cov_xy: F::ZERO,
            var_y: F::ZERO,
        }
    }
}

impl<F: Float> Sampler<F> for Ola<F> {
    fn inverse_temperature(&self) -> F {
        self.params.a
    }

    fn set_inverse_temperature(&mut self, a: F) -> Result<(), Error> {
        let a = positive("a", a)?;
        let noise = (F::TWO * self.drift / a).sqrt();
        if !noise.is_finite() {
            return Err(Error::DegenerateCoefficients);
        }
        self.params.a = a;
        self.noise = noise;
        Ok(())
    }

    #[inline]
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [F; D],
        _y: &mut [F; D],
        grad: &[F; D],
        rng: &mut R,
    ) {
        for (xi, &gi) in x.iter_mut().zip(grad) {
            let z = F::standard_normal(rng);
            *xi = *xi - self.drift * gi + self.noise * z;
        }
    }
}

/// The built-in samplers, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SamplerKind {
    /// [`Hrla`], the paper's method.
    Hrla,
    /// [`Ula`].
    Ula,
    /// [`Ola`].
    Ola,
}

impl SamplerKind {
    /// All three, in the paper's order of presentation.
    pub const ALL: [SamplerKind; 3] = [SamplerKind::Hrla, SamplerKind::Ula, SamplerKind::Ola];

    /// Lower-case name: `"hrla"`, `"ula"` or `"ola"`.
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Hrla => "hrla",
            SamplerKind::Ula => "ula",
            SamplerKind::Ola => "ola",
        }
    }
}

/// One of the built-in samplers, chosen at run time: for a user interface, a
/// command line, or one optimiser type that serves all three. The match per
/// step is perfectly predicted and costs nothing measurable next to the
/// normals of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnySampler<F> {
    /// HRLA.
    Hrla(Hrla<F>),
    /// ULA.
    Ula(Ula<F>),
    /// OLA.
    Ola(Ola<F>),
}

impl<F: Float> AnySampler<F> {
    /// `kind` in the paper's setting (`alpha = beta = 1`, `b = 10`) at
    /// inverse temperature `a` and step `h`.
    pub fn paper(kind: SamplerKind, a: F, h: F) -> Result<Self, Error> {
        Ok(match kind {
            SamplerKind::Hrla => Self::Hrla(Hrla::new(HrlaParams::paper(a, h))?),
            SamplerKind::Ula => Self::Ula(Ula::new(UlaParams::paper(a, h))?),
            SamplerKind::Ola => Self::Ola(Ola::new(OlaParams::paper(a, h))?),
        })
    }

    /// Which sampler this is.
    pub fn kind(&self) -> SamplerKind {
        match self {
            Self::Hrla(_) => SamplerKind::Hrla,
            Self::Ula(_) => SamplerKind::Ula,
            Self::Ola(_) => SamplerKind::Ola,
        }
    }

    /// The conditional mean and covariance of one step of one coordinate.
    pub fn moments(&self, x: F, y: F, g: F) -> StepMoments<F> {
        match self {
            Self::Hrla(s) => s.moments(x, y, g),
            Self::Ula(s) => s.moments(x, y, g),
            Self::Ola(s) => s.moments(x, y, g),
        }
    }
}

impl<F: Float> Sampler<F> for AnySampler<F> {
    fn inverse_temperature(&self) -> F {
        match self {
            Self::Hrla(s) => s.inverse_temperature(),
            Self::Ula(s) => s.inverse_temperature(),
            Self::Ola(s) => s.inverse_temperature(),
        }
    }

    fn set_inverse_temperature(&mut self, a: F) -> Result<(), Error> {
        match self {
            Self::Hrla(s) => s.set_inverse_temperature(a),
            Self::Ula(s) => s.set_inverse_temperature(a),
            Self::Ola(s) => s.set_inverse_temperature(a),
        }
    }

    #[inline]
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [F; D],
        y: &mut [F; D],
        grad: &[F; D],
        rng: &mut R,
    ) {
        match self {
            Self::Hrla(s) => s.step(x, y, grad, rng),
            Self::Ula(s) => s.step(x, y, grad, rng),
            Self::Ola(s) => s.step(x, y, grad, rng),
        }
    }
}

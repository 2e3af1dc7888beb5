//! The exact Ornstein–Uhlenbeck step shared by HRLA and ULA: [`OuKernel`].
//!
//! With the gradient frozen at `g` over a step of length `h`, each coordinate
//! of `(x, y)` solves a linear SDE whose law after `h` is Gaussian. Writing
//! `u = alpha h` and
//!
//! ```text
//! phi1(u)  = (1 - e^-u) / u
//! phi2(u)  = (e^-u - 1 + u) / u^2
//! omega(u) = (u - 2 tanh(u/2)) / u^3
//! ```
//!
//! the spec's formulas (`docs/SPEC.md`, section 4) become
//!
//! ```text
//! mean_x = x + h phi1(u) y - (beta h + gamma h^2 phi2(u)) g
//! mean_y = e^-u y - gamma h phi1(u) g
//! Syy    = 2 sy2 h phi1(2u)
//! Sxy    = sy2 h^2 phi1(u)^2
//! Sxx    = 2 sx2 h + 2 sy2 h^3 omega(u) + Sxy^2 / Syy
//! ```
//!
//! The sample is drawn through the Cholesky factor with `y` first:
//! `y' = mean_y + Lyy z1`, `x' = mean_x + Lxy z1 + Lxx z2`, where
//! `Lxx^2 = Sxx - Sxy^2/Syy = 2 sx2 h + 2 sy2 h^3 omega(u)` is the Schur
//! complement. The identity `(2u - e^-2u + 4e^-u - 3)(1 + e^-u) - (1 - e^-u)^3
//! = 2u(1 + e^-u) - 4(1 - e^-u)` turns it into a sum of two positive terms, so
//! it is computed without any cancellation.
//!
//! Each of `phi2` and `omega` cancels for small `u` when evaluated as written.
//! For `t = u/2 <= 2` they are rewritten as series with positive terms only:
//! with `s = t^2`, `A(s) = sum_{k>=1} 2k s^(k-1) / (2k+1)!` and
//! `S(s) = sinh(t)/t = sum_{k>=0} s^k / (2k+1)!`,
//!
//! ```text
//! phi2(u)  = e^-t (t A(s) + S(s)) / 2       (from t cosh t - sinh t = t^3 A(s))
//! omega(u) = A(s) / (4 cosh t)
//! ```
//!
//! and beyond `t = 2` the direct forms lose at most one bit. Only `phi2`,
//! `omega` and the mean coefficients involve `gamma` or `sx2`, so an annealed
//! temperature refreshes three numbers per step (two products and a square
//! root); everything depending on `u` alone is computed once.

use rand_core::Rng;

use super::traits::{ChainState, Kernel, StepMoments};
use crate::error::{ALPHA_H, Error, INVERSE_TEMPERATURE, in_range, positive};
use crate::float::Float;
use crate::lockstep::{LANES, Xoshiro256Lanes};

/// Terms of the series `A(s)` and `S(s)`: for `s <= 4` the first omitted
/// term is below 2^-60 of the sum, so both are exact to the last place of f64.
const SERIES_TERMS: usize = 14;

/// `A(s) = sum_{k>=1} 2k s^(k-1) / (2k+1)!` by Horner's rule (positive terms).
fn series_a<F: Float>(s: F) -> F {
    let mut acc = F::ZERO;
    let mut k = SERIES_TERMS;
    while k >= 1 {
        acc = acc * s + F::from_f64(2.0 * k as f64 / factorial(2 * k + 1));
        k -= 1;
    }
    acc
}

/// `S(s) = sinh(t)/t = sum_{k>=0} s^k / (2k+1)!` by Horner's rule.
fn series_sinhc<F: Float>(s: F) -> F {
    let mut acc = F::ZERO;
    let mut k = SERIES_TERMS + 1;
    while k >= 1 {
        k -= 1;
        acc = acc * s + F::from_f64(1.0 / factorial(2 * k + 1));
    }
    acc
}

/// `n!` in f64; exact up to 22! and correctly rounded enough beyond for the
/// series coefficients (their relative error is far below the terms' size).
fn factorial(n: usize) -> f64 {
    (2..=n).fold(1.0, |acc, i| acc * i as f64)
}

/// `(1 - e^-u) / u`, accurate for every `u > 0`.
pub(crate) fn phi1<F: Float>(u: F) -> F {
    -(-u).expm1() / u
}

/// `(e^-u - 1 + u) / u^2`, accurate for every `u > 0`.
pub(crate) fn phi2<F: Float>(u: F) -> F {
    let t = u * F::HALF;
    if t <= F::TWO {
        let s = t * t;
        (-t).exp() * (t * series_a(s) + series_sinhc(s)) * F::HALF
    } else {
        (F::ONE - phi1(u)) / u
    }
}

/// `(u - 2 tanh(u/2)) / u^3`, accurate for every `u > 0`.
pub(crate) fn omega<F: Float>(u: F) -> F {
    let t = u * F::HALF;
    if t <= F::TWO {
        series_a(t * t) / (F::from_f64(4.0) * t.cosh())
    } else {
        (F::ONE - t.tanh() / t) / (u * u)
    }
}

/// The lower-triangular factor through which a step turns two independent
/// standard normals `z1`, `z2` into the Gaussian noise of one coordinate:
///
/// ```text
/// y' = mean_y + yy z1
/// x' = mean_x + xy z1 + xx z2
/// ```
///
/// so `yy^2 = Syy`, `xy yy = Sxy` and `xx^2 = Sxx - Sxy^2/Syy` (the Schur
/// complement, computed without cancellation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseFactor<F> {
    /// Standard deviation of the new velocity.
    pub yy: F,
    /// Loading of the velocity's normal on the position.
    pub xy: F,
    /// Conditional standard deviation of the position given the velocity.
    pub xx: F,
}

/// The exact step of HRLA or ULA at one inverse temperature `a`: what
/// [`Hrla::at`](crate::Hrla) and [`Ula::at`](crate::Ula) return.
///
/// Every coordinate moves to the Gaussian of its [`StepMoments`], drawn as
/// `y' = mean_y + yy z1`, `x' = mean_x + xy z1 + xx z2` through the
/// [`NoiseFactor`], from the pair `(z1, z2)` of
/// [`StandardNormal::standard_normal_pair`](crate::StandardNormal::standard_normal_pair),
/// coordinate after coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OuKernel<F> {
    // Fixed by (b, alpha, beta, h).
    e: F,
    c_xy: F,
    l_yy: F,
    l_xy: F,
    schur_y: F,
    cov_xy: F,
    var_y: F,
    beta_h: F,
    two_beta_h: F,
    h2_phi2_over_b: F,
    h_phi1_over_b: F,
    // Refreshed with a.
    a: F,
    c_xg: F,
    c_yg: F,
    l_xx: F,
}

impl<F: Float> OuKernel<F> {
    /// Validates `(b, alpha, h)` (finite, > 0) and `beta` (finite, >= 0:
    /// ULA is `beta = 0`) and computes the coefficients that do not depend
    /// on `a`; [`OuKernel::at`] completes them.
    pub(crate) fn untempered(b: F, alpha: F, beta: F, h: F) -> Result<Self, Error> {
        let b = positive("b", b)?;
        let alpha = positive("alpha", alpha)?;
        let h = positive("h", h)?;
        if !(beta.is_finite() && beta >= F::ZERO) {
            return Err(Error::Negative {
                name: "beta",
                value: beta.to_f64(),
            });
        }
        let u = alpha * h;
        in_range("alpha h", u, ALPHA_H)?;
        let sy2 = alpha / b;
        let p1 = phi1(u);
        let p1_2u = phi1(u + u);
        let sy2_h = sy2 * h;
        let step = Self {
            e: (-u).exp(),
            c_xy: h * p1,
            l_yy: (F::TWO * sy2_h * p1_2u).sqrt(),
            l_xy: sy2_h.sqrt() * h * p1 * p1 / (F::TWO * p1_2u).sqrt(),
            schur_y: F::TWO * sy2_h * h * h * omega(u),
            cov_xy: sy2_h * h * p1 * p1,
            var_y: F::TWO * sy2_h * p1_2u,
            beta_h: beta * h,
            two_beta_h: F::TWO * beta * h,
            h2_phi2_over_b: h * h * phi2(u) / b,
            h_phi1_over_b: h * p1 / b,
            a: F::ZERO,
            c_xg: F::ZERO,
            c_yg: F::ZERO,
            l_xx: F::ZERO,
        };
        let fixed = [
            step.e,
            step.c_xy,
            step.l_yy,
            step.l_xy,
            step.schur_y,
            step.cov_xy,
            step.var_y,
            step.two_beta_h,
            step.h2_phi2_over_b,
            step.h_phi1_over_b,
        ];
        // A vanishing velocity variance would make the step deterministic in
        // y and the moments meaningless: refuse it with the overflows.
        let var_y_positive = step.var_y > F::ZERO;
        if !fixed.iter().all(|c| c.is_finite()) || !var_y_positive {
            return Err(Error::DegenerateCoefficients);
        }
        Ok(step)
    }

    /// This kernel with the three coefficients that depend on the inverse
    /// temperature computed for `a`.
    #[inline]
    pub(crate) fn at(mut self, a: F) -> Result<Self, Error> {
        let a = positive("a", a)?;
        in_range("a", a, INVERSE_TEMPERATURE)?;
        let c_xg = self.beta_h + a * self.h2_phi2_over_b;
        let c_yg = a * self.h_phi1_over_b;
        let l_xx = (self.two_beta_h / a + self.schur_y).sqrt();
        if !(c_xg.is_finite() && c_yg.is_finite() && l_xx.is_finite()) {
            return Err(Error::DegenerateCoefficients);
        }
        self.a = a;
        self.c_xg = c_xg;
        self.c_yg = c_yg;
        self.l_xx = l_xx;
        Ok(self)
    }

    /// This kernel, whose coefficients hold in units of `length` and
    /// `energy`, for positions and gradients in units of 1: the step moves
    /// `length x` and takes `(energy / length) g` as it moved `x` with `g`
    /// (the momentum stays in the kernel's units). Applied after
    /// [`at`](Self::at), which it does not commute with.
    pub(crate) fn in_units(mut self, length: F, energy: F) -> Self {
        let drift = length * length / energy;
        self.c_xy *= length;
        self.l_xy *= length;
        self.l_xx *= length;
        self.c_xg *= drift;
        self.c_yg *= length / energy;
        self.two_beta_h *= length * length;
        self.schur_y *= length * length;
        self.cov_xy *= length;
        self
    }

    /// The factor that turns two standard normals into the step's noise.
    pub fn noise_factor(&self) -> NoiseFactor<F> {
        NoiseFactor {
            yy: self.l_yy,
            xy: self.l_xy,
            xx: self.l_xx,
        }
    }

    #[inline(always)]
    fn mean(&self, x: F, y: F, g: F) -> (F, F) {
        (
            x + self.c_xy * y - self.c_xg * g,
            self.e * y - self.c_yg * g,
        )
    }

    /// One exact step of one coordinate from two standard normals.
    #[inline(always)]
    fn apply(&self, x: &mut F, y: &mut F, g: F, z1: F, z2: F) {
        let (mx, my) = self.mean(*x, *y, g);
        *x = mx + self.l_xy * z1 + self.l_xx * z2;
        *y = my + self.l_yy * z1;
    }
}

impl<F: Float> Kernel<F> for OuKernel<F> {
    #[inline]
    fn inverse_temperature(&self) -> F {
        self.a
    }

    fn moments(&self, x: F, y: F, g: F) -> StepMoments<F> {
        let (mean_x, mean_y) = self.mean(x, y, g);
        StepMoments {
            mean_x,
            mean_y,
            var_x: self.two_beta_h / self.a
                + self.schur_y
                + self.cov_xy * (self.cov_xy / self.var_y),
            cov_xy: self.cov_xy,
            var_y: self.var_y,
        }
    }

    /// Draws in the documented order: per coordinate, the pair `(z1, z2)`.
    #[inline]
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [F; D],
        y: &mut [F; D],
        grad: &[F; D],
        rng: &mut R,
    ) {
        // One block of all D coordinates when it is small (fixed sizes the
        // compiler unrolls); blocks of 64 beyond, so that the draws' buffer
        // stays small whatever D is. Two functions, so that even an
        // unoptimised build reserves only the buffer of the path it takes.
        if D <= BLOCK {
            self.step_block::<R, D>(x, y, grad, rng);
        } else {
            for ((xb, yb), gb) in x
                .chunks_mut(BLOCK)
                .zip(y.chunks_mut(BLOCK))
                .zip(grad.chunks(BLOCK))
            {
                self.step_block::<R, BLOCK>(xb, yb, gb, rng);
            }
        }
    }

    /// Every chain's pair `(z1, z2)` of a coordinate in lockstep, then each
    /// chain's update: the draws of [`step`](Kernel::step), per lane.
    #[inline]
    fn step_lanes<const D: usize>(
        &self,
        mut chains: [ChainState<'_, [F; D]>; LANES],
        rng: &mut Xoshiro256Lanes,
    ) {
        if D <= BLOCK {
            self.step_lanes_block::<D, D>(&mut chains, 0, rng);
        } else {
            for start in (0..D).step_by(BLOCK) {
                self.step_lanes_block::<D, BLOCK>(&mut chains, start, rng);
            }
        }
    }

    /// [`step`](Kernel::step)'s draws and updates in blocks of a size
    /// fixed at compile time (16 coordinates for small points, 64 beyond):
    /// the stream and the arithmetic do not depend on the blocks.
    #[inline]
    fn step_slice<R: Rng + ?Sized>(&self, x: &mut [F], y: &mut [F], grad: &[F], rng: &mut R) {
        if x.len() <= TINY_BLOCK {
            self.step_block::<R, TINY_BLOCK>(x, y, grad, rng);
        } else if x.len() <= SMALL_BLOCK {
            self.step_block::<R, SMALL_BLOCK>(x, y, grad, rng);
        } else {
            for ((xb, yb), gb) in x
                .chunks_mut(BLOCK)
                .zip(y.chunks_mut(BLOCK))
                .zip(grad.chunks(BLOCK))
            {
                self.step_block::<R, BLOCK>(xb, yb, gb, rng);
            }
        }
    }

    #[inline]
    fn step_lanes_slice(
        &self,
        mut chains: [ChainState<'_, [F]>; LANES],
        rng: &mut Xoshiro256Lanes,
    ) {
        let d = chains[0].x.len();
        if d <= SMALL_BLOCK {
            self.step_lanes_block_slices::<SMALL_BLOCK>(&mut chains, d, 0, rng);
        } else {
            for start in (0..d).step_by(BLOCK) {
                self.step_lanes_block_slices::<BLOCK>(&mut chains, d, start, rng);
            }
        }
    }
}

/// The blocks of [`Kernel::step_slice`] for points of at most this many
/// coordinates: buffers small enough to cost nothing to set up.
const TINY_BLOCK: usize = 4;
const SMALL_BLOCK: usize = 16;

/// Coordinates stepped together: all of a block's draws first, then its
/// update, so that the update's loop has no branch and vectorises (the
/// stream is the same either way).
const BLOCK: usize = 64;

impl<F: Float> OuKernel<F> {
    /// One block of at most `B` coordinates. (`#[inline]`, not `always`:
    /// unoptimised builds keep it out of line, so that its buffer's frame
    /// is reserved only when it runs.)
    #[inline]
    fn step_block<R: Rng + ?Sized, const B: usize>(
        &self,
        x: &mut [F],
        y: &mut [F],
        grad: &[F],
        rng: &mut R,
    ) {
        let mut z = [(F::ZERO, F::ZERO); B];
        let z = &mut z[..x.len()];
        for zi in z.iter_mut() {
            *zi = F::standard_normal_pair(rng);
        }
        for (((xi, yi), &gi), &(z1, z2)) in x.iter_mut().zip(y.iter_mut()).zip(grad).zip(&*z) {
            self.apply(xi, yi, gi, z1, z2);
        }
    }

    /// Coordinates `start..start + B` (at most) of [`LANES`] chains: every
    /// chain's normals in lockstep first, then each chain's update, which
    /// vectorises over its coordinates.
    #[inline]
    fn step_lanes_block<const D: usize, const B: usize>(
        &self,
        chains: &mut [ChainState<'_, [F; D]>; LANES],
        start: usize,
        rng_out: &mut Xoshiro256Lanes,
    ) {
        let n = D.min(start + B) - start;
        let mut z1 = [[F::ZERO; B]; LANES];
        let mut z2 = [[F::ZERO; B]; LANES];
        Self::lane_normals(n, rng_out, &mut z1, &mut z2);
        for ((chain, z1), z2) in chains.iter_mut().zip(&z1).zip(&z2) {
            let x = &mut chain.x[start..start + n];
            let y = &mut chain.y[start..start + n];
            let grad = &chain.grad[start..start + n];
            for i in 0..n {
                self.apply(&mut x[i], &mut y[i], grad[i], z1[i], z2[i]);
            }
        }
    }

    /// [`step_lanes_block`](Self::step_lanes_block) for chains of `d`
    /// coordinates in slices: the same draws and updates. (Apart, so that
    /// the fixed-size version indexes arrays.)
    #[inline]
    fn step_lanes_block_slices<const B: usize>(
        &self,
        chains: &mut [ChainState<'_, [F]>; LANES],
        d: usize,
        start: usize,
        rng_out: &mut Xoshiro256Lanes,
    ) {
        let n = d.min(start + B) - start;
        let mut z1 = [[F::ZERO; B]; LANES];
        let mut z2 = [[F::ZERO; B]; LANES];
        Self::lane_normals(n, rng_out, &mut z1, &mut z2);
        for ((chain, z1), z2) in chains.iter_mut().zip(&z1).zip(&z2) {
            let x = &mut chain.x[start..start + n];
            let y = &mut chain.y[start..start + n];
            let grad = &chain.grad[start..start + n];
            for i in 0..n {
                self.apply(&mut x[i], &mut y[i], grad[i], z1[i], z2[i]);
            }
        }
    }

    /// The pairs `(z1, z2)` of `n <= B` coordinates of every lane, drawn
    /// coordinate by coordinate in lockstep, into the caller's buffers (a
    /// returned pair of buffers was copied: 4% of a step at d = 100).
    #[inline(always)]
    fn lane_normals<const B: usize>(
        n: usize,
        rng_out: &mut Xoshiro256Lanes,
        z1: &mut [[F; B]; LANES],
        z2: &mut [[F; B]; LANES],
    ) {
        // A local copy: its address never escapes, so the generators stay
        // in vector registers.
        let mut lanes = *rng_out;
        for i in 0..n {
            let pairs = F::standard_normal_pair_lanes(&mut lanes);
            for l in 0..LANES {
                (z1[l][i], z2[l][i]) = pairs[l];
            }
        }
        *rng_out = lanes;
    }
}

//! What a sampler is: a method ([`Sampler`]) that, at each inverse
//! temperature `a`, gives the Markov kernel of one step ([`Kernel`]).
//!
//! The inverse temperature lives with whoever drives the chains (the
//! optimiser's schedule); a sampler holds only its `a`-free parameters, and
//! [`Sampler::at`] derives the step's coefficients at the `a` asked for.

use rand_core::Rng;

use crate::error::Error;
use crate::float::Float;
use crate::lockstep::{LANES, Xoshiro256Lanes};

/// A Langevin-type sampling method: its parameters, without the inverse
/// temperature.
///
/// A new sampler is one file: a type implementing this trait, with a
/// `paper(h)` constructor, and its [`Kernel`] (or an existing one, as ULA
/// reuses HRLA's).
pub trait Sampler<F: Float> {
    /// The step at one inverse temperature.
    type Kernel: Kernel<F>;

    /// The step at inverse temperature `a`. Errors when `a` is not finite
    /// and > 0, or when the step's coefficients overflow or vanish there.
    fn at(&self, a: F) -> Result<Self::Kernel, Error>;
}

/// One step of a Langevin-type chain at a fixed inverse temperature.
///
/// The chain's state is a position `x` and a velocity `y` (kernels without a
/// velocity leave `y` alone). The gradient of the potential at `x` is
/// passed in, so a step costs no potential evaluation of its own: the caller
/// evaluates the potential once, after the step, for both the running best
/// and the next step's gradient.
pub trait Kernel<F: Float>: Copy {
    /// The inverse temperature `a` of this step.
    fn inverse_temperature(&self) -> F;

    /// The conditional mean and covariance of one step of one coordinate
    /// from position `x`, velocity `y` and gradient component `g`.
    fn moments(&self, x: F, y: F, g: F) -> StepMoments<F>;

    /// Advances `(x, y)` by one step, given `grad = ∇U(x)`.
    ///
    /// Must not fail: every check belongs in [`Sampler::at`].
    fn step<R: Rng + ?Sized, const D: usize>(
        &self,
        x: &mut [F; D],
        y: &mut [F; D],
        grad: &[F; D],
        rng: &mut R,
    );

    /// [`step`](Kernel::step) for a dimension known at run time, the
    /// length of the slices (all three the same): the same draws and the
    /// same float operations, so the same bits.
    fn step_slice<R: Rng + ?Sized>(&self, x: &mut [F], y: &mut [F], grad: &[F], rng: &mut R);

    /// Advances `L` chains by one step each, chain `l` drawing from lane
    /// `l` of `rng`: bit for bit what [`step`](Kernel::step) gives with
    /// that lane's generator alone. This is the seam for wide hardware:
    /// the chains are independent, so a kernel may interleave their draws
    /// and updates in any way that keeps each chain's own order of draws.
    ///
    /// The default steps the chains one after another; kernels override it
    /// to draw every chain's normals in lockstep.
    #[inline]
    fn step_lanes<const D: usize>(
        &self,
        chains: [ChainState<'_, [F; D]>; LANES],
        rng: &mut Xoshiro256Lanes,
    ) {
        for (l, chain) in chains.into_iter().enumerate() {
            self.step(chain.x, chain.y, chain.grad, &mut rng.lane(l));
        }
    }

    /// [`step_lanes`](Kernel::step_lanes) for a dimension known at run time,
    /// the length of every chain's slices.
    #[inline]
    fn step_lanes_slice(&self, chains: [ChainState<'_, [F]>; LANES], rng: &mut Xoshiro256Lanes) {
        for (l, chain) in chains.into_iter().enumerate() {
            self.step_slice(chain.x, chain.y, chain.grad, &mut rng.lane(l));
        }
    }
}

/// What [`Kernel::step_lanes`] and [`Kernel::step_lanes_slice`] advance of
/// one chain: its position and velocity, and the gradient at the position,
/// each a `V`: an array `[F; D]` when the dimension is in the type, a
/// slice `[F]` of the run's dimension otherwise.
#[derive(Debug)]
pub struct ChainState<'a, V: ?Sized> {
    /// Position `x`.
    pub x: &'a mut V,
    /// Velocity `y`.
    pub y: &'a mut V,
    /// `∇U(x)`.
    pub grad: &'a V,
}

/// Mean and covariance of one step of one coordinate, given `(x, y)` and the
/// gradient component `g` at the start of the step.
///
/// For OLA, which has no velocity, `mean_y = y` and the `y` entries of the
/// covariance are zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepMoments<F> {
    /// Conditional mean of the new position.
    pub mean_x: F,
    /// Conditional mean of the new velocity.
    pub mean_y: F,
    /// Conditional variance of the new position.
    pub var_x: F,
    /// Conditional covariance of the new position and velocity.
    pub cov_xy: F,
    /// Conditional variance of the new velocity.
    pub var_y: F,
}

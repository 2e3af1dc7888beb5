//! The default solver's constants, and the parts of a round.

use crate::error::Error;
use crate::float::Float;

/// The most HRLA steps per round [`Auto::steps`] may ask for.
pub const MAX_STEPS: u64 = 10_000;

/// How a round moves a chain away from its basin before the quench.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampling {
    /// [`Auto::steps`] HRLA steps at the chain's temperature (the default).
    Langevin,
    /// The same dynamics with `∇U` set to zero: a Gaussian jump of the law
    /// of [`Auto::steps`] gradient-free HRLA steps, evaluated once at its
    /// end. What the gradient in the sampler adds is the difference.
    Jump,
    /// No trajectory: a differential move `x + γ (x_i - x_j)` along the
    /// difference of two other chains' basins (`γ` uniform in
    /// `[0.5, 1]`; with two chains, along the other's difference from
    /// this one), rotation invariant as in differential evolution. A long
    /// jump between unrelated basins far apart, which a trajectory does
    /// not make: Schwefel's deceptive basins (`docs/QUALITY.md`).
    Differential,
}

/// The parts of a round. The default is Langevin sampling with quenches;
/// switched off one at a time they are the quality benchmark's ablations,
/// and [`Sampling::Differential`] is a user's option for deceptive
/// separable problems (Schwefel's; `docs/QUALITY.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Parts {
    /// How a chain leaves its basin.
    pub sampling: Sampling,
    /// The quench of every proposal (without it, the proposal's end point
    /// is the chain's new state; the best point is still polished at the
    /// end).
    pub quenches: bool,
}

impl Default for Parts {
    fn default() -> Self {
        Self {
            sampling: Sampling::Langevin,
            quenches: true,
        }
    }
}

/// The default solver's constants (see the module docs of `auto` in the
/// crate's source, and [`Auto::minimize`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Auto<F> {
    /// HRLA steps per round, from the chain's basin (1 to [`MAX_STEPS`]).
    pub steps: u64,
    /// `h = step_scale / L`, `L` the typical curvature at the basins'
    /// bottoms.
    pub step_scale: F,
    /// Half-width of the ladder of inverse temperatures in `ln a`: chain
    /// `c` of `N` samples at `a_0 exp(ladder (2c / (N - 1) - 1))`.
    pub ladder: F,
    /// Evaluations per quench, at most (it ends earlier when it converges).
    pub quench: u64,
    /// Evaluations per quench of the initial points, at most, before the
    /// first round: where a gradient costs `1 + d` calls of a black-box
    /// function, a few make the run anytime (its first round of sampling
    /// starts within a few dozen gradients) and the rounds' own quenches
    /// finish the descent.
    pub first_quench: u64,
    /// Rounds without a new best that make a stall: the default convergence
    /// rule ([`Problem::converged`](crate::Problem::converged)) ends a run
    /// after two.
    pub stall: u64,
    /// The parts of a round: Langevin sampling and quenches by default;
    /// see [`Parts`] for the alternatives.
    pub parts: Parts,
    /// The acceptance rate each rung's step is steered to: after each
    /// proposal of a rung, its step is multiplied by `exp(0.3 (1 - accept))`
    /// if the proposal was accepted and by `exp(-0.3 accept)` if not, so
    /// that it stays put on average at that rate (within `1e-3` of the
    /// measured step and the longest the box allows). 0 keeps the measured
    /// step on every rung.
    pub accept: F,
}

impl<F: Float> Default for Auto<F> {
    /// 10 HRLA steps per round from `h = 2 / L`, steered to accept half
    /// the proposals, a ladder of `±3.5` in `ln a`, quenches (the initial
    /// points' too) of up to 1000 evaluations, and a stall of 30 rounds
    /// without a new best.
    fn default() -> Self {
        Self {
            steps: 10,
            step_scale: F::TWO,
            ladder: F::from_f64(3.5),
            quench: 1000,
            first_quench: 1000,
            stall: 30,
            parts: Parts::default(),
            accept: F::HALF,
        }
    }
}

impl<F: Float> Auto<F> {
    /// The constants checked: [`Error::Zero`], [`Error::OutOfRange`],
    /// [`Error::NotPositive`] for a bad one.
    pub(super) fn validate(&self) -> Result<(), Error> {
        if self.quench == 0 {
            return Err(Error::Zero { name: "quench" });
        }
        if self.first_quench == 0 {
            return Err(Error::Zero {
                name: "first_quench",
            });
        }
        if self.stall == 0 {
            return Err(Error::Zero { name: "stall" });
        }
        if self.steps == 0 && self.parts.sampling != Sampling::Differential {
            return Err(Error::Zero { name: "steps" });
        }
        // A jump's steps cost no evaluation: the budget would not bound them.
        if self.steps > MAX_STEPS {
            return Err(Error::OutOfRange {
                name: "steps",
                value: self.steps as f64,
                min: 1.0,
                max: MAX_STEPS as f64,
            });
        }
        if !(self.step_scale.is_finite() && self.step_scale > F::ZERO) {
            return Err(Error::NotPositive {
                name: "step_scale",
                value: self.step_scale.to_f64(),
            });
        }
        // Zero is allowed: a ladder of one temperature.
        if !(self.ladder.is_finite() && self.ladder >= F::ZERO) {
            return Err(Error::NotPositive {
                name: "ladder",
                value: self.ladder.to_f64(),
            });
        }
        if !(self.accept >= F::ZERO && self.accept <= F::ONE) {
            return Err(Error::NotPositive {
                name: "accept (in [0, 1])",
                value: self.accept.to_f64(),
            });
        }
        Ok(())
    }
}

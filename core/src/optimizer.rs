//! Algorithm 1: run N independent chains and keep the best point seen.

use heapless::Vec;
use rand_core::Rng;

use crate::error::{Error, finite};
use crate::float::Float;
use crate::potential::Potential;
use crate::sampler::{Kernel, Sampler};
use crate::schedule::Schedule;
use crate::start::Start;

/// A point with its potential and the iteration at which it was visited.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Best<F, const D: usize> {
    /// The position.
    pub x: [F; D],
    /// `U(x)`, always finite.
    pub value: F,
    /// The iterate index `k` (0 is the initial point).
    pub iteration: u64,
}

/// One chain: its state `(x, y)`, the potential and gradient at `x`, and its
/// own running best.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chain<F, const D: usize> {
    x: [F; D],
    y: [F; D],
    value: F,
    grad: [F; D],
    best: Best<F, D>,
    diverged: bool,
}

impl<F: Float, const D: usize> Chain<F, D> {
    /// Current position `x_k`.
    pub fn x(&self) -> &[F; D] {
        &self.x
    }
    /// Current velocity `y_k` (zero throughout for samplers without one).
    pub fn y(&self) -> &[F; D] {
        &self.y
    }
    /// `U(x_k)`; for a diverged chain, the non-finite value that stopped it
    /// (or the finite value beside a non-finite gradient).
    pub fn value(&self) -> F {
        self.value
    }
    /// `∇U(x_k)`.
    pub fn gradient(&self) -> &[F; D] {
        &self.grad
    }
    /// The chain's running best over its recorded iterates.
    pub fn best(&self) -> &Best<F, D> {
        &self.best
    }
    /// `true` once the position, the potential or its gradient went
    /// non-finite: the chain
    /// is then frozen (no more steps, no more random draws) and excluded
    /// from the best.
    pub fn is_diverged(&self) -> bool {
        self.diverged
    }
}

/// Where a run stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// No stopping condition is met; in a [`Report`] from
    /// [`Optimizer::run`], the step budget was spent.
    Running,
    /// The global best reached the target set by [`Optimizer::with_target`].
    TargetReached,
    /// Every chain has diverged (see [`Chain::is_diverged`]).
    AllDiverged,
}

/// The outcome of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report<F, const D: usize> {
    /// The global running best (never NaN: initial points must be finite).
    pub best: Best<F, D>,
    /// Steps done since construction.
    pub iterations: u64,
    /// Potential-and-gradient evaluations, including the initial ones.
    pub gradient_evaluations: u64,
    /// Chains that diverged.
    pub diverged_chains: usize,
    /// Why the run stopped.
    pub status: Status,
}

/// Algorithm 1 of the paper with running best: `n <= N` independent chains
/// of a [`Sampler`] on a [`Potential`], at inverse temperatures given by a
/// [`Schedule`] (a plain `f32` or `f64` for a constant `a`), holding
/// everything inline (no allocation). The schedule is the one home of `a`:
/// before every step the optimiser takes the sampler's kernel at `a_k`.
///
/// Iterate `k` of a chain is its state after `k` steps; the step from `k`
/// to `k + 1` runs at `a_k`. The running best (per chain and global) is the
/// minimum of `U` over the iterates `k = 0, s, 2s, ...` of the stride `s`
/// (default 1). Unlike the paper's tables, it includes the initial points:
/// they were evaluated, and an optimiser never returns worse than its start.
///
/// Random numbers are drawn chain after chain, coordinate after coordinate,
/// so a run is a pure function of the seed, whatever mix of [`step`] and
/// [`run`] drives it.
///
/// [`step`]: Optimizer::step
/// [`run`]: Optimizer::run
#[derive(Clone, Debug)]
pub struct Optimizer<F: Float, P, S: Sampler<F>, C, const D: usize, const N: usize> {
    potential: P,
    sampler: S,
    kernel: S::Kernel,
    schedule: C,
    chains: Vec<Chain<F, D>, N>,
    best: Best<F, D>,
    iteration: u64,
    gradient_evaluations: u64,
    stride: u64,
    target: Option<F>,
    diverged: usize,
}

impl<F, P, S, C, const D: usize, const N: usize> Optimizer<F, P, S, C, D, N>
where
    F: Float,
    P: Potential<F, D>,
    S: Sampler<F>,
    C: Schedule<F>,
{
    /// Draws `chains` initial points (`1 <= chains <= N`) from `start`, with
    /// zero velocities, and evaluates the potential there; the first step
    /// runs at the schedule's `a_0`.
    ///
    /// Errors: [`Error::Count`] for a bad number of chains, the sampler's
    /// error if it refuses `a_0`, [`Error::NonFiniteStart`] if `U` or `∇U`
    /// is not finite at an initial point.
    pub fn new<St: Start<F, D>, R: Rng + ?Sized>(
        potential: P,
        sampler: S,
        schedule: C,
        chains: usize,
        start: &mut St,
        rng: &mut R,
    ) -> Result<Self, Error> {
        const { assert!(D > 0, "the dimension D must be at least 1") };
        if chains == 0 || chains > N {
            return Err(Error::Count {
                name: "chains",
                value: chains,
                max: N,
            });
        }
        let kernel = sampler.at(schedule.inverse_temperature(0))?;
        let mut list = Vec::new();
        let mut best: Option<Best<F, D>> = None;
        for c in 0..chains {
            let x = start.initial_point(c, rng);
            let mut grad = [F::ZERO; D];
            let value = potential.value_and_gradient(&x, &mut grad);
            if !(value.is_finite() && all_finite(&x) && all_finite(&grad)) {
                return Err(Error::NonFiniteStart { chain: c });
            }
            let here = Best {
                x,
                value,
                iteration: 0,
            };
            if best.is_none_or(|b| value < b.value) {
                best = Some(here);
            }
            let chain = Chain {
                x,
                y: [F::ZERO; D],
                value,
                grad,
                best: here,
                diverged: false,
            };
            // Cannot fail: chains <= N was checked above.
            let _ = list.push(chain);
        }
        Ok(Self {
            potential,
            sampler,
            kernel,
            schedule,
            chains: list,
            // Cannot be None: chains >= 1.
            best: best.unwrap_or(Best {
                x: [F::ZERO; D],
                value: F::INFINITY,
                iteration: 0,
            }),
            iteration: 0,
            gradient_evaluations: chains as u64,
            stride: 1,
            target: None,
            diverged: 0,
        })
    }

    /// Records the running best only at iterates `k` that are multiples of
    /// `stride >= 1` (the paper's tables use 100 or 1).
    pub fn with_stride(mut self, stride: u64) -> Result<Self, Error> {
        if stride == 0 {
            return Err(Error::Zero { name: "stride" });
        }
        self.stride = stride;
        Ok(self)
    }

    /// Stops [`Optimizer::run`] as soon as the global best is `<= target`.
    pub fn with_target(mut self, target: F) -> Result<Self, Error> {
        self.target = Some(finite("target", target)?);
        Ok(self)
    }

    /// Advances every live chain by one step, then evaluates `U` and `∇U` at
    /// the new points and updates the running bests.
    ///
    /// Errors only if the schedule's `a_k` is refused by the sampler (not
    /// finite, not positive, or degenerate coefficients); the state is then
    /// unchanged.
    pub fn step<R: Rng + ?Sized>(&mut self, rng: &mut R) -> Result<Status, Error> {
        let a = self.schedule.inverse_temperature(self.iteration);
        if a != self.kernel.inverse_temperature() {
            self.kernel = self.sampler.at(a)?;
        }
        let k = self.iteration + 1;
        let record = k % self.stride == 0;
        for chain in self.chains.iter_mut().filter(|c| !c.diverged) {
            self.kernel
                .step(&mut chain.x, &mut chain.y, &chain.grad, rng);
            let value = self.potential.value_and_gradient(&chain.x, &mut chain.grad);
            self.gradient_evaluations += 1;
            chain.value = value;
            if !(value.is_finite() && all_finite(&chain.grad) && all_finite(&chain.x)) {
                chain.diverged = true;
                self.diverged += 1;
                continue;
            }
            if record && value < chain.best.value {
                chain.best = Best {
                    x: chain.x,
                    value,
                    iteration: k,
                };
                if value < self.best.value {
                    self.best = chain.best;
                }
            }
        }
        self.iteration = k;
        Ok(self.status())
    }

    /// Runs up to `steps` more steps, stopping early at the target or when
    /// every chain has diverged.
    pub fn run<R: Rng + ?Sized>(&mut self, steps: u64, rng: &mut R) -> Result<Report<F, D>, Error> {
        let mut status = self.status();
        let mut done = 0;
        while status == Status::Running && done < steps {
            status = self.step(rng)?;
            done += 1;
        }
        Ok(self.report())
    }

    /// Where the run stands now.
    pub fn status(&self) -> Status {
        if self.diverged == self.chains.len() {
            Status::AllDiverged
        } else if self.target.is_some_and(|t| self.best.value <= t) {
            Status::TargetReached
        } else {
            Status::Running
        }
    }

    /// The report of the run so far.
    pub fn report(&self) -> Report<F, D> {
        Report {
            best: self.best,
            iterations: self.iteration,
            gradient_evaluations: self.gradient_evaluations,
            diverged_chains: self.diverged,
            status: self.status(),
        }
    }

    /// The global running best.
    pub fn best(&self) -> &Best<F, D> {
        &self.best
    }

    /// The index and current value of the live chain with the lowest `U(x_k)`
    /// (the paper's "best chain at iterate k", not running); `None` when
    /// every chain has diverged.
    pub fn current_best(&self) -> Option<(usize, F)> {
        let mut best: Option<(usize, F)> = None;
        for (i, c) in self.chains.iter().enumerate() {
            if !c.diverged && best.is_none_or(|(_, v)| c.value < v) {
                best = Some((i, c.value));
            }
        }
        best
    }

    /// The chains, in order.
    pub fn chains(&self) -> &[Chain<F, D>] {
        &self.chains
    }

    /// Steps done so far (the current iterate index `k`).
    pub fn iteration(&self) -> u64 {
        self.iteration
    }

    /// Potential-and-gradient evaluations so far.
    pub fn gradient_evaluations(&self) -> u64 {
        self.gradient_evaluations
    }

    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }

    /// The sampler.
    pub fn sampler(&self) -> &S {
        &self.sampler
    }

    /// The sampler's kernel at the inverse temperature of the last step
    /// (`a_0` before the first).
    pub fn kernel(&self) -> &S::Kernel {
        &self.kernel
    }

    /// The schedule.
    pub fn schedule(&self) -> &C {
        &self.schedule
    }
}

/// Without short-circuit, so that the checks vectorise: this runs on every
/// chain at every step, and a chain is almost always finite.
#[inline(always)]
fn all_finite<F: Float, const D: usize>(v: &[F; D]) -> bool {
    v.iter().fold(true, |ok, x| ok & x.is_finite())
}

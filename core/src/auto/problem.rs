//! What a run of [`Auto`] is asked ([`Problem`]), what its observer sees
//! ([`AutoProgress`]), what it returns ([`Solution`]), and the two stores
//! it runs on: const-generic [`Chain`]s with an [`Lbfgs`], or the caller's
//! [`AutoStorage`] at a dimension known at run time.

use core::fmt;
use core::ops::ControlFlow;

use rand_core::{Rng, SeedableRng};

use super::run::{self, Found, Seen};
use super::settings::Auto;
use super::storage::{AutoStorage, Lent};
use crate::domain::Sides;
use crate::error::{Error, check_dimensions};
use crate::float::Float;
use crate::optimizer::{Chain, Stop, Termination};
use crate::polish::{Arrays, Lbfgs};
use crate::potential::BatchPotential;
use crate::potential::traits::Potential;

/// One problem for [`Auto`]: the potential, its box, the evaluation
/// budget, the seed, an optional start, and the rules that end a run
/// before its budget. Built by chaining, as [`Stop`] is:
///
/// ```
/// use hrla::{Interval, Problem, Rastrigin};
///
/// let domain = Interval::new(-5.12, 5.12)?;
/// let problem = Problem::new(&Rastrigin, &domain, 125_000)
///     .seed(7)
///     .target(1e-8)
///     .stall(50, 0.0)
///     .rounds(10_000);
/// # let _ = problem;
/// # Ok::<(), hrla::Error>(())
/// ```
///
/// The rules:
/// - [`target`](Problem::target): the run ends at once when the best value
///   is at or below it ([`Termination::Target`]);
/// - [`rounds`](Problem::rounds): at most that many rounds
///   ([`Termination::Steps`]);
/// - [`stall`](Problem::stall): the rounds end when the best value has not
///   fallen by more than the tolerance over the window's rounds
///   ([`Termination::Stalled`]);
/// - [`converge`](Problem::converge): the same with a tolerance relative
///   to the problem's scale ([`Termination::Converged`]): the rule that
///   makes the budget a cap rather than a target.
///
/// A run ended by its rounds, its stall or its convergence rule still
/// polishes its best point with what is left of the budget; one that reached its target
/// ends there.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'p, F, P: ?Sized, B: ?Sized> {
    pub(super) potential: &'p P,
    pub(super) domain: &'p B,
    pub(super) budget: u64,
    pub(super) seed: u64,
    pub(super) x0: Option<&'p [F]>,
    /// Target, stall and rounds (`steps`); the budget is `budget`.
    pub(super) rules: Stop<F>,
    /// The convergence rule's window of rounds.
    pub(super) converge: Option<u64>,
    /// The budget the run plans within, at most `budget`.
    pub(super) soft: Option<u64>,
}

impl<'p, F: Float, P: ?Sized, B: Sides<F> + ?Sized> Problem<'p, F, P, B> {
    /// Minimise `potential` over the box `domain` (an
    /// [`Interval`](crate::Interval), a [`Bounds`](crate::Bounds) with a
    /// side per coordinate) within `budget` evaluations, every one counted;
    /// seed 0, every chain's start drawn, no rule but the budget.
    pub fn new(potential: &'p P, domain: &'p B, budget: u64) -> Self {
        Self {
            potential,
            domain,
            budget,
            seed: 0,
            x0: None,
            rules: Stop::new(),
            converge: None,
            soft: None,
        }
    }

    /// Chain `c` draws from the generator of `(seed, c)`.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Chain 0 starts at `x0` instead of a uniform draw (the other chains
    /// draw theirs as without it): a guess the run starts from, as scipy's
    /// `x0`. It costs the one evaluation chain 0's draw would have; the run
    /// differs from one without `x0` only through chain 0. `x0` must lie in
    /// the box, and `U` and its gradient must be finite there (it is not
    /// redrawn, since the caller chose it).
    pub fn x0(mut self, x0: &'p [F]) -> Self {
        self.x0 = Some(x0);
        self
    }

    /// End the run as soon as the best value is `<= target`.
    pub fn target(mut self, target: F) -> Self {
        self.rules = self.rules.target(target);
        self
    }

    /// End the rounds when the best value has not fallen by more than
    /// `tolerance` over the last `window` rounds.
    pub fn stall(mut self, window: u64, tolerance: F) -> Self {
        self.rules = self.rules.stall(window, tolerance);
        self
    }

    /// End the run as converged ([`Termination::Converged`]) when the
    /// best value has not fallen, beyond rounding, over the last `window`
    /// rounds: by more than `1e-12` times the spread (interquartile
    /// range) of `U` at the initial points, a tolerance in the problem's
    /// own units, so that the rule reads the same whatever the scale of
    /// `U`. The default window is two stalls, `2` [`Auto::stall`] rounds
    /// ([`Problem::converged`]). The
    /// rule also holds after a sixth of the window (at least one round)
    /// in which the best did not fall and every chain's basin was the
    /// best's (within `1e-8` of that spread): every chain, the hottest
    /// included, keeps finding the one basin, as on a unimodal problem.
    /// The best point is then polished.
    pub fn converge(mut self, window: u64) -> Self {
        self.converge = Some(window);
        self
    }

    /// [`converge`](Problem::converge) with the window `auto` measured
    /// best: two stalls, `2 auto.stall` rounds.
    pub fn converged(self, auto: &Auto<F>) -> Self {
        self.converge(auto.stall.saturating_mul(2))
    }

    /// A soft budget: the run plans within `soft` evaluations (its rounds
    /// and the polish's reserve), but the quench of the lowest initial
    /// point, the run's best start, may go on past it to the budget. A
    /// run whose first quench went past `soft` starts nothing after it
    /// and ends as its budget ends ([`Termination::Evaluations`]), having
    /// spent what that quench took. For a caller that hands what is left
    /// to another method: a best start cut short is a basin half searched,
    /// where a converged one is a point the other method can build on. A
    /// soft budget at or above the budget changes nothing.
    pub fn soft_budget(mut self, soft: u64) -> Self {
        self.soft = Some(soft);
        self
    }

    /// End the rounds after `k` of them (`0`: the starts and the polish
    /// only).
    pub fn rounds(mut self, k: u64) -> Self {
        self.rules = self.rules.steps(k);
        self
    }
}

/// What a run of [`Auto`] found, its best point as `X`: an array `[F; D]`
/// from const-generic chains, a slice of the caller's [`AutoStorage`]
/// otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solution<F, X> {
    /// The best point.
    pub x: X,
    /// `U(x)`.
    pub value: F,
    /// Evaluations used, all included (at most the budget).
    pub evaluations: u64,
    /// Rounds done.
    pub rounds: u64,
    /// The step size measured (`step_scale / L`, in units of `x^2 / U`),
    /// from which every rung started.
    pub step: F,
    /// The inverse temperature of the coldest chain.
    pub inverse_temperature: F,
    /// Why the run ended: [`Termination::Evaluations`] (the budget is
    /// spent), one of the [`Problem`]'s rules, or
    /// [`Termination::Observer`].
    pub termination: Termination,
    /// Chains whose last proposal met a point where `U` or its gradient
    /// is not finite (the chain stayed in its basin).
    pub diverged_chains: usize,
    /// Chains in the run.
    pub chains: usize,
}

impl<F, X> Solution<F, X> {
    /// Whether every chain's last proposal met an infeasible point. Not a
    /// failure: a rejected proposal leaves its chain in its feasible
    /// basin, and the best point is feasible and polished either way (a
    /// run that finds no feasible point at all is an error, not a
    /// solution).
    pub fn all_diverged(&self) -> bool {
        self.diverged_chains == self.chains
    }

    fn from_found(x: X, found: Found<F>) -> Self {
        Self {
            x,
            value: found.value,
            evaluations: found.evaluations,
            rounds: found.rounds,
            step: found.step,
            inverse_temperature: found.inverse_temperature,
            termination: found.termination,
            diverged_chains: found.diverged_chains,
            chains: found.chains,
        }
    }
}

impl<F: Float, X> fmt::Display for Solution<F, X> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: best U = {} after {} evaluations in {} rounds (h = {}, a = {}); \
             the last proposal of {} of {} chains met an infeasible point",
            self.termination,
            self.value,
            self.evaluations,
            self.rounds,
            self.step,
            self.inverse_temperature,
            self.diverged_chains,
            self.chains,
        )
    }
}

/// What the observer of [`Auto::minimize_with`] sees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoProgress<'a, F> {
    /// Evaluations so far, all included.
    pub evaluations: u64,
    /// Rounds done.
    pub rounds: u64,
    /// The best point so far.
    pub x: &'a [F],
    /// `U` there.
    pub value: F,
    /// Whether the best value fell since the observer's last call (`true`
    /// at the first call).
    pub improved: bool,
    /// The inverse temperature of the coldest chain.
    pub inverse_temperature: F,
    /// Chains whose last proposal met an infeasible point.
    pub diverged_chains: usize,
}

impl<'a, F: Copy> AutoProgress<'a, F> {
    fn of(seen: &Seen<'a, F>) -> Self {
        Self {
            evaluations: seen.evaluations,
            rounds: seen.rounds,
            x: seen.x,
            value: seen.value,
            improved: seen.improved,
            inverse_temperature: seen.inverse_temperature,
            diverged_chains: seen.diverged_chains,
        }
    }
}

/// A store [`Auto`] runs on, for a potential `P`: `(&mut [Chain<F, D, R>],
/// &mut Lbfgs<F, D, M>)` for a [`Potential<F, D>`](crate::Potential), or
/// `&mut AutoStorage<F, R>` for a [`BatchPotential<F>`] at the storage's
/// dimension. Sealed: the crate's two stores are the only ones.
pub trait AutoStore<F: Float, P: ?Sized> {
    /// The best point as the solution holds it.
    type Point;

    /// Runs `auto` on `problem` in this store.
    #[doc(hidden)]
    fn solve<B, O>(
        self,
        auto: &Auto<F>,
        problem: &Problem<'_, F, P, B>,
        observer: O,
    ) -> Result<Solution<F, Self::Point>, Error>
    where
        B: Sides<F> + ?Sized,
        O: FnMut(&AutoProgress<'_, F>) -> ControlFlow<()>;
}

impl<'s, F, P, const D: usize, R, const M: usize> AutoStore<F, P>
    for (&'s mut [Chain<F, D, R>], &'s mut Lbfgs<F, D, M>)
where
    F: Float,
    P: Potential<F, D> + ?Sized,
    R: Rng + SeedableRng + 'static,
{
    type Point = [F; D];

    fn solve<B, O>(
        self,
        auto: &Auto<F>,
        problem: &Problem<'_, F, P, B>,
        mut observer: O,
    ) -> Result<Solution<F, [F; D]>, Error>
    where
        B: Sides<F> + ?Sized,
        O: FnMut(&AutoProgress<'_, F>) -> ControlFlow<()>,
    {
        let (chains, lbfgs) = self;
        let mut floats = [[F::ZERO; D]; 7];
        let buffers = run::Buffers::new(D, floats.as_flattened_mut());
        let found = auto.drive(
            &Arrays::<_, D>(problem.potential),
            problem,
            chains,
            lbfgs,
            buffers,
            |seen: &Seen<'_, F>| observer(&AutoProgress::of(seen)),
        )?;
        Ok(Solution::from_found(floats[0], found))
    }
}

impl<'s, F, P, R> AutoStore<F, P> for &'s mut AutoStorage<'_, F, R>
where
    F: Float,
    P: BatchPotential<F> + ?Sized,
    R: Rng + SeedableRng + 'static,
{
    type Point = &'s [F];

    fn solve<B, O>(
        self,
        auto: &Auto<F>,
        problem: &Problem<'_, F, P, B>,
        mut observer: O,
    ) -> Result<Solution<F, &'s [F]>, Error>
    where
        B: Sides<F> + ?Sized,
        O: FnMut(&AutoProgress<'_, F>) -> ControlFlow<()>,
    {
        check_dimensions(
            self.dim(),
            [
                ("box sides", problem.domain.dimension()),
                ("potential", problem.potential.batch_dimension()),
            ],
        )?;
        let Lent {
            mut chains,
            buffers,
            lbfgs,
        } = self.parts();
        let found = auto.drive(
            problem.potential,
            problem,
            &mut chains,
            &mut lbfgs?,
            buffers,
            |seen: &Seen<'_, F>| observer(&AutoProgress::of(seen)),
        )?;
        Ok(Solution::from_found(self.best(), found))
    }
}

//! The default solver: Langevin basin hopping on a ladder of temperatures,
//! with no setting to tune.
//!
//! Every chain holds a basin: a point quenched to a local minimum, and its
//! value. A round moves each chain by named steps:
//!
//! 1. **Sampling**: [`Auto::steps`] HRLA steps at the chain's inverse
//!    temperature `a_c`, from there, with the momentum `y` the chain kept
//!    from its last trajectory. The exact OU step is stable at large `h`,
//!    so the trajectory follows the gradient's trend across several basins.
//!    Each rung's step is steered to accept [`Auto::accept`] of its
//!    proposals (half): after every proposal `ln h_c` moves up if it was
//!    accepted and down if not (a Robbins–Monro step, as adaptive
//!    Metropolis samplers and basin hopping steer theirs), so hot rungs
//!    lengthen their trajectories until they reach other basins, and cold
//!    ones shorten theirs.
//! 2. **Quench**: L-BFGS from the trajectory's end until it converges
//!    (at most [`Auto::quench`] evaluations): the basin it fell into. It
//!    starts from the value and gradient the trajectory's last step
//!    evaluated there (as the initial quenches start from their points'),
//!    not evaluating them again.
//! 3. **Acceptance**: Metropolis on the quenched values at `a_c`: the chain
//!    moves to the new basin with probability `min(1, exp(-a_c ΔU))`.
//!
//! After each round, **tempering**: adjacent rungs of the ladder swap their
//! basins with the replica-exchange probability, so good basins flow to the
//! cold chains and the hot ones keep exploring. At the end the best point
//! is **polished** by L-BFGS until it converges: the returned point is a
//! local minimum to the float type's precision (unless the observer
//! stopped the run, or the budget ran out within the polish).
//!
//! The settings are **measured** on the problem ([`measure`]) after the
//! initial points are quenched, the lowest first (a budget that ends within
//! those quenches has searched the best start), and every constant holds
//! in the **problem's own units**: lengths in units of `ℓ`, the box's widest side
//! over `10.24`, and energies in units of `ε`, at which the median
//! curvature `L` along random directions at the basins' bottoms (positive
//! there even on landscapes with flat stretches) is `2 + 4π^2`. On the
//! paper's Rastrigin in `[-5.12, 5.12]^d` these are about the units of `x`
//! and `U`; on `c U(x / s)` in `s` times the box they are `s ℓ` and `c ε`,
//! and the run makes the same decisions, up to rounding (which the hot
//! rungs' long trajectories across a rugged landscape multiply, a
//! hundredfold or more a step: there the first rounds are the same, and
//! the rest the same in law). In them:
//!
//! - the sampling is the paper's HRLA (`alpha = beta = 1`, `b = 10`), and
//!   every rung starts from `h = step_scale / L`, never longer than the
//!   step whose velocity term `h |y|` moves a tenth of the box (the whole
//!   rule where no curvature is measured); `alpha h` within `[1e-8, 50]`;
//! - the ladder is centred on `a_0 = 1 / IQR` of the quenched values
//!   (minima are on the problem's own scale even where random points reach
//!   `1e9`), `±` [`Auto::ladder`] in `ln a`, every rung within `[1e-6,
//!   1e6] / ε`; where the basins have one value (a spread below `1e-9` of
//!   their size), `1 / max(ε, |median|)`;
//! - a quench's first step moves at most `ℓ` in any coordinate and is at
//!   most `ℓ^2 / ε`, and it ends where the decrease its next step would
//!   predict is below `64 eps max(ε, |U|)`: no line search is decided by the
//!   rounding of the values it compares. The initial quenches, before
//!   any curvature is known, take the spread of the initial values for
//!   `ε` and no bound on the first step but `ℓ`.
//!
//! The random numbers of the Metropolis test and of the exchanges are
//! drawn whatever the values compare, and the best falling by less than
//! a quench resolves is no progress for [`Auto::stall`]: values equal up
//! to their rounding never change the run's course.
//!
//! In a box whose sides differ, the sampling, the quenches, the polish
//! and the curvature probes run in the box's **unit coordinates**
//! (`u_i = x_i / w_i`, `w_i` the side of coordinate `i` over the widest:
//! every side as long as the widest), so that one step `h` suits every
//! coordinate; the map is linear, so `exp(-a U)` is the same law there.
//! In a box of equal sides the unit coordinates are the box's own.
//!
//! The evaluation budget covers everything: initial points, probes,
//! steps, quenches and the final polish. A [soft
//! budget](Problem::soft_budget) below it is the one the run plans
//! within, the quench of the best start free to finish past it. The constants of
//! [`Auto::default`] were chosen on the quality benchmark
//! (`bench/quality`, `docs/QUALITY.md`), the same for every problem;
//! [`Auto::parts`] switches parts off for the benchmark's ablations and
//! chooses how a chain leaves its basin ([`Sampling`]).

mod measure;
mod moves;
mod problem;
mod run;
mod scale;
mod settings;
mod storage;

use core::ops::ControlFlow;

use rand_core::{Rng, SeedableRng};

use crate::domain::{Interval, Sides};
use crate::error::Error;
use crate::float::Float;
use crate::optimizer::{Stop, Termination};
use crate::polish::Quencher;
use crate::potential::BatchPotential;

pub use problem::{AutoProgress, Problem, Solution};
pub use settings::{Auto, MAX_STEPS, Parts, Sampling};
pub use storage::AutoStorage;

use problem::AutoStore;

impl<F: Float> Auto<F> {
    /// The number of chains measured best for an evaluation budget:
    /// `budget / 60 000`, at least 4 and at most 16 (few chains, many
    /// rounds each: 4 measured best at `10 000` and `125 000`; see
    /// `docs/QUALITY.md`).
    ///
    /// ```
    /// assert_eq!(hrla::Auto::<f64>::chains_for(10_000), 4);
    /// assert_eq!(hrla::Auto::<f64>::chains_for(125_000), 4);
    /// assert_eq!(hrla::Auto::<f64>::chains_for(10_000_000), 16);
    /// ```
    pub fn chains_for(budget: u64) -> usize {
        (budget / 60_000).clamp(4, 16) as usize
    }

    /// Minimises the [`Problem`] in `store`, with as many chains as it
    /// holds ([`Auto::chains_for`] is the measured choice); chain `c`
    /// draws from the generator of `(problem's seed, c)`.
    ///
    /// The store is either const-generic chains with their L-BFGS storage,
    /// `(&mut [Chain<F, D, R>], &mut Lbfgs<F, D, M>)`, for a
    /// [`Potential<F, D>`](crate::Potential), the solution's point an array
    /// `[F; D]`:
    ///
    /// ```
    /// use hrla::{Auto, Chain, Interval, Lbfgs, Problem, Rastrigin};
    ///
    /// let mut chains: Vec<Chain<f64, 10>> = (0..32).map(|_| Chain::new()).collect();
    /// let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
    /// let domain = Interval::new(-5.12, 5.12)?;
    /// let problem = Problem::new(&Rastrigin, &domain, 125_000).seed(1);
    /// let found = Auto::default().minimize(&problem, (chains.as_mut_slice(), &mut lbfgs))?;
    /// assert!(found.value < 1e-6, "{found:?}");
    /// # Ok::<(), hrla::Error>(())
    /// ```
    ///
    /// or the caller's [`AutoStorage`] at a dimension known at run time,
    /// for a [`BatchPotential<F>`](crate::BatchPotential), with the same
    /// bits as `Chain<F, d, R>`s and an `Lbfgs<F, d, m>`; the solution's
    /// point is a slice of the storage:
    ///
    /// ```
    /// use hrla::{Auto, AutoStorage, Bounds, FnPotential, Problem};
    /// use rand_xoshiro::Xoshiro256PlusPlus;
    /// use rand_core::SeedableRng;
    ///
    /// // A sphere centred at 3 on each coordinate's own scale, in a box
    /// // whose sides run from 10 to 10^6.
    /// let (n, d, m) = (4, 3, 8);
    /// let scale = [10.0, 1e3, 1e6];
    /// let sphere = FnPotential::slices(move |x: &[f64], g: &mut [f64]| {
    ///     let mut u = 0.0;
    ///     for i in 0..x.len() {
    ///         let z = x[i] / scale[i] - 0.3;
    ///         u += z * z;
    ///         g[i] = 2.0 * z / scale[i];
    ///     }
    ///     u
    /// });
    /// let bounds = Bounds::new(vec![0.0; 3], scale.to_vec())?;
    /// let mut floats = vec![0.0; AutoStorage::<f64, Xoshiro256PlusPlus>::floats(n, d, m)];
    /// let mut diverged = vec![false; n];
    /// let mut rngs: Vec<_> = (0..n).map(|_| Xoshiro256PlusPlus::seed_from_u64(0)).collect();
    /// let mut storage = AutoStorage::new(d, m, &mut floats, &mut diverged, &mut rngs)?;
    /// let problem = Problem::new(&sphere, &bounds, 10_000).seed(1);
    /// let found = Auto::default().minimize(&problem, &mut storage)?;
    /// assert!(found.value < 1e-20, "{found}");
    /// assert!((found.x[2] - 3e5).abs() < 1e-3);
    /// # Ok::<(), hrla::Error>(())
    /// ```
    ///
    /// A point where the potential or its gradient is not finite (a NaN,
    /// `+inf`) is infeasible, never fatal: initial points are redrawn
    /// there (up to [`START_TRIES`](crate::START_TRIES) each, within the
    /// budget); a proposal that meets one is rejected (the chain stays in
    /// its basin); a quench's trial points there count as `+inf`. The best
    /// point is always one where `U` and its gradient were finite.
    ///
    /// Errors: no chains ([`Error::Zero`]), a budget below twice the
    /// number of chains ([`Error::Budget`]), no feasible initial point
    /// ([`Error::NonFiniteStart`]), a bad constant or rule
    /// ([`Error::Zero`], [`Error::NotPositive`], [`Error::Negative`],
    /// [`Error::NotFinite`]), a box, potential or `x0` of another dimension
    /// than the storage's ([`Error::Length`]), an `x0` outside the box
    /// ([`Error::OutsideBox`]) or where `U` is not finite
    /// ([`Error::NotFinite`] naming `x0`), and a potential that is
    /// unbounded below ([`Error::UnboundedBelow`]).
    pub fn minimize<P, B, S>(
        &self,
        problem: &Problem<'_, F, P, B>,
        store: S,
    ) -> Result<Solution<F, S::Point>, Error>
    where
        P: ?Sized,
        B: Sides<F> + ?Sized,
        S: AutoStore<F, P>,
    {
        store.solve(self, problem, |_| ControlFlow::Continue(()))
    }

    /// [`minimize`](Auto::minimize) with an observer: called once after
    /// the initial points, then after every HRLA step of a chain, every
    /// quench and the final polish, with
    /// the best so far and whether it fell since the last call. Returning
    /// `ControlFlow::Break(())` ends the run at once with the best so far
    /// and [`Termination::Observer`]: a time limit or a cancellation
    /// (Ctrl-C).
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use hrla::{Auto, Chain, Interval, Lbfgs, Problem, Rastrigin, Termination};
    ///
    /// let mut chains: Vec<Chain<f64, 4>> = (0..8).map(|_| Chain::new()).collect();
    /// let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
    /// let domain = Interval::new(-5.12, 5.12)?;
    /// // A budget that never runs out: the observer ends the run.
    /// let problem = Problem::new(&Rastrigin, &domain, u64::MAX).seed(1);
    /// let found = Auto::default().minimize_with(
    ///     &problem,
    ///     (chains.as_mut_slice(), &mut lbfgs),
    ///     |p| if p.evaluations > 50_000 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) },
    /// )?;
    /// assert_eq!(found.termination, Termination::Observer);
    /// # Ok::<(), hrla::Error>(())
    /// ```
    pub fn minimize_with<P, B, S, O>(
        &self,
        problem: &Problem<'_, F, P, B>,
        store: S,
        observer: O,
    ) -> Result<Solution<F, S::Point>, Error>
    where
        P: ?Sized,
        B: Sides<F> + ?Sized,
        S: AutoStore<F, P>,
        O: FnMut(&AutoProgress<'_, F>) -> ControlFlow<()>,
    {
        store.solve(self, problem, observer)
    }

    /// The one run of every store: checks, start (chain 0 at the
    /// problem's `x0` where given), solve, and the termination; the best
    /// point is left in the buffers' `best`. `potential` is the problem's,
    /// as the store evaluates it.
    fn drive<Q, P, B, S, L, O>(
        &self,
        potential: &Q,
        problem: &Problem<'_, F, P, B>,
        chains: &mut S,
        lbfgs: &mut L,
        buffers: run::Buffers<'_, F>,
        observer: O,
    ) -> Result<run::Found<F>, Error>
    where
        Q: BatchPotential<F> + ?Sized,
        P: ?Sized,
        B: Sides<F> + ?Sized,
        S: run::Chains<F> + ?Sized,
        S::Rng: Rng + SeedableRng + 'static,
        L: Quencher<F> + ?Sized,
        O: FnMut(&run::Seen<'_, F>) -> ControlFlow<()>,
    {
        let (hard, budget) = self.check(problem, chains, buffers.best.len())?;
        let mut run = run::Run::start(
            self,
            potential,
            problem.domain,
            problem.x0,
            budget,
            problem.seed,
            chains,
            lbfgs,
            buffers,
            observer,
        )?
        .with_rules(problem.rules, problem.converge)
        .with_overrun(hard);
        let ended = run.solve();
        // A stop can read as an infeasible point the method steps over (a
        // quench that cannot start): it ends the run however it ended.
        if run.stopped() {
            return Err(Error::Stopped);
        }
        let termination = match ended {
            ControlFlow::Continue(()) => run.ended(),
            ControlFlow::Break(run::Stop::Observer) => Termination::Observer,
            ControlFlow::Break(run::Stop::Target) => Termination::Target,
            ControlFlow::Break(run::Stop::Budget) => Termination::Evaluations,
            ControlFlow::Break(run::Stop::Failed(e)) => return Err(e),
        };
        Ok(run.found(termination))
    }

    /// The settings, the rules and the problem checked for a run of
    /// `chains` in dimension `dim`: the hard budget and the one planned
    /// within (the soft budget where lower).
    fn check<P, B, S>(
        &self,
        problem: &Problem<'_, F, P, B>,
        chains: &S,
        dim: usize,
    ) -> Result<(u64, u64), Error>
    where
        P: ?Sized,
        B: Sides<F> + ?Sized,
        S: run::Chains<F> + ?Sized,
    {
        self.validate()?;
        // No round at all is a run of its starts and polish.
        Stop {
            steps: None,
            ..problem.rules
        }
        .validate()?;
        if problem.converge == Some(0) {
            return Err(Error::Zero {
                name: "convergence window",
            });
        }
        let n = chains.len();
        if n == 0 {
            return Err(Error::Zero { name: "chains" });
        }
        // Every side as `Bounds::new` and `Interval::new` check theirs: a
        // caller's own `Sides` gets no pass.
        let domain = problem.domain;
        for i in 0..chains.x(0).len() {
            let (lo, hi) = domain.side(i);
            Interval::new(lo, hi)?;
        }
        let (hard, budget) = (
            problem.budget,
            problem
                .soft
                .map_or(problem.budget, |s| s.min(problem.budget)),
        );
        if budget < 2 * n as u64 {
            return Err(Error::Budget {
                budget,
                chains: 2 * n,
            });
        }
        if let Some(x0) = problem.x0 {
            check_start(x0, domain, dim)?;
        }
        Ok((hard, budget))
    }
}

/// A caller's start: `d` coordinates, each within its side of the box
/// ([`Error::Length`], [`Error::OutsideBox`] naming `x0`; a NaN is outside).
fn check_start<F: Float, B: Sides<F> + ?Sized>(
    x0: &[F],
    domain: &B,
    d: usize,
) -> Result<(), Error> {
    if x0.len() != d {
        return Err(Error::Length {
            name: "x0",
            expected: d,
            got: x0.len(),
        });
    }
    for (index, &value) in x0.iter().enumerate() {
        let (lo, hi) = domain.side(index);
        if !(lo <= value && value <= hi) {
            return Err(Error::OutsideBox {
                index,
                value: value.to_f64(),
                lo: lo.to_f64(),
                hi: hi.to_f64(),
            });
        }
    }
    Ok(())
}

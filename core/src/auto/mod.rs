//! The default solver: Langevin basin hopping on a ladder of temperatures,
//! with no setting to tune.
//!
//! Every chain holds a basin: a point quenched to a local minimum, and its
//! value. A round moves each chain by named steps:
//!
//! 1. **Global move** (with probability [`Auto::jump_rate`]): from its
//!    basin, a differential move `x + γ (x_i - x_j)` along the difference
//!    of two other chains' basins (`γ` uniform in `[0.5, 1]`). Its length
//!    and direction come from where the chains are, not from the
//!    coordinate axes, so the solver is rotation invariant as CMA-ES and
//!    differential evolution are.
//! 2. **Sampling**: [`Auto::steps`] HRLA steps at the chain's inverse
//!    temperature `a_c`, from there, with the momentum `y` the chain kept
//!    from its last trajectory. The exact OU step is stable at large `h`,
//!    so the trajectory follows the gradient's trend across several basins.
//!    Each rung's step is steered to accept [`Auto::accept`] of its
//!    proposals (half): after every proposal `ln h_c` moves up if it was
//!    accepted and down if not (a Robbins–Monro step, as adaptive
//!    Metropolis samplers and basin hopping steer theirs), so hot rungs
//!    lengthen their trajectories until they reach other basins, and cold
//!    ones shorten theirs.
//! 3. **Quench**: L-BFGS from the trajectory's end until it converges
//!    (at most [`Auto::quench`] evaluations): the basin it fell into.
//! 4. **Acceptance**: Metropolis on the quenched values at `a_c`: the chain
//!    moves to the new basin with probability `min(1, exp(-a_c ΔU))`.
//!
//! After each round, **tempering**: adjacent rungs of the ladder swap their
//! basins with the replica-exchange probability, so good basins flow to the
//! cold chains and the hot ones keep exploring. When the best has not
//! fallen for [`Auto::stall`] rounds, the hotter half **restarts** uniformly
//! in the box. At the end the best point is **polished** by L-BFGS until it
//! converges: the returned point is a local minimum to the float type's
//! precision (unless the observer stopped the run, or the budget ran out
//! within the polish).
//!
//! The settings are **measured** on the problem, after the initial points
//! are quenched ([`measure`]): the ladder is centred on `a_0 = 1 / IQR` of
//! the quenched values (minima are on the problem's own scale even where
//! random points reach `1e9`), `±` [`Auto::ladder`] in `ln a`; the step is
//! `h = step_scale / L`, `L` the median curvature along random directions
//! at the basins' bottoms, where it is positive even on landscapes with
//! flat stretches; every rung starts from it.
//!
//! In a box whose sides differ, the sampling, the quenches, the polish
//! and the curvature probes run in the box's **unit coordinates**
//! (`u_i = x_i / w_i`, `w_i` the side of coordinate `i` over the widest:
//! every side as long as the widest), so that one step `h` suits every
//! coordinate; the map is linear, so `exp(-a U)` is the same law there.
//! In a box of equal sides the unit coordinates are the box's own.
//!
//! The evaluation budget covers everything: initial points, probes,
//! steps, quenches, restarts and the final polish. The constants of
//! [`Auto::default`] were chosen on the quality benchmark
//! (`bench/quality`, `docs/QUALITY.md`), the same for every problem;
//! [`Auto::parts`] switches parts off for the benchmark's ablations.

mod measure;
mod moves;
mod run;
mod scale;
mod settings;

use core::fmt;
use core::ops::ControlFlow;

use rand_core::{Rng, SeedableRng};

use crate::domain::{Interval, Sides};
use crate::error::Error;
use crate::float::Float;
use crate::optimizer::{Chain, Termination};
use crate::polish::{Arrays, Lbfgs};
use crate::potential::BatchPotential;
use crate::potential::traits::Potential;
use crate::schedule::Schedule;

pub use settings::{Auto, MAX_STEPS, Parts, Sampling};
pub use storage::AutoStorage;

mod storage;

/// An inverse temperature that the caller changes between steps: a
/// schedule for runs whose temperature adapts to the run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tempering<F>(pub F);

impl<F: Float> Schedule<F> for Tempering<F> {
    #[inline]
    fn inverse_temperature(&self, _k: u64) -> F {
        self.0
    }
}

/// What a run of [`Auto`] found, its best point as `X`: an array in
/// [`Solution`] (from [`Auto::minimize`]), a slice of the caller's storage
/// in [`FlatSolution`] (from [`Auto::minimize_flat`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoSolution<F, X> {
    /// The best point.
    pub x: X,
    /// `U(x)`.
    pub value: F,
    /// Evaluations used, all included (at most the budget).
    pub evaluations: u64,
    /// Rounds done.
    pub rounds: u64,
    /// The step size measured (`step_scale / L`), from which every rung
    /// started.
    pub step: F,
    /// The inverse temperature of the coldest chain.
    pub inverse_temperature: F,
    /// Why the run ended: [`Termination::Evaluations`] (the budget is
    /// spent) or [`Termination::Observer`].
    pub termination: Termination,
    /// Chains whose last proposal met a point where `U` or its gradient
    /// is not finite (the chain stayed in its basin).
    pub diverged_chains: usize,
    /// Chains in the run.
    pub chains: usize,
}

/// What [`Auto::minimize`] found.
pub type Solution<F, const D: usize> = AutoSolution<F, [F; D]>;

/// What [`Auto::minimize_flat`] found: the best point borrowed from the
/// storage.
pub type FlatSolution<'a, F> = AutoSolution<F, &'a [F]>;

impl<F, X> AutoSolution<F, X> {
    /// Whether every chain's last proposal met an infeasible point. Not a
    /// failure: a rejected proposal leaves its chain in its feasible
    /// basin, and the best point is feasible and polished either way (a
    /// run that finds no feasible point at all is an error, not a
    /// solution).
    pub fn all_diverged(&self) -> bool {
        self.diverged_chains == self.chains
    }
}

impl<F: Float, X> fmt::Display for AutoSolution<F, X> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        run::Found {
            value: self.value,
            evaluations: self.evaluations,
            rounds: self.rounds,
            step: self.step,
            inverse_temperature: self.inverse_temperature,
            termination: self.termination,
            diverged_chains: self.diverged_chains,
            chains: self.chains,
        }
        .fmt(f)
    }
}

impl<F: Float> fmt::Display for run::Found<F> {
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

/// What the observer of a run of [`Auto`] sees, the best point as `X`:
/// an array in [`AutoProgress`] (for [`Auto::minimize_with`]), a slice in
/// [`FlatAutoProgress`] (for [`Auto::minimize_flat_with`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoProgressOf<'a, F, X: ?Sized> {
    /// Evaluations so far, all included.
    pub evaluations: u64,
    /// Rounds done.
    pub rounds: u64,
    /// The best point so far.
    pub x: &'a X,
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

/// What the observer of [`Auto::minimize_with`] sees.
pub type AutoProgress<'a, F, const D: usize> = AutoProgressOf<'a, F, [F; D]>;

/// What the observer of [`Auto::minimize_flat_with`] sees: the best point
/// as a slice.
pub type FlatAutoProgress<'a, F> = AutoProgressOf<'a, F, [F]>;

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

    /// Minimises `potential` over the box `domain` within `budget`
    /// evaluations, with as many chains as `chains` holds
    /// ([`Auto::chains_for`] is the measured choice) and L-BFGS storage
    /// `lbfgs`; chain `c` draws from the generator of `(seed, c)`.
    ///
    /// ```
    /// use hrla::{Auto, Chain, Interval, Lbfgs, Rastrigin};
    ///
    /// let mut chains: Vec<Chain<f64, 10>> = (0..32).map(|_| Chain::new()).collect();
    /// let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
    /// let found = Auto::default().minimize(
    ///     &Rastrigin,
    ///     Interval::new(-5.12, 5.12)?,
    ///     125_000,
    ///     1,
    ///     &mut chains,
    ///     &mut lbfgs,
    /// )?;
    /// assert!(found.value < 1e-6, "{found:?}");
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
    /// ([`Error::NonFiniteStart`]), a bad constant ([`Error::Zero`],
    /// [`Error::NotPositive`]), and a potential that is unbounded below
    /// ([`Error::UnboundedBelow`]).
    pub fn minimize<P, const D: usize, R, const M: usize>(
        &self,
        potential: &P,
        domain: Interval<F>,
        budget: u64,
        seed: u64,
        chains: &mut [Chain<F, D, R>],
        lbfgs: &mut Lbfgs<F, D, M>,
    ) -> Result<Solution<F, D>, Error>
    where
        P: Potential<F, D> + ?Sized,
        R: Rng + SeedableRng + 'static,
    {
        self.minimize_with(potential, domain, budget, seed, chains, lbfgs, |_| {
            ControlFlow::Continue(())
        })
    }

    /// [`minimize`](Auto::minimize) with an observer: called once after
    /// the initial points, then after every HRLA step of a chain, every
    /// quench, every restart and the final polish, with
    /// the best so far and whether it fell since the last call. Returning
    /// `ControlFlow::Break(())` ends the run at once with the best so far
    /// and [`Termination::Observer`]: a time limit, a cancellation (Ctrl-C)
    /// or a target.
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use hrla::{Auto, Chain, Interval, Lbfgs, Rastrigin, Termination};
    ///
    /// let mut chains: Vec<Chain<f64, 4>> = (0..8).map(|_| Chain::new()).collect();
    /// let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
    /// // A budget that never runs out: the observer ends the run.
    /// let found = Auto::default().minimize_with(
    ///     &Rastrigin,
    ///     Interval::new(-5.12, 5.12)?,
    ///     u64::MAX,
    ///     1,
    ///     &mut chains,
    ///     &mut lbfgs,
    ///     |p| if p.evaluations > 50_000 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) },
    /// )?;
    /// assert_eq!(found.termination, Termination::Observer);
    /// # Ok::<(), hrla::Error>(())
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn minimize_with<P, const D: usize, R, const M: usize, O>(
        &self,
        potential: &P,
        domain: Interval<F>,
        budget: u64,
        seed: u64,
        chains: &mut [Chain<F, D, R>],
        lbfgs: &mut Lbfgs<F, D, M>,
        observer: O,
    ) -> Result<Solution<F, D>, Error>
    where
        P: Potential<F, D> + ?Sized,
        R: Rng + SeedableRng + 'static,
        O: FnMut(&AutoProgress<'_, F, D>) -> ControlFlow<()>,
    {
        self.solve_const(
            potential, domain, None, budget, seed, chains, lbfgs, observer,
        )
    }

    /// [`minimize_with`](Auto::minimize_with) with chain 0 starting at
    /// `x0` instead of a uniform draw (the other chains draw theirs as
    /// without it): a guess the run starts from, as scipy's `x0`. It costs
    /// the one evaluation chain 0's draw would have. The other chains, and
    /// so the run, differ from a run without `x0` only through chain 0.
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use hrla::{Auto, Chain, Interval, Lbfgs, Rastrigin};
    ///
    /// let mut chains: Vec<Chain<f64, 6>> = (0..4).map(|_| Chain::new()).collect();
    /// let mut lbfgs: Lbfgs<f64, 6, 8> = Lbfgs::new();
    /// // Started at the global minimum, a tiny budget keeps it.
    /// let found = Auto::default().minimize_from(
    ///     &Rastrigin,
    ///     Interval::new(-5.12, 5.12)?,
    ///     &[0.0; 6],
    ///     100,
    ///     1,
    ///     &mut chains,
    ///     &mut lbfgs,
    ///     |_| ControlFlow::Continue(()),
    /// )?;
    /// assert_eq!(found.value, 0.0);
    /// # Ok::<(), hrla::Error>(())
    /// ```
    ///
    /// Errors: those of [`minimize`](Auto::minimize), and a start that is
    /// not one the caller can mean: outside the box or NaN in a
    /// coordinate ([`Error::OutsideBox`]), or a point where `U` or its
    /// gradient is not finite ([`Error::NotFinite`] naming `x0`: it is
    /// not redrawn, since the caller chose it).
    #[allow(clippy::too_many_arguments)]
    pub fn minimize_from<P, const D: usize, R, const M: usize, O>(
        &self,
        potential: &P,
        domain: Interval<F>,
        x0: &[F; D],
        budget: u64,
        seed: u64,
        chains: &mut [Chain<F, D, R>],
        lbfgs: &mut Lbfgs<F, D, M>,
        observer: O,
    ) -> Result<Solution<F, D>, Error>
    where
        P: Potential<F, D> + ?Sized,
        R: Rng + SeedableRng + 'static,
        O: FnMut(&AutoProgress<'_, F, D>) -> ControlFlow<()>,
    {
        self.solve_const(
            potential,
            domain,
            Some(x0),
            budget,
            seed,
            chains,
            lbfgs,
            observer,
        )
    }

    /// The const-generic entry points' run.
    #[allow(clippy::too_many_arguments)]
    fn solve_const<P, const D: usize, R, const M: usize, O>(
        &self,
        potential: &P,
        domain: Interval<F>,
        x0: Option<&[F; D]>,
        budget: u64,
        seed: u64,
        chains: &mut [Chain<F, D, R>],
        lbfgs: &mut Lbfgs<F, D, M>,
        mut observer: O,
    ) -> Result<Solution<F, D>, Error>
    where
        P: Potential<F, D> + ?Sized,
        R: Rng + SeedableRng + 'static,
        O: FnMut(&AutoProgress<'_, F, D>) -> ControlFlow<()>,
    {
        let mut floats = [[F::ZERO; D]; 7];
        let buffers = run::Buffers::new(D, floats.as_flattened_mut());
        let observe = |seen: &run::Seen<'_, F>| match <&[F; D]>::try_from(seen.x) {
            Ok(x) => observer(&AutoProgress {
                evaluations: seen.evaluations,
                rounds: seen.rounds,
                x,
                value: seen.value,
                improved: seen.improved,
                inverse_temperature: seen.inverse_temperature,
                diverged_chains: seen.diverged_chains,
            }),
            // Every point of a run of `Chain<F, D>`s has length D.
            Err(_) => ControlFlow::Continue(()),
        };
        let found = self.drive(
            &Arrays::<_, D>(potential),
            &domain,
            x0.map(|x| x.as_slice()),
            budget,
            seed,
            chains,
            lbfgs,
            buffers,
            observe,
        )?;
        Ok(Solution {
            x: floats[0],
            value: found.value,
            evaluations: found.evaluations,
            rounds: found.rounds,
            step: found.step,
            inverse_temperature: found.inverse_temperature,
            termination: found.termination,
            diverged_chains: found.diverged_chains,
            chains: found.chains,
        })
    }

    /// Minimises `potential` over the box `domain` (an [`Interval`], a
    /// [`Bounds`](crate::Bounds) with a side per coordinate) at the
    /// dimension of `storage`, in storage the caller lends
    /// ([`AutoStorage`]): [`minimize`](Auto::minimize) at any dimension,
    /// with the same bits as `Chain<F, d, R>`s and an `Lbfgs<F, d, m>`.
    /// The potential is evaluated through the batch seam.
    ///
    /// ```
    /// use hrla::{Auto, AutoStorage, Bounds, FnPotential};
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
    /// let found = Auto::default().minimize_flat(&sphere, &bounds, 10_000, 1, &mut storage)?;
    /// assert!(found.value < 1e-20, "{found}");
    /// assert!((found.x[2] - 3e5).abs() < 1e-3);
    /// # Ok::<(), hrla::Error>(())
    /// ```
    ///
    /// Errors: those of [`minimize`](Auto::minimize), and
    /// [`Error::Length`] for a box or a potential made for another
    /// dimension than the storage's.
    pub fn minimize_flat<'s, P, B, R>(
        &self,
        potential: &P,
        domain: &B,
        budget: u64,
        seed: u64,
        storage: &'s mut AutoStorage<'_, F, R>,
    ) -> Result<FlatSolution<'s, F>, Error>
    where
        P: BatchPotential<F> + ?Sized,
        B: Sides<F> + ?Sized,
        R: Rng + SeedableRng + 'static,
    {
        self.minimize_flat_with(potential, domain, budget, seed, storage, |_| {
            ControlFlow::Continue(())
        })
    }

    /// [`minimize_flat`](Auto::minimize_flat) with an observer, called as
    /// [`minimize_with`](Auto::minimize_with)'s is.
    pub fn minimize_flat_with<'s, P, B, R, O>(
        &self,
        potential: &P,
        domain: &B,
        budget: u64,
        seed: u64,
        storage: &'s mut AutoStorage<'_, F, R>,
        observer: O,
    ) -> Result<FlatSolution<'s, F>, Error>
    where
        P: BatchPotential<F> + ?Sized,
        B: Sides<F> + ?Sized,
        R: Rng + SeedableRng + 'static,
        O: FnMut(&FlatAutoProgress<'_, F>) -> ControlFlow<()>,
    {
        self.solve_flat(potential, domain, None, budget, seed, storage, observer)
    }

    /// [`minimize_flat_with`](Auto::minimize_flat_with) with chain 0
    /// starting at `x0`, as [`minimize_from`](Auto::minimize_from); `x0`
    /// has the storage's dimension ([`Error::Length`] otherwise).
    #[allow(clippy::too_many_arguments)]
    pub fn minimize_flat_from<'s, P, B, R, O>(
        &self,
        potential: &P,
        domain: &B,
        x0: &[F],
        budget: u64,
        seed: u64,
        storage: &'s mut AutoStorage<'_, F, R>,
        observer: O,
    ) -> Result<FlatSolution<'s, F>, Error>
    where
        P: BatchPotential<F> + ?Sized,
        B: Sides<F> + ?Sized,
        R: Rng + SeedableRng + 'static,
        O: FnMut(&FlatAutoProgress<'_, F>) -> ControlFlow<()>,
    {
        self.solve_flat(potential, domain, Some(x0), budget, seed, storage, observer)
    }

    /// The flat entry points' run.
    #[allow(clippy::too_many_arguments)]
    fn solve_flat<'s, P, B, R, O>(
        &self,
        potential: &P,
        domain: &B,
        x0: Option<&[F]>,
        budget: u64,
        seed: u64,
        storage: &'s mut AutoStorage<'_, F, R>,
        mut observer: O,
    ) -> Result<FlatSolution<'s, F>, Error>
    where
        P: BatchPotential<F> + ?Sized,
        B: Sides<F> + ?Sized,
        R: Rng + SeedableRng + 'static,
        O: FnMut(&FlatAutoProgress<'_, F>) -> ControlFlow<()>,
    {
        let d = storage.dim();
        for (name, dimension) in [
            ("box sides", domain.dimension()),
            ("potential", potential.batch_dimension()),
        ] {
            if let Some(got) = dimension
                && got != d
            {
                return Err(Error::Length {
                    name,
                    expected: d,
                    got,
                });
            }
        }
        let storage::Lent {
            mut chains,
            buffers,
            lbfgs,
        } = storage.parts();
        let mut lbfgs = lbfgs?;
        let observe = |seen: &run::Seen<'_, F>| {
            observer(&FlatAutoProgress {
                evaluations: seen.evaluations,
                rounds: seen.rounds,
                x: seen.x,
                value: seen.value,
                improved: seen.improved,
                inverse_temperature: seen.inverse_temperature,
                diverged_chains: seen.diverged_chains,
            })
        };
        let found = self.drive(
            potential,
            domain,
            x0,
            budget,
            seed,
            &mut chains,
            &mut lbfgs,
            buffers,
            observe,
        )?;
        Ok(FlatSolution {
            x: storage.best(),
            value: found.value,
            evaluations: found.evaluations,
            rounds: found.rounds,
            step: found.step,
            inverse_temperature: found.inverse_temperature,
            termination: found.termination,
            diverged_chains: found.diverged_chains,
            chains: found.chains,
        })
    }

    /// The one run of every entry point: checks, start (chain 0 at `x0`
    /// where given), solve, and the termination; the best point is left
    /// in the buffers' `best`.
    #[allow(clippy::too_many_arguments)]
    fn drive<P, B, S, L, O>(
        &self,
        potential: &P,
        domain: &B,
        x0: Option<&[F]>,
        budget: u64,
        seed: u64,
        chains: &mut S,
        lbfgs: &mut L,
        buffers: run::Buffers<'_, F>,
        observer: O,
    ) -> Result<run::Found<F>, Error>
    where
        P: BatchPotential<F> + ?Sized,
        B: Sides<F> + ?Sized,
        S: run::Chains<F> + ?Sized,
        S::Rng: Rng + SeedableRng + 'static,
        L: run::Quencher<F> + ?Sized,
        O: FnMut(&run::Seen<'_, F>) -> ControlFlow<()>,
    {
        self.validate()?;
        let n = chains.len();
        if n == 0 {
            return Err(Error::Zero { name: "chains" });
        }
        // Every side as `Bounds::new` and `Interval::new` check theirs: a
        // caller's own `Sides` gets no pass.
        for i in 0..chains.x(0).len() {
            let (lo, hi) = domain.side(i);
            Interval::new(lo, hi)?;
        }
        if budget < 2 * n as u64 {
            return Err(Error::Budget {
                budget,
                chains: 2 * n,
            });
        }
        if let Some(x0) = x0 {
            check_start(x0, domain, buffers.best.len())?;
        }
        let mut run = run::Run::start(
            self, potential, domain, x0, budget, seed, chains, lbfgs, buffers, observer,
        )?;
        let termination = match run.solve() {
            ControlFlow::Continue(()) => Termination::Evaluations,
            ControlFlow::Break(run::Stop::Observer) => Termination::Observer,
            ControlFlow::Break(run::Stop::Budget) => Termination::Evaluations,
            ControlFlow::Break(run::Stop::Failed(e)) => return Err(e),
        };
        Ok(run.found(termination))
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

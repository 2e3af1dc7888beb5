//! The default solver: rounds of Langevin sampling, quenches and
//! one-coordinate restarts, with no setting to tune.
//!
//! The paper leaves `a`, `h` and the cooling open, and its settings are
//! Rastrigin's: `a = 4` means nothing on another function's scale, and
//! `h = 0.01` is unstable on a stiff one. [`Auto`] measures what it needs
//! from the problem:
//!
//! - **`h` from the curvature.** At each initial point the gradient is
//!   differenced along one coordinate (`j = c mod D` for chain `c`); with
//!   `L` the median of `|Δ∂_j U| / δ`, `h = step_scale / L` (the position's
//!   drift `-h ∇U` is then a stable gradient step on the typical
//!   curvature).
//! - **Rounds.** The budget is spread over `rounds` rounds of HRLA steps of
//!   every chain. After each, every chain is quenched
//!   ([`Optimizer::quench`](crate::Optimizer::quench): an L-BFGS polish of
//!   a copy of its current point, which records the bottom of its basin as
//!   the chain's best), so the best point is always a local minimum to the
//!   float type's precision.
//! - **Restarts** (global moves). Then the `restarts` chains in the worst
//!   basins start again from the best point with one coordinate redrawn
//!   uniformly in the box: the next round explores from there and its
//!   quench finds that point's basin. On separable landscapes this walks
//!   coordinate by coordinate to the global basin, as dual annealing's
//!   one-coordinate visits do.
//! - **Temperature.** `a` starts at `1 / IQR(U)` over the initial points
//!   and follows how many chains changed basin in a round: divided by
//!   `factor` (hotter) when fewer than `low_rate` did, multiplied (colder)
//!   when more than `high_rate` did. A restarted chain counts as having
//!   changed basin, so with every chain restarted (the default) `a` rises
//!   by `factor` each round, up to `1e6`: a geometric cooling whose start
//!   is set by the problem's scale.
//!
//! The evaluation budget covers everything: the curvature probes, the
//! initial points, the steps, the quenches and the restarts. The constants
//! of [`Auto::default`] were chosen on the quality benchmark
//! (`bench/quality`, `docs/QUALITY.md`), the same for every function.

use core::fmt;
use core::ops::ControlFlow;

use rand_core::{Rng, SeedableRng};

use crate::domain::Interval;
use crate::error::Error;
use crate::float::Float;
use crate::optimizer::{Builder, Chain, Optimizer, Stop, Termination, splitmix64};
use crate::polish::{Lbfgs, PolishSettings};
use crate::potential::traits::Potential;
use crate::sampler::Hrla;
use crate::schedule::Schedule;

/// An inverse temperature that the caller changes between steps: the
/// schedule of [`Auto`]'s adaptive tempering.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tempering<F>(pub F);

impl<F: Float> Schedule<F> for Tempering<F> {
    #[inline]
    fn inverse_temperature(&self, _k: u64) -> F {
        self.0
    }
}

/// The default solver's constants (see the module docs of `auto` in the
/// crate's source, and [`Auto::minimize`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Auto<F> {
    /// Rounds of sampling the budget is spread over: each round takes
    /// `budget / (rounds N)` steps of the `N` chains (at least 10), then
    /// quenches them.
    pub rounds: u64,
    /// Evaluations per quench, at most.
    pub quench: u64,
    /// Heat when fewer than this fraction of chains changed basin in a
    /// round.
    pub low_rate: F,
    /// Cool when more than this fraction did.
    pub high_rate: F,
    /// The factor by which `a` changes.
    pub factor: F,
    /// `h = step_scale / L`, `L` the typical curvature at the starts.
    pub step_scale: F,
    /// Chains that restart, after every round, from the best point with one
    /// coordinate redrawn uniformly in the box: the ones in the worst basins
    /// (at most the run's chains, and 64).
    pub restarts: usize,
}

impl<F: Float> Default for Auto<F> {
    /// 50 rounds, quenches of up to 100 evaluations, every chain restarted
    /// after each round, heat below 20% of chains moving, cool above 50%,
    /// by 1.5; `h = 0.5 / L`.
    fn default() -> Self {
        Self {
            rounds: 50,
            quench: 100,
            low_rate: F::from_f64(0.2),
            high_rate: F::HALF,
            factor: F::from_f64(1.5),
            step_scale: F::HALF,
            restarts: 64,
        }
    }
}

/// What [`Auto::minimize`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solution<F, const D: usize> {
    /// The best point.
    pub x: [F; D],
    /// `U(x)`.
    pub value: F,
    /// Evaluations used, all included (at most the budget).
    pub evaluations: u64,
    /// Rounds of sampling done.
    pub rounds: u64,
    /// The step size chosen.
    pub step: F,
    /// The inverse temperature at the end.
    pub inverse_temperature: F,
    /// Why the run ended: [`Termination::Evaluations`] (the budget is
    /// spent) or [`Termination::Observer`].
    pub termination: Termination,
    /// Chains diverged at the end (each restarts after its round, so this
    /// counts those that diverged in the last one).
    pub diverged_chains: usize,
    /// Chains in the run.
    pub chains: usize,
}

impl<F, const D: usize> Solution<F, D> {
    /// Whether every chain had diverged at the end: the best point is then
    /// the lowest feasible point found before, and the last round found
    /// nowhere feasible to go.
    pub fn all_diverged(&self) -> bool {
        self.diverged_chains == self.chains
    }
}

impl<F: Float, const D: usize> fmt::Display for Solution<F, D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: best U = {} after {} evaluations in {} rounds (h = {}, a = {}); \
             {} of {} chains diverged",
            self.termination,
            self.value,
            self.evaluations,
            self.rounds,
            self.step,
            self.inverse_temperature,
            self.diverged_chains,
            self.chains,
        )?;
        if self.all_diverged() {
            f.write_str(" (all: the best is the last feasible point found)")?;
        }
        Ok(())
    }
}

/// What the observer of [`Auto::minimize_with`] sees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoProgress<'a, F, const D: usize> {
    /// Evaluations so far, all included.
    pub evaluations: u64,
    /// Rounds of sampling done.
    pub rounds: u64,
    /// The best point so far.
    pub x: &'a [F; D],
    /// `U` there.
    pub value: F,
    /// Whether the best value fell since the observer's last call (`true`
    /// at the first call).
    pub improved: bool,
    /// The inverse temperature now.
    pub inverse_temperature: F,
    /// Chains diverged now.
    pub diverged_chains: usize,
}

/// The observer of a run and what it has seen.
struct Watch<O, F> {
    observer: O,
    /// The best value at the last call; `None` before the first.
    seen: Option<F>,
    /// Evaluations of the curvature probes, done outside the optimiser.
    probes: u64,
}

impl<O, F: Float> Watch<O, F> {
    fn call<P, S, C, St, const D: usize, R, B>(
        &mut self,
        opt: &Optimizer<F, P, S, C, St, D, R, B>,
        rounds: u64,
    ) -> ControlFlow<()>
    where
        O: FnMut(&AutoProgress<'_, F, D>) -> ControlFlow<()>,
        P: Potential<F, D>,
        S: crate::sampler::Sampler<F>,
        C: Schedule<F>,
        St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
        R: Rng + 'static,
        B: crate::domain::Domain<F, D>,
    {
        let best = opt.best();
        let improved = self.seen.is_none_or(|v| best.value < v);
        self.seen = Some(best.value);
        (self.observer)(&AutoProgress {
            evaluations: opt.evaluations() + self.probes,
            rounds,
            x: &best.x,
            value: best.value,
            improved,
            inverse_temperature: opt.schedule().inverse_temperature(0),
            diverged_chains: opt.diverged_chains(),
        })
    }
}

impl<F: Float> Auto<F> {
    /// The number of chains measured best for an evaluation budget:
    /// `budget / 4 000`, at least 8 and at most 32 (few chains, many
    /// rounds each, on small budgets; 32 from `B = 128 000` on; see
    /// `docs/QUALITY.md`).
    ///
    /// ```
    /// assert_eq!(hrla::Auto::<f64>::chains_for(10_000), 8);
    /// assert_eq!(hrla::Auto::<f64>::chains_for(125_000), 31);
    /// assert_eq!(hrla::Auto::<f64>::chains_for(10_000_000), 32);
    /// ```
    pub fn chains_for(budget: u64) -> usize {
        (budget / 4_000).clamp(8, 32) as usize
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
    /// there (see [`Builder::build`]); a chain that steps there diverges
    /// and restarts after its round, like the chains in the worst basins;
    /// a quench's trial points there count as `+inf`. The best point is
    /// always one where `U` and its gradient were finite.
    ///
    /// Errors: those of [`Builder::build`] (no chains, a budget below
    /// twice the number of chains: [`Error::Budget`], no feasible initial
    /// point: [`Error::NonFiniteStart`]), a bad constant ([`Error::Zero`],
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
    /// the initial points, then after every step of the chains, every
    /// quench and every round's restarts (so at least every
    /// `max(N, quench, restarts)` evaluations), with the best so far and
    /// whether it fell since the last call. Returning
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
        self.validate()?;
        let n = chains.len();
        if n == 0 {
            return Err(Error::Zero { name: "chains" });
        }
        if budget < 2 * n as u64 {
            return Err(Error::Budget {
                budget,
                chains: 2 * n,
            });
        }
        // The initial points, then one probe each (of at most 64 chains,
        // evenly spread: their median suffices) for the curvature.
        let m = n.min(64);
        let probes = m as u64;
        let mut opt = Builder::new(
            potential,
            Hrla::paper(F::from_f64(0.01))?,
            Tempering(F::ONE),
            domain,
        )
        .domain(domain)
        .seed(seed)
        .stop(Stop::new().evaluations(budget - probes))
        .build(&mut *chains)?;
        let (l, iqr) = {
            let delta = F::from_f64(1e-4) * (domain.hi() - domain.lo());
            let mut curvature = [F::ZERO; 64];
            let mut values = [F::ZERO; 64];
            let mut probe = [F::ZERO; D];
            let mut grad = [F::ZERO; D];
            for (i, c) in (0..m).map(|i| (i, i * n / m)) {
                let chain = &opt.chains()[c];
                let j = c % D.max(1);
                probe.copy_from_slice(chain.x());
                probe[j] += if probe[j] + delta <= domain.hi() {
                    delta
                } else {
                    -delta
                };
                potential.value_and_gradient(&probe, &mut grad);
                let k = ((grad[j] - chain.gradient()[j]) / delta).abs();
                curvature[i] = if k.is_finite() { k } else { F::INFINITY };
                values[i] = chain.value();
            }
            (
                median(&mut curvature[..m]),
                quartile_spread(&mut values[..m]),
            )
        };
        let (lo_h, hi_h) = (F::from_f64(1e-8), F::from_f64(50.0));
        let h = clamp(self.step_scale / positive_or(l, F::ONE), lo_h, hi_h);
        let a0 = clamp(
            F::ONE / positive_or(iqr, F::ONE),
            F::from_f64(1e-6),
            F::from_f64(1e6),
        );
        opt.schedule_mut().0 = a0;
        opt.set_sampler(Hrla::paper(h)?)?;
        // Basins as the value at their bottom, equal within this relative
        // tolerance (the quench's precision, with a margin).
        let same = F::from_f64(if F::MANTISSA_DIGITS > 24 { 1e-6 } else { 1e-3 });
        let mut basins = [F::INFINITY; 64];
        let tracked = n.min(64);
        let quench = PolishSettings::new(self.quench);
        // Saturating: a product past `u64::MAX` means rounds of the
        // shortest length.
        let round = (budget / self.rounds.saturating_mul(n as u64)).max(10);
        let mut rounds = 0;
        let mut watch = Watch {
            observer,
            seen: None,
            probes,
        };
        let mut termination = Termination::Evaluations;
        // Ends the run when the observer asks to.
        macro_rules! observe {
            ($run:lifetime) => {
                if watch.call(&opt, rounds).is_break() {
                    termination = Termination::Observer;
                    break $run;
                }
            };
        }
        // Quench first (the initial points' basins), then sample: on a
        // problem with few minima the quenches alone find the answer.
        let mut first = true;
        'run: {
            observe!('run);
            loop {
                for _ in 0..if first { 0 } else { round } {
                    if opt.termination().is_some() {
                        break 'run;
                    }
                    match opt.step() {
                        Ok(()) => {}
                        // Every chain stepped where `U` is not finite: they
                        // all restart below.
                        Err(Error::AllDiverged { .. }) => {
                            opt.forgive_divergence();
                            observe!('run);
                            break;
                        }
                        Err(e) => return Err(e),
                    }
                    observe!('run);
                }
                rounds += u64::from(!first);
                first = false;
                let (mut moved, mut live) = (0usize, 0usize);
                #[allow(clippy::needless_range_loop)] // `c` indexes the optimiser's chains too
                for c in 0..n {
                    if opt.chains()[c].is_diverged() {
                        // The worst basin: restarted first.
                        if c < tracked {
                            basins[c] = F::INFINITY;
                        }
                        continue;
                    }
                    let done = match opt.quench(c, lbfgs, quench) {
                        Ok(done) => done,
                        // The potential is not finite where it was (a
                        // noisy or failing evaluation): infeasible now, and
                        // the chain goes on from there.
                        Err(Error::NotFinite { .. }) => continue,
                        Err(e) => return Err(e),
                    };
                    if done.evaluations == 0 {
                        break 'run;
                    }
                    observe!('run);
                    if c < tracked {
                        live += 1;
                        let scale = if done.value.abs() > F::ONE {
                            done.value.abs()
                        } else {
                            F::ONE
                        };
                        let stayed = (done.value - basins[c]).abs() <= same * scale;
                        moved += usize::from(!stayed);
                        basins[c] = done.value;
                    }
                }
                // Global moves: the chains in the worst basins restart from
                // the best point with one coordinate redrawn uniformly in
                // the box (the next round's quench finds that point's
                // basin); diverged chains restart in any case.
                let restarts = self.restarts.min(tracked);
                let mut order = [0usize; 64];
                let m = tracked;
                for (i, o) in order.iter_mut().enumerate().take(m) {
                    *o = i;
                }
                // Worst first.
                for i in 1..m {
                    let mut j = i;
                    while j > 0 && basins[order[j]] > basins[order[j - 1]] {
                        order.swap(j, j - 1);
                        j -= 1;
                    }
                }
                let best = opt.best().x;
                for (r, &c) in order.iter().take(m).enumerate() {
                    if r >= restarts && !opt.chains()[c].is_diverged() {
                        continue;
                    }
                    let x = redrawn(&best, domain, seed, rounds, r as u64);
                    if !revive(&mut opt, c, &x, &best)? {
                        break 'run;
                    }
                    basins[c] = F::INFINITY;
                }
                for c in tracked..n {
                    if opt.chains()[c].is_diverged() {
                        // Streams apart from those of the tracked chains.
                        let x = redrawn(&best, domain, !seed, rounds, c as u64);
                        if !revive(&mut opt, c, &x, &best)? {
                            break 'run;
                        }
                    }
                }
                if restarts > 0 || opt.diverged_chains() > 0 {
                    observe!('run);
                }
                let rate = F::from_u64(moved as u64) / F::from_u64(live.max(1) as u64);
                let a = opt.schedule().0;
                let next = if rate < self.low_rate {
                    a / self.factor
                } else if rate > self.high_rate {
                    a * self.factor
                } else {
                    a
                };
                opt.schedule_mut().0 = clamp(next, F::from_f64(1e-6), F::from_f64(1e6));
                if opt.termination() == Some(Termination::Evaluations) {
                    break;
                }
            }
        }
        let best = opt.best();
        Ok(Solution {
            x: best.x,
            value: best.value,
            evaluations: opt.evaluations() + probes,
            rounds,
            step: h,
            inverse_temperature: opt.schedule().0,
            termination,
            diverged_chains: opt.diverged_chains(),
            chains: n,
        })
    }

    fn validate(&self) -> Result<(), Error> {
        if self.rounds == 0 {
            return Err(Error::Zero { name: "rounds" });
        }
        if self.quench == 0 {
            return Err(Error::Zero { name: "quench" });
        }
        for (name, v) in [
            ("low_rate", self.low_rate),
            ("high_rate", self.high_rate),
            ("step_scale", self.step_scale),
        ] {
            if !(v.is_finite() && v > F::ZERO) {
                return Err(Error::NotPositive {
                    name,
                    value: v.to_f64(),
                });
            }
        }
        if !(self.factor.is_finite() && self.factor > F::ONE) {
            return Err(Error::NotPositive {
                name: "factor - 1",
                value: (self.factor - F::ONE).to_f64(),
            });
        }
        Ok(())
    }
}

/// The best point with one coordinate redrawn uniformly in the box, from
/// a stream of `(seed, rounds, r)`.
fn redrawn<F: Float, const D: usize>(
    best: &[F; D],
    domain: Interval<F>,
    seed: u64,
    rounds: u64,
    r: u64,
) -> [F; D] {
    let h1 = splitmix64(seed ^ splitmix64(rounds.wrapping_mul(64).wrapping_add(r)));
    let h2 = splitmix64(h1);
    let j = (h1 % D.max(1) as u64) as usize;
    let u = F::from_u64(h2 >> 11) * F::from_f64(1.0 / (1u64 << 53) as f64);
    let mut x = *best;
    x[j] = domain.lo() + (domain.hi() - domain.lo()) * u;
    x
}

/// Restarts chain `c` at `x`, or at the best point itself (feasible: its
/// value was finite) when `x` is infeasible; `false` when the budget is
/// spent.
fn revive<F, P, S, C, St, const D: usize, R, B>(
    opt: &mut Optimizer<F, P, S, C, St, D, R, B>,
    c: usize,
    x: &[F; D],
    best: &[F; D],
) -> Result<bool, Error>
where
    F: Float,
    P: Potential<F, D>,
    S: crate::sampler::Sampler<F>,
    C: Schedule<F>,
    St: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
    R: Rng + 'static,
    B: crate::domain::Domain<F, D>,
{
    if !opt.restart(c, x)? {
        return Ok(false);
    }
    if opt.chains()[c].is_diverged() {
        return opt.restart(c, best);
    }
    Ok(true)
}

fn clamp<F: Float>(v: F, lo: F, hi: F) -> F {
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
    }
}

fn positive_or<F: Float>(v: F, fallback: F) -> F {
    if v.is_finite() && v > F::ZERO {
        v
    } else {
        fallback
    }
}

/// Insertion sort: at most 64 values, no allocation.
fn sort<F: Float>(v: &mut [F]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j] < v[j - 1] {
            v.swap(j, j - 1);
            j -= 1;
        }
    }
}

fn median<F: Float>(v: &mut [F]) -> F {
    sort(v);
    v[v.len() / 2]
}

fn quartile_spread<F: Float>(v: &mut [F]) -> F {
    sort(v);
    v[3 * v.len() / 4] - v[v.len() / 4]
}

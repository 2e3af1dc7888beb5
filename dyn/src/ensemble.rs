//! A gradient-free solver: an ensemble of Langevin particles in its own
//! whitened frame, driven by the gradient of a quadratic model fitted to
//! the ensemble's values, with restarts of growing population.
//!
//! [`Ensemble::minimize`] needs only values of `U`, asked for a whole
//! generation at a time (one call of the function on the `n` points, or
//! those of them that moved, so a user's map can spread them over
//! workers). Each generation:
//!
//! 1. **Frame.** `m` = the particles' mean, `C` = their covariance (plus
//!    `1e-12 tr(C)/d` on the diagonal) `= L L^T`; `z = L^-1 (x - m)`.
//! 2. **Values, scale-free.** `U` is replaced by the normal scores
//!    `s = Phi^-1((rank + 1/2) / N)` of its ranks among the points of the
//!    last two generations (non-finite values rank last), so every decision
//!    is invariant to increasing transforms of `U`, its units included.
//!    They are tempered to `V = kappa s / sd(s)` over the current
//!    generation, `kappa = spread sqrt(d / 2)`: at a quadratic centred on
//!    the ensemble, `V = spread |z|^2 / 2` exactly.
//! 3. **A model gradient.** `V ~ c0 + g^T z + z^T H z / 2` by least
//!    squares over the last two generations' points (older points more than
//!    `1e3` whitened units out left out), the isotropic part of `H` free and
//!    the rest shrunk by a ridge of `0.05 N` on standardised features; the
//!    drift is `g + H z - (d + 1)/n z` (the last term is ALDI's finite-`n`
//!    correction, which keeps the ensemble's spread unbiased).
//! 4. **HRLA's exact step** (the spec's section 4 at `a = b = alpha = beta
//!    = 1`) in `z` with that frozen gradient, step `h = min(1, 1 /
//!    lambda_max(H))` (a Newton-sized step of the model; `1` without
//!    positive curvature), the velocities kept per particle, the drift
//!    capped at `3 sqrt(d)` whitened units; the new `x = m + L z` is
//!    brought back into the box where it left it (below).
//!
//! For the isotropic model the variance ratio per step is `2 / spread`:
//! the default `spread = 6` contracts an ensemble 3 times in variance per
//! step on a quadratic, so a bowl is solved at a linear rate, while on a
//! rugged landscape the ranks' noise holds the ensemble wide; after every
//! `cool_every` generations without a new best, `kappa` is multiplied by
//! `cool`, and a spread ensemble contracts.
//!
//! **The box's walls.** A particle whose step leaves the box either stops
//! where its path from its last position meets the wall, or is clipped
//! coordinatewise, whichever the model values lower; through a wall on
//! which most particles lie, it is clipped. Clipping moves a particle
//! along the box's axes, which are not the function's: in a narrow valley
//! oblique to them (the discus, condition `10^6`) a clipped particle lands
//! across the valley, and each generation that touches a wall undoes the
//! ensemble's contraction across it (on bbob's discus at `d = 10`, with
//! 1–7% of the coordinates clipped a generation, the ensemble stayed about
//! `0.1` wide across a valley it must narrow to `1e-3` for 80
//! generations). Stopping on the path keeps the particle's place in the
//! ensemble's frame. Clipping slides along the wall, which is what reaches
//! a minimum on a face or in a corner of the box: there most particles
//! lie on the wall, where a path that leaves through it stops at once,
//! and the model, which ranks the ensemble's last, tighter positions
//! lower than the noisy new ones, would keep them where they are. A
//! particle that stays where it was is not evaluated again: it keeps its
//! value (on bbob's Katsuura and Weierstrass functions, whose ensembles
//! stay wide, a quarter and a sixth of the calls were such repeats).
//!
//! **Travel.** Far from a minimum along a narrow valley, the model's pull
//! moves the ensemble's mean by many of its own widths a generation while
//! the contraction goes on, so the ensemble shrinks faster than it
//! travels and crawls (on an ill-conditioned bowl it stops improving short
//! of the minimum). While the mean moves more than half the drift's cap
//! (`1.5 sqrt(d)` whitened units) from one generation to the next,
//! `kappa` is halved each generation, a warmer law that the ensemble
//! widens towards (CMA-ES's step-size rule grows its step on long paths in
//! the same way); once it moves less, the factor doubles back to 1.
//!
//! **Restarts** (IPOP's rule): when the generation's values agree to `1e-12`
//! of their mean, the ensemble's widest standard deviation is below `1e-12`
//! of the box, or the restart's best has not improved (by `1e-12`,
//! relatively) for `20 + 3 d` generations, the particles are drawn again
//! uniformly in the box with twice as many; but the restart after the
//! first that ended by agreement keeps its population, so that the
//! convergence rule below can be met for the cost of one more restart of
//! the same size. The first population is
//! `max(8, ceil(population P / 2) + 1)`, `P = 1 + d + d(d+1)/2` the model's
//! parameters.
//!
//! A restart that ends otherwise (the stall, or a frame or fit that breaks
//! down) with most of its particles on one point of its best value ended
//! by agreement too: a minimum on the box's boundary, where the clipping
//! pins the particles that reach it while the rest never join them (a
//! slope's corner). Its best is that point's one value, known exactly,
//! however spread the other particles' values are.
//!
//! **Local restarts** (BIPOP's second regime): after the first two
//! restarts, a restart is local whenever the local ones have spent fewer
//! calls than the others. A local restart draws `u` uniform in `[0, 1)`
//! and `max(n0, n0 (n / n0)^(u^2))` particles (`n0` the first population,
//! `n` the current one, which it leaves unchanged), normal with a
//! standard deviation of `0.03 * 10^(-2u)` of each side, clipped to the
//! box: many small searches, where the large ones average over a landscape
//! whose structure is local (Katsuura's, Weierstrass's and Gallagher's
//! functions). The local restarts take turns: the first around a uniform
//! point of the box, the second around the run's best point, and so on. A
//! large restart's best point is often a lucky draw in a basin better than
//! the one the restart then converges to; a search around it finishes
//! that basin (on bbob at `d = 2`, runs ended `1e-3` to `1e-1` above the
//! minimum with their best point in its basin).
//!
//! **Coordinate scans** (the one-coordinate visits of scipy's
//! `dual_annealing`): after a large restart that leaves the run neither
//! converged nor waiting for its confirming restart, where the run's best
//! point moved since the last scan, `U` is scanned along each
//! coordinate's side through the best point: a grid of 64 points (one
//! call of the function), then the two lowest refined by golden section
//! within a grid step of them, to `1e-10` of the side; the best point
//! moves to whatever is lower, coordinate after coordinate, in one sweep
//! (about `150 d` calls). A separable function's best point is then the
//! best on every line through it: the separable Rastrigin's restarts end
//! with a coordinate or two in a neighbouring cell, which no restart of
//! the ensemble repairs. Sweeps repeated while one lowers the best spent
//! the restarts' calls on slow descents along the axes of non-separable
//! functions (docs/QUALITY.md). Each of a scan's calls counts as a
//! generation. A scan is no evidence for the convergence rule.
//!
//! **Convergence** ([`Ensemble::converge`]): the run ends once two large
//! restarts that ended by agreement (values, positions or pinned, not the
//! stall) at one point, or three anywhere, reached the best value, each to
//! its last generation's spread of values, plus `1e-12` of the spread of
//! `U` over the first generation and `1e-11` of `|U|` there (a restart's
//! own agreement, `1e-12` of its values' mean, leaves two bests that far
//! apart): a second ensemble as large or larger found nothing better. The
//! best value is the lower of the run's and an earlier phase's
//! ([`EnsembleRules::known`]): restarts that agree above a point already
//! found have found a trap, not the minimum. Two
//! points are one when every coordinate agrees to `1e-3` of its side. Two
//! restarts that agree on the value at different points have most often
//! found symmetric local minima (Rastrigin's ring of `2 d` about its
//! minimum), so a third must agree; a function with several global minima
//! converges for the cost of that restart. A local restart is no
//! evidence: it searches a small region, where it finds a local minimum of
//! the best value as readily as the minimum. An earlier phase's best point
//! ([`EnsembleRules::known_at`]; `hrla.minimize` passes `Auto`'s, the best
//! of its quenches from uniform starts) is evidence: a large restart that
//! ends by agreement at it, at the best value, ends the run, for the cost
//! of one restart rather than two.
//!
//! Nothing but the stop depends on the budget: a run's first `B`
//! evaluations are those of any longer run with the same seed.

use std::ops::ControlFlow;

use hrla::rand_core::{Rng, SeedableRng};
use hrla::{Bounds, Hrla, HrlaParams, Kernel, Sampler, Sides, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::linalg::{
    cholesky, dot, largest_eigenvalue, normal_quantile, solve_lower, solve_upper_transposed,
};
use crate::{Error, Progress, UserError};

/// The generations the model is fitted over.
const MEMORY: usize = 2;
/// The large restarts ended by agreement at different points that must
/// reach the best value for the run to converge (two suffice at one
/// point). Three in every case (measured on bbob with every restart
/// doubled, docs/QUALITY.md) mend runs that two agree to end at a local
/// minimum, but earn 0–2 points at `10^4 d` for stopping about twice as
/// late; two at different points are most often symmetric local minima of
/// one value (Rastrigin's).
const AGREEING_APART: usize = 3;
/// Two restarts ended at one point when each coordinate agrees to this
/// share of its side: converged restarts end far closer, distinct minima
/// are a basin apart.
const SAME: f64 = 1e-3;
/// Points of a coordinate's grid in a scan (module docs, "Coordinate
/// scans"): at least two per period of a landscape with 30 periods across
/// the box.
const SCAN_GRID: usize = 64;
/// The grid's lowest points a scan refines.
const SCAN_REFINED: usize = 2;
/// A refinement ends when its bracket is this share of the side...
const SCAN_WIDTH: f64 = 1e-10;
/// ... or after this many steps (from two grid steps, `SCAN_WIDTH` takes
/// 42).
const SCAN_STEPS: usize = 60;
/// The ridge on the model's non-isotropic curvature, per fitted point.
const RIDGE: f64 = 0.05;
/// A local restart's largest standard deviation, in units of the box's
/// sides.
const LOCAL: f64 = 0.03;
/// The mean's move a generation, in whitened units per `sqrt(d)`, beyond
/// which the ensemble is travelling: half the drift's cap.
const TRAVEL: f64 = 1.5;

/// The settings of the ensemble solver (the module docs give the method).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ensemble {
    /// The model's curvature, in whitened units, at a quadratic centred
    /// on the ensemble: `2 / spread` is the variance ratio per step
    /// (default 6).
    pub spread: f64,
    /// The first population in units of half the model's parameters
    /// (default 2: one generation holds as many points as the model has
    /// parameters).
    pub population: f64,
    /// The factor on `kappa` after every `cool_every` generations of a
    /// restart without a new best (default 1.5; 1 never cools).
    pub cool: f64,
    /// See `cool` (default 10).
    pub cool_every: u32,
    /// End the run when restarts agree on the best value (module docs;
    /// default true); false spends the whole budget.
    pub converge: bool,
}

impl Default for Ensemble {
    fn default() -> Self {
        Self {
            spread: 6.0,
            population: 2.0,
            cool: 1.5,
            cool_every: 10,
            converge: true,
        }
    }
}

/// The caller's rules that end an ensemble run besides its budget, all
/// off by default. A run may continue an earlier phase (another solver's
/// run on the same problem): `elapsed` iterations that reached `known` at
/// `known_at`; the rules then count iterations from the earlier phase's
/// start, they and the convergence rule read the lower of `known` and the
/// run's best, and the convergence rule counts `known_at` as a large
/// restart's point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnsembleRules<'a> {
    /// End once the best value is at or below this.
    pub target: Option<f64>,
    /// `(window, tolerance)`: end once the best has not fallen by more
    /// than `tolerance` over `window` iterations (a window reaching back
    /// into the earlier phase measures the fall from `known`).
    pub stall: Option<(u64, f64)>,
    /// End after this many iterations, the earlier phase's included.
    pub iterations: Option<u64>,
    /// The earlier phase's iterations.
    pub elapsed: u64,
    /// The earlier phase's best value (`inf`: none).
    pub known: f64,
    /// The earlier phase's best point (empty: none): one large restart
    /// that ends by agreement at it converges the run (module docs).
    pub known_at: &'a [f64],
}

impl Default for EnsembleRules<'_> {
    fn default() -> Self {
        Self {
            target: None,
            stall: None,
            iterations: None,
            elapsed: 0,
            known: f64::INFINITY,
            known_at: &[],
        }
    }
}

/// Why an ensemble run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnsembleEnd {
    /// The budget was spent.
    Budget,
    /// Restarts agreed on the best value ([`Ensemble::converge`]).
    Converged,
    /// The observer asked.
    Observer,
    /// [`EnsembleRules::target`] was reached.
    Target,
    /// [`EnsembleRules::stall`] held.
    Stalled,
    /// [`EnsembleRules::iterations`] were done.
    Iterations,
}

/// What [`Ensemble::minimize`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct EnsembleSolution {
    /// The lowest point evaluated.
    pub x: Vec<f64>,
    /// `U(x)`.
    pub value: f64,
    /// Evaluations used (at most the budget).
    pub evaluations: u64,
    /// Generations evaluated, all restarts counted.
    pub generations: u64,
    /// Restarts done.
    pub restarts: u32,
    /// The population of the last generation.
    pub population: usize,
    /// Why it ended.
    pub end: EnsembleEnd,
}

/// A restart's best value, where it was found, and the generations
/// since it last improved.
struct RestartBest {
    value: f64,
    at: Vec<f64>,
    since: u32,
}

impl RestartBest {
    /// Takes a generation's values `f` at its points `x`: whether they
    /// improved the best (by `1e-12` of it, relatively).
    fn update(&mut self, f: &[f64], x: &[f64], d: usize) -> bool {
        let generation_best = f
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f64::INFINITY, f64::min);
        if generation_best < self.value - 1e-12 * self.value.abs()
            || !self.value.is_finite() && generation_best.is_finite()
        {
            (self.value, self.since) = (generation_best, 0);
            if let Some(i) = f.iter().position(|&v| v == generation_best) {
                self.at = x[i * d..i * d + d].to_vec();
            }
            true
        } else {
            self.since += 1;
            false
        }
    }

    /// How a restart of `n` particles in `d` coordinates that ended
    /// otherwise than by agreement counts. A minimum on the box's
    /// boundary: the clipping pins the particles that reach it to one
    /// point, which the others may never join; with most particles there,
    /// on the best value, it ended by agreement too, its best known
    /// exactly (the pinned particles' one value, whatever the spread of
    /// the others).
    fn ended_otherwise(&self, history: &[(Vec<f64>, Vec<f64>)], n: usize, d: usize) -> Restart {
        let pinned = history.last().map_or(0, |(xs, fs)| {
            let at = xs.chunks_exact(d).zip(fs);
            let mut at = at.filter(|&(_, &v)| v == self.value).map(|(p, _)| p);
            at.next()
                .map_or(0, |first| 1 + at.filter(|p| *p == first).count())
        });
        if 2 * pinned > n {
            Restart::Agreed {
                spread: 0.0,
                at: self.at.clone(),
            }
        } else {
            Restart::Other
        }
    }
}

/// The temperature's factor `warm` after the ensemble's mean moved from
/// `last` to `m` in the frame `L` (module docs, "Travel"): halved while it
/// travels, doubled back towards 1 once it does not.
fn travel(warm: f64, m: &[f64], last: &[f64], l: &[f64]) -> f64 {
    let d = m.len();
    let mut moved: Vec<f64> = m.iter().zip(last).map(|(a, b)| a - b).collect();
    solve_lower(l, d, &mut moved);
    if dot(&moved, &moved) > TRAVEL * TRAVEL * d as f64 {
        warm / 2.0
    } else {
        (warm * 2.0).min(1.0)
    }
}

/// How a restart ended.
enum Restart {
    /// Its values or positions agreed: it converged to something at `at`
    /// (its best point), its best known to about `spread`, the standard
    /// deviation of its last generation's values.
    Agreed { spread: f64, at: Vec<f64> },
    /// Its best stalled, or its frame or model broke down.
    Other,
}

/// The restarts' sizes and kinds (module docs, "Restarts" and "Local
/// restarts").
struct Schedule {
    /// The first population.
    first: usize,
    /// The next large restart's population.
    n: usize,
    /// The calls of the large and the local restarts.
    large: u64,
    local: u64,
    /// Whether the next restart is local.
    next_local: bool,
    /// The local restarts begun.
    locals: u64,
}

impl Schedule {
    fn new(first: usize) -> Self {
        Self {
            first,
            n: first,
            large: 0,
            local: 0,
            next_local: false,
            locals: 0,
        }
    }

    /// The next restart's population, and for a local one its draw.
    fn next(&mut self, rng: &mut impl Rng, best_x: &[f64]) -> (usize, Option<Local>) {
        if !self.next_local {
            return (self.n, None);
        }
        let (size, sd) = local_size(rng, self.first, self.n);
        // Every second local restart searches around the best point (once
        // there is one).
        let around_best = self.locals % 2 == 1 && !best_x.is_empty();
        let centre = around_best.then(|| best_x.to_vec());
        self.locals += 1;
        (size, Some((sd, centre)))
    }

    /// Records the restart just done: its `calls`, whether it keeps the
    /// population (`confirming`, for a large one), and the `restarts` so
    /// far.
    fn done(&mut self, calls: u64, confirming: bool, restarts: u32) {
        if self.next_local {
            self.local += calls;
        } else {
            self.large += calls;
            if !confirming {
                self.n = self.n.saturating_mul(2);
            }
        }
        self.next_local = restarts >= 2 && self.local < self.large;
    }
}

/// A large restart that ended by agreement.
struct Agreement {
    best: f64,
    spread: f64,
    at: Vec<f64>,
}

/// Whether the run has converged with `new` (module docs): it and one
/// earlier agreement at its point, or two anywhere, reached the run's best.
fn converged<V, O>(earlier: &[Agreement], new: &Agreement, run: &Run<'_, V, O>) -> bool {
    // A restart ends when its values agree to 1e-12 of their mean, or its
    // positions to 1e-12 of the box: its best is known to its last
    // generation's spread of values. Two restarts' bests then differ by
    // that, and by no less than 1e-12 of U's spread, the problem's own
    // scale. The best is the lower of the run's and an earlier phase's: a
    // restart that agrees above a point already found is no evidence
    // that nothing better exists.
    let best = run.best_known();
    let tol = 1e-12 * run.spread0.unwrap_or(0.0) + 1e-11 * best.abs();
    let at_best = |a: &&Agreement| a.best <= best + tol + a.spread;
    if !at_best(&new) {
        return false;
    }
    let (lo, hi) = (run.bounds.lo(), run.bounds.hi());
    let same = |at: &[f64]| {
        let mut sides = at.iter().zip(&new.at).zip(lo.iter().zip(hi));
        !at.is_empty()
            && at.len() == new.at.len()
            && sides.all(|((p, q), (l, h))| (p - q).abs() <= SAME * (h - l))
    };
    let agreeing = earlier.iter().filter(at_best);
    same(run.rules.known_at)
        || agreeing.clone().any(|a| same(&a.at))
        || agreeing.count() + 1 >= AGREEING_APART
}

/// The run's state across restarts.
struct Run<'f, V, O> {
    bounds: Bounds<f64, &'f [f64]>,
    budget: u64,
    rules: EnsembleRules<'f>,
    /// The best after each iteration of the stall window, oldest first.
    bests: std::collections::VecDeque<f64>,
    values: V,
    observer: O,
    rng: Xoshiro256PlusPlus,
    evaluations: u64,
    generation: u64,
    restarts: u32,
    best: f64,
    best_x: Vec<f64>,
    /// The spread of `U` over the first generation: the unit of the
    /// convergence rule's tolerance.
    spread0: Option<f64>,
}

impl Ensemble {
    /// The largest dimension taken: the model has `(d + 1)(d + 2) / 2`
    /// parameters, and a generation's fit costs `O(d^6)`.
    pub const MAX_DIM: usize = 20;

    /// The lowest value of `U` found in the box `[lo, hi]` (one side per
    /// coordinate) within `budget` evaluations, from the generator of
    /// `seed`, ending early by the `rules`. `values(points, d, out)` fills
    /// `out[i] = U(points row i)` for the `n x d` row-major `points`; its
    /// error ends the run and is returned as [`Error::User`]. `observer`
    /// is called after each generation with the layer's [`Progress`]
    /// (`iteration`: generations so far, all restarts counted; `chains`:
    /// the generation's particles; `value` `inf` and `x` empty before the
    /// first finite value); `Break` ends the run.
    ///
    /// Refused: a box that [`hrla::Bounds::new`] refuses, more than
    /// [`MAX_DIM`](Self::MAX_DIM) coordinates, a budget of 0, settings that
    /// are not finite and positive (`cool >= 1`, `cool_every >= 1`), a
    /// [`known_at`](EnsembleRules::known_at) that is not `d` finite numbers. A run
    /// that saw no finite value is [`hrla::Error::AllDiverged`], one whose
    /// best fell below `-sqrt(f64::MAX)` [`hrla::Error::UnboundedBelow`]:
    /// never a result.
    #[allow(clippy::too_many_arguments)]
    pub fn minimize<V, O>(
        &self,
        lo: &[f64],
        hi: &[f64],
        budget: u64,
        seed: u64,
        rules: EnsembleRules,
        values: V,
        observer: O,
    ) -> Result<EnsembleSolution, Error>
    where
        V: FnMut(&[f64], usize, &mut [f64]) -> Result<(), UserError>,
        O: FnMut(&Progress<'_>) -> ControlFlow<()>,
    {
        let bounds = self.check(lo, hi, budget, rules.known_at)?;
        let d = lo.len();
        let mut run = Run {
            bounds,
            budget,
            rules,
            bests: std::collections::VecDeque::from([rules.known]),
            values,
            observer,
            rng: Xoshiro256PlusPlus::seed_from_u64(seed),
            evaluations: 0,
            generation: 0,
            restarts: 0,
            best: f64::INFINITY,
            best_x: Vec::new(),
            spread0: None,
        };
        let parameters = 1 + d + d * (d + 1) / 2;
        let first =
            8.max((self.population * parameters as f64 / MEMORY as f64).ceil() as usize + 1);
        let mut schedule = Schedule::new(first);
        // The large restarts that ended by agreement.
        let mut agreed: Vec<Agreement> = Vec::new();
        // The best point of the last coordinate scan.
        let mut scanned_at: Vec<f64> = Vec::new();
        let end = loop {
            let before = run.evaluations;
            let (size, local_draw) = schedule.next(&mut run.rng, &run.best_x);
            let (restart, run_best) = match self.restart(&mut run, size, local_draw)? {
                Ok(r) => r,
                Err(end) => break end,
            };
            let agreement = match restart {
                Restart::Agreed { spread, at } => Some(Agreement {
                    best: run_best,
                    spread,
                    at,
                }),
                Restart::Other => None,
            };
            let ended_agreed = agreement.is_some();
            // Only a large restart is evidence (module docs).
            if let Some(agreement) = agreement.filter(|_| !schedule.next_local) {
                if self.converge && converged(&agreed, &agreement, &run) {
                    break EnsembleEnd::Converged;
                }
                agreed.push(agreement);
            }
            run.restarts += 1;
            // The restart after the first agreement keeps the population: it
            // can confirm that agreement for the cost of one more restart,
            // where a doubled one costs two (docs/QUALITY.md).
            let confirming = ended_agreed && agreed.len() == 1;
            let large = !schedule.next_local;
            schedule.done(run.evaluations - before, confirming, run.restarts);
            if large && !confirming && run.best_x != scanned_at {
                if let Err(end) = run.scan()? {
                    break end;
                }
                scanned_at.clone_from(&run.best_x);
            }
        };
        run.solution(schedule.n, end)
    }

    /// The box of a call, or why the call is refused ([`Self::minimize`]).
    fn check<'f>(
        &self,
        lo: &'f [f64],
        hi: &'f [f64],
        budget: u64,
        known_at: &[f64],
    ) -> Result<Bounds<f64, &'f [f64]>, Error> {
        let positive = |name, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(Error::Kernel(hrla::Error::NotPositive { name, value }))
            }
        };
        positive("spread", self.spread)?;
        positive("population", self.population)?;
        positive("cool", self.cool)?;
        if self.cool < 1.0 {
            return Err(Error::Kernel(hrla::Error::OutOfRange {
                name: "cool",
                value: self.cool,
                min: 1.0,
                max: f64::MAX,
            }));
        }
        if self.cool_every == 0 {
            return Err(Error::Kernel(hrla::Error::Zero { name: "cool_every" }));
        }
        let bounds = Bounds::new(lo, hi).map_err(Error::Kernel)?;
        let d = lo.len();
        if d > Self::MAX_DIM {
            return Err(Error::Kernel(hrla::Error::OutOfRange {
                name: "dimension",
                value: d as f64,
                min: 1.0,
                max: Self::MAX_DIM as f64,
            }));
        }
        if budget == 0 {
            return Err(Error::Kernel(hrla::Error::Zero { name: "budget" }));
        }
        if !known_at.is_empty() && known_at.len() != d {
            return Err(Error::Kernel(hrla::Error::Length {
                name: "known_at",
                expected: d,
                got: known_at.len(),
            }));
        }
        crate::settings::finite_all("known_at", known_at).map_err(Error::Kernel)?;
        Ok(bounds)
    }

    /// One restart of `n` particles, drawn uniformly in the box or as a
    /// local restart's (see [`draw`]): how it ended and its best, or the
    /// run's end.
    fn restart<V, O>(
        &self,
        run: &mut Run<'_, V, O>,
        n: usize,
        local: Option<Local>,
    ) -> Result<Result<(Restart, f64), EnsembleEnd>, Error>
    where
        V: FnMut(&[f64], usize, &mut [f64]) -> Result<(), UserError>,
        O: FnMut(&Progress<'_>) -> ControlFlow<()>,
    {
        let bounds = run.bounds;
        let (lo, hi) = (bounds.lo(), bounds.hi());
        let d = lo.len();
        let width = lo.iter().zip(hi).map(|(l, h)| h - l).fold(0.0, f64::max);
        let mut x = draw(&bounds, &mut run.rng, n, local);
        let mut y = vec![0.0; n * d];
        // The last MEMORY generations' points and values, oldest first.
        let mut history: Vec<(Vec<f64>, Vec<f64>)> = Vec::with_capacity(MEMORY);
        let mut best = RestartBest {
            value: f64::INFINITY,
            at: Vec::new(),
            since: 0,
        };
        let mut kappa = self.spread * (d as f64 / 2.0).sqrt();
        // The temperature's factor while the ensemble travels (module docs).
        let (mut warm, mut last_mean) = (1.0_f64, None::<Vec<f64>>);
        let stall = 20 + 3 * d as u32;
        loop {
            let f = match run.evaluate(&x, d, history.last())? {
                Ok(f) => f,
                Err(end) => return Ok(Err(end)),
            };
            if !best.update(&f, &x, d) && best.since.is_multiple_of(self.cool_every) {
                kappa *= self.cool;
            }
            let (mean_f, sd_f) = mean_sd(f.iter().copied().filter(|v| v.is_finite()));
            if history.len() == MEMORY {
                history.remove(0);
            }
            history.push((x.clone(), f));
            let (m, mut c) = mean_covariance(&x, n, d);
            let trace: f64 = (0..d).map(|i| c[i * d + i]).sum();
            let widest = (0..d).map(|i| c[i * d + i]).fold(0.0, f64::max).sqrt();
            if sd_f <= 1e-12 * (mean_f.abs() + 1e-300) || widest < 1e-12 * width {
                let agreed = Restart::Agreed {
                    spread: sd_f,
                    at: best.at,
                };
                return Ok(Ok((agreed, best.value)));
            }
            let other = || Ok(Ok((best.ended_otherwise(&history, n, d), best.value)));
            if best.since > stall || !(trace.is_finite() && trace > 0.0) {
                return other();
            }
            for i in 0..d {
                c[i * d + i] += 1e-12 * trace / d as f64;
            }
            if !cholesky(&mut c, d) {
                return other();
            }
            let l = c;
            if let Some(last) = last_mean.replace(m.clone()) {
                warm = travel(warm, &m, &last, &l);
            }
            let Some(drift) = self.drift(&history, &m, &l, n, d, kappa * warm) else {
                return other();
            };
            if step(drift, &m, &l, &bounds, &mut x, &mut y, &mut run.rng).is_none() {
                return other();
            }
        }
    }

    /// The model gradient at the current generation (the last of
    /// `history`) in the frame `(m, L)`, or `None` where the frame or the
    /// fit breaks down.
    fn drift(
        &self,
        history: &[(Vec<f64>, Vec<f64>)],
        m: &[f64],
        l: &[f64],
        n: usize,
        d: usize,
        kappa: f64,
    ) -> Option<Drift> {
        let total: usize = history.iter().map(|(points, _)| points.len() / d).sum();
        let mut z = Vec::with_capacity(total * d);
        let mut values = Vec::with_capacity(total);
        for (points, f) in history {
            for row in points.chunks_exact(d) {
                let start = z.len();
                z.extend(row.iter().zip(m).map(|(x, m)| x - m));
                solve_lower(l, d, &mut z[start..]);
            }
            values.extend_from_slice(f);
        }
        let current = total - n;
        if !z[current * d..].iter().all(|v| v.is_finite()) {
            return None;
        }
        let scores = rank_scores(&values);
        let (_, sd) = mean_sd(scores[current..].iter().copied());
        let sd = if sd > 0.0 { sd } else { 1.0 };
        // Older points far outside the current frame say nothing local.
        let near: Vec<usize> = (0..total)
            .filter(|&i| {
                i >= current
                    || z[i * d..i * d + d]
                        .iter()
                        .all(|v| v.is_finite() && v.abs() < 1e3)
            })
            .collect();
        let v: Vec<f64> = near.iter().map(|&i| kappa / sd * scores[i]).collect();
        let rows: Vec<&[f64]> = near.iter().map(|&i| &z[i * d..i * d + d]).collect();
        let (g, h) = fit_quadratic(&rows, &v, d, RIDGE)?;
        let aldi = (d + 1) as f64 / n as f64;
        let z_now = z.split_off(current * d);
        let mut gradient = vec![0.0; n * d];
        for (gi, zi) in gradient.chunks_exact_mut(d).zip(z_now.chunks_exact(d)) {
            for k in 0..d {
                gi[k] = g[k] + dot(&h[k * d..k * d + d], zi) - aldi * zi[k];
            }
        }
        Some(Drift {
            z: z_now,
            gradient,
            curvature: h,
            linear: g,
        })
    }
}

/// HRLA's exact step of every particle in the frame `(m, L)` with the
/// frozen model gradient, the drift capped at `3 sqrt(d)` whitened units,
/// and the new positions brought back into the box ([`into_box`]); `None`
/// where the model's curvature gives no kernel.
fn step(
    drift: Drift,
    m: &[f64],
    l: &[f64],
    bounds: &Bounds<f64, &[f64]>,
    x: &mut [f64],
    y: &mut [f64],
    rng: &mut impl Rng,
) -> Option<()> {
    let d = m.len();
    let (kernel, reach) = step_kernel(&drift.curvature, d)?;
    let cap = 3.0 * (d as f64).sqrt() / reach.max(1e-300);
    let mut z = drift.z;
    let mut g = drift.gradient;
    for ((zi, yi), gi) in z
        .chunks_exact_mut(d)
        .zip(y.chunks_exact_mut(d))
        .zip(g.chunks_exact_mut(d))
    {
        let norm = dot(gi, gi).sqrt();
        if norm > cap {
            gi.iter_mut().for_each(|v| *v *= cap / norm);
        }
        kernel.step_slice(zi, yi, gi, rng);
    }
    let held = held_walls(x, bounds);
    let mut to = vec![0.0; d];
    for (xi, zi) in x.chunks_exact_mut(d).zip(z.chunks_exact(d)) {
        for (k, t) in to.iter_mut().enumerate() {
            *t = m[k] + dot(&l[k * d..k * d + k + 1], &zi[..k + 1]);
        }
        into_box(xi, &to, bounds, &held, |p| {
            model_value(&drift.linear, &drift.curvature, m, l, p)
        });
    }
    Some(())
}

/// For each coordinate, whether most of the particles `x` lie on its lower
/// and on its upper wall.
fn held_walls(x: &[f64], bounds: &Bounds<f64, &[f64]>) -> Vec<[bool; 2]> {
    let (lo, hi) = (bounds.lo(), bounds.hi());
    let d = lo.len();
    let n = x.len() / d;
    let most = |k: usize, wall: f64| 2 * x.chunks_exact(d).filter(|p| p[k] == wall).count() > n;
    (0..d).map(|k| [most(k, lo[k]), most(k, hi[k])]).collect()
}

/// A particle's move from `x` (in the box) to `to`, written into `x`:
/// `to` itself where it is in the box; otherwise the point where the path
/// meets a wall not `held` ([`held_walls`]) or `to` clipped
/// coordinatewise, whichever `value` ranks lower (module docs, "The box's
/// walls").
fn into_box(
    x: &mut [f64],
    to: &[f64],
    bounds: &Bounds<f64, &[f64]>,
    held: &[[bool; 2]],
    value: impl Fn(&[f64]) -> f64,
) {
    let (lo, hi) = (bounds.lo(), bounds.hi());
    // The share of the path inside the walls that are not held.
    let mut share = 1.0_f64;
    for (k, &t) in to.iter().enumerate() {
        let wall = if t > hi[k] && !held[k][1] {
            hi[k]
        } else if t < lo[k] && !held[k][0] {
            lo[k]
        } else {
            continue;
        };
        share = share.min((wall - x[k]) / (t - x[k]));
    }
    if share < 1.0 {
        let share = share.max(0.0);
        let stopped: Vec<f64> = (0..x.len())
            .map(|k| (x[k] + share * (to[k] - x[k])).clamp(lo[k], hi[k]))
            .collect();
        let clipped: Vec<f64> = (0..x.len()).map(|k| to[k].clamp(lo[k], hi[k])).collect();
        let better = if value(&stopped) <= value(&clipped) {
            stopped
        } else {
            clipped
        };
        x.copy_from_slice(&better);
    } else {
        for (k, xk) in x.iter_mut().enumerate() {
            *xk = to[k].clamp(lo[k], hi[k]);
        }
    }
}

/// The quadratic model `g^T z + z^T H z / 2` at the point `p`, `z = L^-1
/// (p - m)`.
fn model_value(g: &[f64], h: &[f64], m: &[f64], l: &[f64], p: &[f64]) -> f64 {
    let d = g.len();
    let mut z: Vec<f64> = p.iter().zip(m).map(|(p, m)| p - m).collect();
    solve_lower(l, d, &mut z);
    let curvature: f64 = (0..d).map(|k| z[k] * dot(&h[k * d..k * d + d], &z)).sum();
    dot(g, &z) + curvature / 2.0
}

/// A local restart's population and standard deviation (module docs):
/// `u` uniform in `[0, 1)` sets both.
fn local_size(rng: &mut impl Rng, first: usize, n: usize) -> (usize, f64) {
    let u = (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
    let size = (first as f64 * (n as f64 / first as f64).powf(u * u)).floor() as usize;
    (size.max(first), LOCAL * 10f64.powf(-2.0 * u))
}

/// A local restart's standard deviation, in units of each side, and its
/// centre (none: a uniform point of the box).
type Local = (f64, Option<Vec<f64>>);

/// A restart's `n` particles: uniform in the box, or for a local restart
/// normal around its centre with its standard deviation, clipped.
fn draw(
    bounds: &Bounds<f64, &[f64]>,
    rng: &mut impl Rng,
    n: usize,
    local: Option<Local>,
) -> Vec<f64> {
    let (lo, hi) = (bounds.lo(), bounds.hi());
    let d = lo.len();
    let mut x = vec![0.0; n * d];
    let local = local.map(|(sd, centre)| {
        let centre = centre.unwrap_or_else(|| {
            let mut centre = vec![0.0; d];
            bounds.uniform(rng, &mut centre);
            centre
        });
        (centre, sd)
    });
    for row in x.chunks_exact_mut(d) {
        match &local {
            Some((centre, sd)) => {
                for (k, xk) in row.iter_mut().enumerate() {
                    let z = f64::standard_normal(rng);
                    *xk = (centre[k] + sd * (hi[k] - lo[k]) * z).clamp(lo[k], hi[k]);
                }
            }
            None => bounds.uniform(rng, row),
        }
    }
    x
}

/// The current generation in whitened units, its model gradient, and the
/// model's Hessian.
struct Drift {
    z: Vec<f64>,
    gradient: Vec<f64>,
    curvature: Vec<f64>,
    /// The model's gradient at the mean, `g`.
    linear: Vec<f64>,
}

impl<V, O> Run<'_, V, O> {
    /// The lower of the run's best and an earlier phase's
    /// ([`EnsembleRules::known`]): what the caller's rules and the
    /// convergence rule read.
    fn best_known(&self) -> f64 {
        self.best.min(self.rules.known)
    }
}

impl<V, O> Run<'_, V, O>
where
    V: FnMut(&[f64], usize, &mut [f64]) -> Result<(), UserError>,
    O: FnMut(&Progress<'_>) -> ControlFlow<()>,
{
    /// The run's result once it ended by `end` with `n` the next large
    /// restart's population: never a result when it saw no finite value or
    /// its best fell below `-sqrt(f64::MAX)`.
    fn solution(self, n: usize, end: EnsembleEnd) -> Result<EnsembleSolution, Error> {
        if self.best_x.is_empty() {
            return Err(Error::Kernel(hrla::Error::AllDiverged { chains: n }));
        }
        if self.best < -f64::MAX.sqrt() {
            return Err(Error::Kernel(hrla::Error::UnboundedBelow {
                chain: 0,
                value: self.best,
            }));
        }
        Ok(EnsembleSolution {
            x: self.best_x,
            value: self.best,
            evaluations: self.evaluations,
            generations: self.generation,
            restarts: self.restarts,
            population: n,
            end,
        })
    }

    /// `U` at the rows of `x`, asked only where a row moved since `last`
    /// (the previous generation's points and values; a row that did not
    /// keeps its value), the best kept; the run's end when the budget is
    /// spent (the rows it still covered evaluated) or the observer asks.
    fn evaluate(
        &mut self,
        x: &[f64],
        d: usize,
        last: Option<&(Vec<f64>, Vec<f64>)>,
    ) -> Result<Result<Vec<f64>, EnsembleEnd>, Error> {
        let n = x.len() / d;
        let mut f = vec![f64::NAN; n];
        // A particle where it was a generation ago keeps its value.
        let mut ask = Vec::with_capacity(n);
        for (i, row) in x.chunks_exact(d).enumerate() {
            match last {
                Some((xs, fs)) if xs.get(i * d..i * d + d) == Some(row) => f[i] = fs[i],
                _ => ask.push(i),
            }
        }
        let take = (self.budget - self.evaluations).min(ask.len() as u64) as usize;
        ask.truncate(take);
        if take > 0 {
            let points: Vec<f64> = ask
                .iter()
                .flat_map(|&i| &x[i * d..i * d + d])
                .copied()
                .collect();
            let mut asked = vec![f64::NAN; take];
            (self.values)(&points, d, &mut asked).map_err(Error::User)?;
            for (&i, v) in ask.iter().zip(asked) {
                f[i] = v;
            }
        }
        self.evaluations += take as u64;
        self.generation += 1;
        for &i in &ask {
            let v = f[i];
            if v.is_finite() && v < self.best {
                self.best = v;
                self.best_x.clear();
                self.best_x.extend_from_slice(&x[i * d..i * d + d]);
            }
        }
        if self.spread0.is_none() {
            self.spread0 = Some(mean_sd(f.iter().copied().filter(|v| v.is_finite())).1);
        }
        let progress = Progress {
            iteration: self.generation,
            evaluations: self.evaluations,
            value: self.best,
            x: &self.best_x,
            dim: d,
            chains: n,
        };
        if (self.observer)(&progress).is_break() {
            return Ok(Err(EnsembleEnd::Observer));
        }
        if let Some(end) = self.rule() {
            return Ok(Err(end));
        }
        if self.evaluations >= self.budget {
            return Ok(Err(EnsembleEnd::Budget));
        }
        Ok(Ok(f))
    }

    /// A coordinate scan from the run's best point: one sweep over the
    /// coordinates (module docs, "Coordinate scans"); the run's end if one
    /// came.
    fn scan(&mut self) -> Result<Result<(), EnsembleEnd>, Error> {
        let bounds = self.bounds;
        let (lo, hi) = (bounds.lo(), bounds.hi());
        let d = lo.len();
        for j in 0..d {
            let x = self.best_x.clone();
            let step = (hi[j] - lo[j]) / (SCAN_GRID - 1) as f64;
            let at = |k: usize| {
                if k + 1 == SCAN_GRID {
                    hi[j]
                } else {
                    lo[j] + k as f64 * step
                }
            };
            let mut grid = Vec::with_capacity(SCAN_GRID * d);
            for k in 0..SCAN_GRID {
                grid.extend_from_slice(&x);
                grid[k * d + j] = at(k);
            }
            let f = match self.evaluate(&grid, d, None)? {
                Ok(f) => f,
                Err(end) => return Ok(Err(end)),
            };
            let mut order: Vec<usize> = (0..SCAN_GRID).filter(|&k| f[k].is_finite()).collect();
            order.sort_by(|&a, &b| f[a].total_cmp(&f[b]));
            for &k in order.iter().take(SCAN_REFINED) {
                let bracket = ((at(k) - step).max(lo[j]), (at(k) + step).min(hi[j]));
                let width = SCAN_WIDTH * (hi[j] - lo[j]);
                if let Err(end) = self.golden_section(&x, j, bracket, width)? {
                    return Ok(Err(end));
                }
            }
        }
        Ok(Ok(()))
    }

    /// Golden-section search for the lowest `U` on `x` with coordinate `j`
    /// in `[a, b]`, until the bracket is `width` wide, each point one call;
    /// the run keeps the lowest (its end if one came). A value that is not
    /// finite counts as `+inf`.
    fn golden_section(
        &mut self,
        x: &[f64],
        j: usize,
        (mut a, mut b): (f64, f64),
        width: f64,
    ) -> Result<Result<(), EnsembleEnd>, Error> {
        const R: f64 = 0.618_033_988_749_894_9;
        let d = x.len();
        let mut p = x.to_vec();
        let mut value = |t: f64| -> Result<Result<f64, EnsembleEnd>, Error> {
            p[j] = t;
            let f = self.evaluate(&p, d, None)?;
            Ok(f.map(|f| {
                if f[0].is_finite() {
                    f[0]
                } else {
                    f64::INFINITY
                }
            }))
        };
        let (mut c, mut e) = (b - R * (b - a), a + R * (b - a));
        let mut fc = match value(c)? {
            Ok(f) => f,
            Err(end) => return Ok(Err(end)),
        };
        let mut fe = match value(e)? {
            Ok(f) => f,
            Err(end) => return Ok(Err(end)),
        };
        // The bracket shrinks by `R` a step until it is `width` wide; where
        // a side is narrow next to its coordinates' size, rounding can
        // hold a bracket of one spacing of the doubles still, each step
        // a call: `SCAN_STEPS` bounds it.
        for _ in 0..SCAN_STEPS {
            if b - a <= width {
                break;
            }
            if fc <= fe {
                (b, e, fe) = (e, c, fc);
                c = b - R * (b - a);
                fc = match value(c)? {
                    Ok(f) => f,
                    Err(end) => return Ok(Err(end)),
                };
            } else {
                (a, c, fc) = (c, e, fe);
                e = a + R * (b - a);
                fe = match value(e)? {
                    Ok(f) => f,
                    Err(end) => return Ok(Err(end)),
                };
            }
        }
        Ok(Ok(()))
    }

    /// The caller's rule that ends the run after this generation, if any.
    fn rule(&mut self) -> Option<EnsembleEnd> {
        let rules = self.rules;
        let best = self.best_known();
        let iteration = rules.elapsed + self.generation;
        if rules.target.is_some_and(|t| best <= t) {
            return Some(EnsembleEnd::Target);
        }
        if let Some((window, tolerance)) = rules.stall {
            // The best `window` iterations ago, or `known` where that is
            // before this run.
            self.bests.push_back(best);
            let keep = (window.min(self.generation) + 1) as usize;
            while self.bests.len() > keep {
                self.bests.pop_front();
            }
            let fell = self.bests.front().map_or(0.0, |b| b - best);
            let falling = fell > tolerance;
            if iteration >= window && !falling {
                return Some(EnsembleEnd::Stalled);
            }
        }
        if rules.iterations.is_some_and(|k| iteration >= k) {
            return Some(EnsembleEnd::Iterations);
        }
        None
    }
}

/// The mean and the population standard deviation (`0, 0` for nothing).
fn mean_sd(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let (count, sum) = values
        .clone()
        .fold((0usize, 0.0), |(c, s), v| (c + 1, s + v));
    if count == 0 {
        return (0.0, 0.0);
    }
    let mean = sum / count as f64;
    let var = values.map(|v| (v - mean) * (v - mean)).sum::<f64>() / count as f64;
    (mean, var.sqrt())
}

/// The mean (`d`) and the sample covariance (`d x d`, divided by `n - 1`)
/// of the `n` rows of `x`.
fn mean_covariance(x: &[f64], n: usize, d: usize) -> (Vec<f64>, Vec<f64>) {
    let mut m = vec![0.0; d];
    for row in x.chunks_exact(d) {
        m.iter_mut().zip(row).for_each(|(m, v)| *m += v);
    }
    m.iter_mut().for_each(|v| *v /= n as f64);
    let mut c = vec![0.0; d * d];
    for row in x.chunks_exact(d) {
        for i in 0..d {
            for j in 0..=i {
                c[i * d + j] += (row[i] - m[i]) * (row[j] - m[j]);
            }
        }
    }
    let denominator = (n.max(2) - 1) as f64;
    for i in 0..d {
        for j in 0..=i {
            c[i * d + j] /= denominator;
            c[j * d + i] = c[i * d + j];
        }
    }
    (m, c)
}

/// The normal scores `Phi^-1((r + 1/2) / N)` of the ranks `r` of `values`
/// (ties by index; non-finite values last).
fn rank_scores(values: &[f64]) -> Vec<f64> {
    let key = |v: f64| if v.is_finite() { v } else { f64::INFINITY };
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| key(values[a]).total_cmp(&key(values[b])));
    let total = values.len() as f64;
    let mut scores = vec![0.0; values.len()];
    for (rank, &i) in order.iter().enumerate() {
        scores[i] = normal_quantile((rank as f64 + 0.5) / total);
    }
    scores
}

/// `g` and `H` of `v ~ c0 + g^T z + z^T H z / 2` by least squares over the
/// rows `z`: features `1, z, |z|^2 / 2` free, and `z_k z_l` (halved on the
/// diagonal) shrunk by a ridge of `ridge N` after each feature is scaled
/// to unit root mean square. `None` when the normal equations break down.
fn fit_quadratic(z: &[&[f64]], v: &[f64], d: usize, ridge: f64) -> Option<(Vec<f64>, Vec<f64>)> {
    let free = 2 + d;
    let p = free + d * (d + 1) / 2;
    let features = |zi: &[f64], out: &mut [f64]| {
        out[0] = 1.0;
        out[1..=d].copy_from_slice(zi);
        out[1 + d] = 0.5 * dot(zi, zi);
        let mut j = free;
        for k in 0..d {
            for l in k..d {
                out[j] = zi[k] * zi[l] * if k == l { 0.5 } else { 1.0 };
                j += 1;
            }
        }
    };
    let rows = z.len();
    let mut a = vec![0.0; rows * p];
    for (zi, row) in z.iter().zip(a.chunks_exact_mut(p)) {
        features(zi, row);
    }
    let mut scale = vec![0.0; p];
    for row in a.chunks_exact(p) {
        scale.iter_mut().zip(row).for_each(|(s, v)| *s += v * v);
    }
    scale
        .iter_mut()
        .for_each(|s| *s = (*s / rows as f64).sqrt() + 1e-300);
    for row in a.chunks_exact_mut(p) {
        row.iter_mut().zip(&scale).for_each(|(v, s)| *v /= s);
    }
    // The normal equations (A^T A + ridge) theta = A^T v, lower triangle.
    let mut normal = vec![0.0; p * p];
    let mut rhs = vec![0.0; p];
    for (row, &vi) in a.chunks_exact(p).zip(v) {
        for i in 0..p {
            let ri = row[i];
            rhs[i] += ri * vi;
            for (nij, rj) in normal[i * p..i * p + i + 1].iter_mut().zip(&row[..=i]) {
                *nij += ri * rj;
            }
        }
    }
    for j in free..p {
        normal[j * p + j] += ridge * rows as f64;
    }
    if !cholesky(&mut normal, p) {
        return None;
    }
    solve_lower(&normal, p, &mut rhs);
    solve_upper_transposed(&normal, p, &mut rhs);
    let theta: Vec<f64> = rhs.iter().zip(&scale).map(|(t, s)| t / s).collect();
    let g = theta[1..=d].to_vec();
    let mut h = vec![0.0; d * d];
    let mut j = free;
    for k in 0..d {
        for l in k..d {
            h[k * d + l] = theta[j];
            h[l * d + k] = theta[j];
            j += 1;
        }
        h[k * d + k] += theta[1 + d];
    }
    let finite = g.iter().chain(&h).all(|v| v.is_finite());
    finite.then_some((g, h))
}

/// HRLA's kernel at `a = b = alpha = beta = 1` with the step `min(1, 1 /
/// lambda_max(H))`, and how far a unit gradient moves its mean.
fn step_kernel(h: &[f64], d: usize) -> Option<(hrla::OuKernel<f64>, f64)> {
    let top = largest_eigenvalue(h, d);
    let step = if top > 0.0 { (1.0 / top).min(1.0) } else { 1.0 };
    let params = HrlaParams {
        b: 1.0,
        alpha: 1.0,
        beta: 1.0,
        h: step,
    };
    let kernel = Hrla::new(params).ok()?.at(1.0).ok()?;
    let reach = -kernel.moments(0.0, 0.0, 1.0).mean_x;
    Some((kernel, reach))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_recovers_a_quadratic() {
        // v = 1 + g.z + z^T H z / 2 exactly, with a ridge far below the
        // curvature's share: the fit returns g and H to rounding.
        let d = 3;
        let g = [0.5, -1.0, 2.0];
        let h = [2.0, 0.3, -0.1, 0.3, 1.0, 0.2, -0.1, 0.2, 3.0];
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let square = Bounds::new([-2.0; 3], [2.0; 3]).unwrap();
        let z: Vec<Vec<f64>> = (0..400)
            .map(|_| {
                let mut zi = vec![0.0; d];
                square.uniform(&mut rng, &mut zi);
                zi
            })
            .collect();
        let v: Vec<f64> = z
            .iter()
            .map(|zi| {
                let hz: Vec<f64> = (0..d).map(|k| dot(&h[k * d..k * d + d], zi)).collect();
                1.0 + dot(&g, zi) + 0.5 * dot(zi, &hz)
            })
            .collect();
        let rows: Vec<&[f64]> = z.iter().map(Vec::as_slice).collect();
        // With a vanishing ridge (some is needed: the isotropic feature is
        // the sum of the diagonal ones) the fit is exact up to a bias of
        // the ridge's order and the rounding of normal equations of
        // condition about 1/ridge.
        let (fg, fh) = fit_quadratic(&rows, &v, d, 1e-10).unwrap();
        for (a, b) in fg.iter().chain(&fh).zip(g.iter().chain(&h)) {
            assert!(
                (a - b).abs() < 1e-6,
                "g {fg:?}, H {fh:?} against {g:?}, {h:?}"
            );
        }
        // The default ridge biases the curvature, by less than a tenth of
        // it here (Frobenius norms).
        let (_, rh) = fit_quadratic(&rows, &v, d, RIDGE).unwrap();
        let norm = |m: &[f64]| dot(m, m).sqrt();
        let diff: Vec<f64> = rh.iter().zip(&h).map(|(a, b)| a - b).collect();
        assert!(norm(&diff) < 0.1 * norm(&h), "{rh:?} against {h:?}");
    }
}

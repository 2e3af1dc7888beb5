//! One run of [`Auto`]: its state, and each step of the method by name,
//! over chains and buffers of any dimension (slices of length `d`): the
//! const-generic [`Chain`]s and the caller's flat storage run this one
//! body.

use core::cell::{Cell, RefCell};
use core::ops::ControlFlow;

use rand_core::{Rng, SeedableRng};

use super::measure::{self, A_RANGE, Units};
use super::moves;
use super::scale::{Scaled, Unit};
use super::settings::{Auto, Sampling};
use crate::domain::{Domain, Sides};
use crate::error::{Error, floor};
use crate::float::Float;
use crate::optimizer::{Chain, Stop as Rules, Termination, chain_seed, draw_point};
use crate::optimizer::{Verdict, judge};
use crate::polish::{PolishEnd, PolishSettings, Polished, Quencher, Scale};
use crate::potential::traits::one_point;
use crate::potential::{BatchPotential, SlicePotential};
use crate::sampler::{Hrla, Kernel, OuKernel, Sampler};

/// Why a run ended early.
pub(super) enum Stop {
    /// The evaluation budget is spent.
    Budget,
    /// The observer asked to stop.
    Observer,
    /// A failure to report (a potential unbounded below).
    Failed(Error),
    /// The target was reached.
    Target,
}

type Flow = ControlFlow<Stop>;

/// A proposal's point as it goes through a round's steps: its value where
/// known, its value and gradient where evaluated there (the gradient in
/// the run's buffer), not yet evaluated, or rejected (an infeasible point
/// met).
#[derive(Clone, Copy)]
enum Point<F> {
    Known(F),
    Evaluated(F),
    Unknown,
    Rejected,
}

/// Chains whose curvature is probed: their median suffices.
const PROBES: usize = 16;

/// The floats of [`Buffers`] in dimension `d`.
pub(super) const fn buffer_floats(d: usize) -> usize {
    d.saturating_mul(7)
}

/// One chain's state, borrowed from wherever the chains live.
pub(super) struct ChainMut<'a, F, R> {
    pub(super) x: &'a mut [F],
    pub(super) y: &'a mut [F],
    pub(super) grad: &'a mut [F],
    pub(super) value: &'a mut F,
    pub(super) diverged: &'a mut bool,
    pub(super) rng: &'a mut R,
}

/// The chains of a run, as the body reads and writes them: an array of
/// [`Chain`]s or the caller's flat storage.
pub(super) trait Chains<F> {
    /// The chains' generator.
    type Rng;
    /// The number of chains.
    fn len(&self) -> usize;
    /// Chain `c`'s state.
    fn chain(&mut self, c: usize) -> ChainMut<'_, F, Self::Rng>;
    /// Chain `c`'s basin.
    fn x(&self, c: usize) -> &[F];
    /// `U` at chain `c`'s basin.
    fn value(&self, c: usize) -> F;
    /// Whether chain `c`'s last proposal met an infeasible point.
    fn diverged(&self, c: usize) -> bool;
    /// Chains `c` and `c + 1` exchange their basins and momenta.
    fn swap(&mut self, c: usize);
    /// Chain `c`'s initial point is drawn and evaluated.
    fn started(&mut self, _c: usize) {}
}

impl<F: Float, const D: usize, R> Chains<F> for [Chain<F, D, R>] {
    type Rng = R;
    fn len(&self) -> usize {
        <[_]>::len(self)
    }
    fn chain(&mut self, c: usize) -> ChainMut<'_, F, R> {
        let chain = &mut self[c];
        ChainMut {
            x: &mut chain.x,
            y: &mut chain.y,
            grad: &mut chain.grad,
            value: &mut chain.value,
            diverged: &mut chain.diverged,
            rng: &mut chain.rng,
        }
    }
    fn x(&self, c: usize) -> &[F] {
        &self[c].x
    }
    fn value(&self, c: usize) -> F {
        self[c].value
    }
    fn diverged(&self, c: usize) -> bool {
        self[c].diverged
    }
    fn swap(&mut self, c: usize) {
        let (lo, hi) = self.split_at_mut(c + 1);
        let (p, q) = (&mut lo[c], &mut hi[0]);
        core::mem::swap(&mut p.x, &mut q.x);
        core::mem::swap(&mut p.value, &mut q.value);
        core::mem::swap(&mut p.grad, &mut q.grad);
        core::mem::swap(&mut p.y, &mut q.y);
    }
    fn started(&mut self, c: usize) {
        let chain = &mut self[c];
        chain.best.x = chain.x;
        chain.best.value = chain.value;
        chain.best.iteration = 0;
    }
}

/// `n` chains of dimension `d` in flat arrays, chain-major (chain `c`'s
/// vectors at `c d..(c + 1) d`).
pub(super) struct FlatChains<'a, F, R> {
    pub(super) d: usize,
    pub(super) x: &'a mut [F],
    pub(super) y: &'a mut [F],
    pub(super) grad: &'a mut [F],
    pub(super) value: &'a mut [F],
    pub(super) diverged: &'a mut [bool],
    pub(super) rngs: &'a mut [R],
}

/// Swaps blocks `c` and `c + 1` of `d` values.
fn swap_blocks<T>(v: &mut [T], c: usize, d: usize) {
    let (lo, hi) = v.split_at_mut((c + 1) * d);
    lo[c * d..].swap_with_slice(&mut hi[..d]);
}

impl<F: Float, R> Chains<F> for FlatChains<'_, F, R> {
    type Rng = R;
    fn len(&self) -> usize {
        self.rngs.len()
    }
    fn chain(&mut self, c: usize) -> ChainMut<'_, F, R> {
        let span = c * self.d..(c + 1) * self.d;
        ChainMut {
            x: &mut self.x[span.clone()],
            y: &mut self.y[span.clone()],
            grad: &mut self.grad[span],
            value: &mut self.value[c],
            diverged: &mut self.diverged[c],
            rng: &mut self.rngs[c],
        }
    }
    fn x(&self, c: usize) -> &[F] {
        &self.x[c * self.d..(c + 1) * self.d]
    }
    fn value(&self, c: usize) -> F {
        self.value[c]
    }
    fn diverged(&self, c: usize) -> bool {
        self.diverged[c]
    }
    fn swap(&mut self, c: usize) {
        let d = self.d;
        swap_blocks(self.x, c, d);
        self.value.swap(c, c + 1);
        swap_blocks(self.grad, c, d);
        swap_blocks(self.y, c, d);
    }
}

/// The points a run works on besides the chains' own (`d` floats each).
pub(super) struct Buffers<'a, F> {
    /// The best feasible point evaluated.
    pub(super) best: &'a mut [F],
    /// A proposal's position, momentum and gradient.
    x: &'a mut [F],
    y: &'a mut [F],
    grad: &'a mut [F],
    /// A curvature probe's direction, base point and gradient there.
    v: &'a mut [F],
    base: &'a mut [F],
    g0: &'a mut [F],
}

impl<'a, F> Buffers<'a, F> {
    /// Cuts `floats` ([`buffer_floats`]`(d)` of them) into the buffers.
    pub(super) fn new(d: usize, floats: &'a mut [F]) -> Self {
        let (best, rest) = floats.split_at_mut(d);
        let (x, rest) = rest.split_at_mut(d);
        let (y, rest) = rest.split_at_mut(d);
        let (grad, rest) = rest.split_at_mut(d);
        let (v, rest) = rest.split_at_mut(d);
        let (base, g0) = rest.split_at_mut(d);
        Self {
            best,
            x,
            y,
            grad,
            v,
            base,
            g0: &mut g0[..d],
        }
    }
}

/// One point at a time through the batch seam ([`one_point`]): a stop ends
/// every step of the method at once, and the run reports
/// [`Error::Stopped`].
pub(super) struct One<'a, P: ?Sized> {
    potential: &'a P,
    stopped: Cell<bool>,
}

impl<'a, P: ?Sized> One<'a, P> {
    fn new(potential: &'a P) -> Self {
        Self {
            potential,
            stopped: Cell::new(false),
        }
    }

    /// `e`, or [`Error::Stopped`] where the potential stopped the run.
    fn cause(&self, e: Error) -> Error {
        if self.stopped.get() {
            Error::Stopped
        } else {
            e
        }
    }
}

impl<F: Float, P: BatchPotential<F> + ?Sized> SlicePotential<F> for One<'_, P> {
    #[inline]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        one_point(self.potential, x, grad, &self.stopped)
    }
}

/// What the observer sees: the run's state at a call.
pub(super) struct Seen<'a, F> {
    pub(super) evaluations: u64,
    pub(super) rounds: u64,
    pub(super) x: &'a [F],
    pub(super) value: F,
    pub(super) improved: bool,
    pub(super) inverse_temperature: F,
    pub(super) diverged_chains: usize,
}

/// What a run found, but its point (in [`Buffers::best`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Found<F> {
    pub(super) value: F,
    pub(super) evaluations: u64,
    pub(super) rounds: u64,
    pub(super) step: F,
    pub(super) inverse_temperature: F,
    pub(super) termination: Termination,
    pub(super) diverged_chains: usize,
    pub(super) chains: usize,
}

/// The evaluations and the best point: what every evaluation updates.
struct Tally<'a, F, P: ?Sized, B: ?Sized, L: ?Sized> {
    auto: &'a Auto<F>,
    potential: One<'a, P>,
    domain: &'a B,
    /// The box's unit coordinates, where the dynamics and the quenches run.
    unit: Unit<'a, F, B>,
    lbfgs: &'a mut L,
    /// The problem's units, in which the quenches' constants hold.
    scale: Scale<F>,
    budget: u64,
    /// The budget the first quench may run to (at least `budget`).
    overrun: u64,
    evaluations: u64,
    rounds: u64,
    /// The best feasible point evaluated, and whether a converged L-BFGS
    /// ended there.
    best: &'a mut [F],
    best_value: F,
    polished: bool,
}

impl<F, P, B, L> Tally<'_, F, P, B, L>
where
    F: Float,
    P: BatchPotential<F> + ?Sized,
    B: Sides<F> + ?Sized,
    L: Quencher<F> + ?Sized,
{
    fn remaining(&self) -> u64 {
        self.budget - self.evaluations
    }

    /// Evaluations kept for the final polish while the best point is not
    /// a converged minimum: 5% of the budget, whatever a quench may take
    /// (a quench cut short is why the best is not converged).
    fn reserve(&self) -> u64 {
        if self.polished { 0 } else { self.budget / 20 }
    }

    /// One evaluation at `x` within the budget: its value where feasible,
    /// `None` where not.
    fn evaluate(&mut self, x: &[F], grad: &mut [F]) -> ControlFlow<Stop, Option<F>> {
        if self.remaining() == 0 {
            return ControlFlow::Break(Stop::Budget);
        }
        let value = self.potential.value_and_gradient(x, grad);
        self.evaluations += 1;
        match judge(x, value, grad, floor()) {
            Verdict::Feasible => {
                self.record(x, value, false);
                ControlFlow::Continue(Some(value))
            }
            Verdict::Infeasible(_) => ControlFlow::Continue(None),
            Verdict::Unbounded => ControlFlow::Break(Stop::Failed(Error::UnboundedBelow {
                chain: 0,
                value: value.to_f64(),
            })),
        }
    }

    /// L-BFGS from `x` (in place) for chain `c`, within `cap` evaluations
    /// and the budget: the value at its end, or `None` where `x` is
    /// infeasible. `scratch` is a point's worth of working space; `start`,
    /// where known, `U(x)` and the gradient at `x` (overwritten).
    fn quench(
        &mut self,
        c: usize,
        x: &mut [F],
        scratch: &mut [F],
        start: Option<(F, &mut [F])>,
        cap: u64,
    ) -> ControlFlow<Stop, Option<F>> {
        let cap = cap.min(self.remaining());
        if cap == 0 {
            return ControlFlow::Break(Stop::Budget);
        }
        match self.local(x, scratch, start, PolishSettings::new(cap)) {
            Ok(done) => {
                self.evaluations += done.evaluations;
                self.record(x, done.value, done.end != PolishEnd::Budget);
                ControlFlow::Continue(Some(done.value))
            }
            // Infeasible where it started: one evaluation spent.
            Err(Error::NotFinite { .. }) => {
                self.evaluations += 1;
                ControlFlow::Continue(None)
            }
            Err(Error::UnboundedBelow { value, .. }) => {
                ControlFlow::Break(Stop::Failed(Error::UnboundedBelow { chain: c, value }))
            }
            Err(e) => ControlFlow::Break(Stop::Failed(e)),
        }
    }

    /// L-BFGS from `x` in the box's unit coordinates, `x` ending at its
    /// end in the box's own; `start` as in [`quench`](Self::quench).
    fn local(
        &mut self,
        x: &mut [F],
        scratch: &mut [F],
        start: Option<(F, &mut [F])>,
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        let (unit, scale) = (self.unit, self.scale);
        if unit.is_identity() {
            return self
                .lbfgs
                .quench(&self.potential, self.domain, x, start, settings, scale);
        }
        let mut start = start;
        if let Some((_, grad)) = &mut start {
            unit.gradient_in_place(grad);
        }
        let scaled = Scaled {
            potential: &self.potential,
            unit,
            x: RefCell::new(scratch),
        };
        unit.scale_in(x);
        let done = self.lbfgs.quench(
            &scaled,
            &unit,
            x,
            start.as_mut().map(|(v, g)| (*v, &mut **g)),
            settings,
            scale,
        );
        unit.scale_out(x);
        if let (Ok(_), Some((_, grad))) = (&done, start) {
            unit.gradient_out_in_place(grad);
        }
        done
    }

    /// A feasible point evaluated: the new best if it is lower.
    fn record(&mut self, x: &[F], value: F, converged: bool) {
        if value < self.best_value {
            self.best.copy_from_slice(x);
            self.best_value = value;
            self.polished = converged;
        } else if value == self.best_value && converged && *x == *self.best {
            self.polished = true;
        }
    }
}

/// A run in progress. Each chain's `x` and `value` hold its basin (the
/// quenched point, its value at a converged minimum), `grad` the gradient
/// there as the first quenches leave it (the measurement reads it; a
/// round's sampling takes a basin's gradient as zero), `y` the momentum
/// its last trajectory ended with, `diverged` whether its last proposal
/// met an infeasible point.
pub(super) struct Run<'a, F, P: ?Sized, B: ?Sized, S: ?Sized, L: ?Sized, O> {
    tally: Tally<'a, F, P, B, L>,
    chains: &'a mut S,
    x: &'a mut [F],
    y: &'a mut [F],
    grad: &'a mut [F],
    v: &'a mut [F],
    base: &'a mut [F],
    g0: &'a mut [F],
    observer: O,
    /// The best value at the observer's last call.
    seen: Option<F>,
    /// The problem's units, and the settings measured in them: the
    /// ladder's centre and the step.
    units: Units<F>,
    a0: F,
    h: F,
    /// The problem's target, stall and round rules.
    rules: Rules<F>,
    /// The best value when it last fell by more than the stall tolerance,
    /// and the round it did; the same for the convergence tolerance.
    stall_from: (F, u64),
    converge_from: (F, u64),
    /// The last round at whose end some chain's basin was not the best's.
    agree_from: u64,
    /// The convergence rule's window, and the spread of `U` at the initial
    /// points its tolerances are relative to.
    converge: Option<u64>,
    spread: F,
    /// The rule that ended the rounds.
    ended: Option<Termination>,
    /// The longest step the box allows, in the problem's units.
    longest: F,
    /// Each rung's step as a multiple of `h` (beyond [`SLOTS`] rungs,
    /// neighbouring rungs share one).
    scale: [F; SLOTS],
}

/// The least decrease of `U`, in value tolerances, that a quench's line
/// search is tried for: above the rounding of the values it compares, so
/// that the problem in other units makes the same decisions.
const RESOLUTION: f64 = 16.0;
/// Rungs whose steps adapt apart.
const SLOTS: usize = 16;
/// The gain of the step rule: `ln h_c` moves by `KAPPA (1 - accept)` after
/// an accepted proposal and by `-KAPPA accept` after a rejected one.
const KAPPA: f64 = 0.3;

impl<'a, F, P, B, S, L, O> Run<'a, F, P, B, S, L, O>
where
    F: Float,
    P: BatchPotential<F> + ?Sized,
    B: Sides<F> + ?Sized,
    S: Chains<F> + ?Sized,
    S::Rng: Rng + SeedableRng + 'static,
    L: Quencher<F> + ?Sized,
    O: FnMut(&Seen<'_, F>) -> ControlFlow<()>,
{
    /// Every chain's initial point, as [`start`](Self::start) says: the
    /// evaluations spent, and the lowest value (its point written to
    /// `best`).
    fn first_points(
        chains: &mut S,
        one: &One<'_, P>,
        domain: &B,
        x0: Option<&[F]>,
        budget: u64,
        seed: u64,
        best: &mut [F],
    ) -> Result<(u64, F), Error> {
        let n = chains.len();
        let mut spare = budget - n as u64;
        let mut evaluations = 0;
        let mut best_value = F::INFINITY;
        for c in 0..n {
            let chain = chains.chain(c);
            *chain.rng = S::Rng::seed_from_u64(chain_seed(seed, c as u64));
            chain.y.fill(F::ZERO);
            *chain.diverged = false;
            *chain.value = match x0 {
                Some(x0) if c == 0 => given_point(x0, chain.x, chain.grad, one)?,
                _ => draw_point(
                    c,
                    chain.x,
                    chain.grad,
                    chain.rng,
                    one,
                    &mut spare,
                    &mut evaluations,
                    |rng, x| domain.uniform(rng, x),
                )?,
            };
            if x0.is_some() && c == 0 {
                evaluations += 1;
            }
            if *chain.value < best_value {
                best_value = *chain.value;
                best.copy_from_slice(chain.x);
            }
            chains.started(c);
        }
        Ok((evaluations, best_value))
    }

    /// Draws every chain's initial point uniformly in the box (redrawn
    /// where infeasible, up to [`START_TRIES`](crate::START_TRIES), within
    /// the budget), but chain 0's where the caller gave `x0` (in the box):
    /// that point itself, an error where it is infeasible. `budget` is at
    /// least twice the number of chains, and every slice has the run's
    /// dimension.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn start(
        auto: &'a Auto<F>,
        potential: &'a P,
        domain: &'a B,
        x0: Option<&[F]>,
        budget: u64,
        seed: u64,
        chains: &'a mut S,
        lbfgs: &'a mut L,
        buffers: Buffers<'a, F>,
        observer: O,
    ) -> Result<Self, Error> {
        let Buffers {
            best,
            x,
            y,
            grad,
            v,
            base,
            g0,
        } = buffers;
        let one = One::new(potential);
        let (evaluations, best_value) =
            Self::first_points(&mut *chains, &one, domain, x0, budget, seed, best)
                .map_err(|e| one.cause(e))?;
        Ok(Self {
            tally: Tally {
                auto,
                potential: one,
                domain,
                unit: Unit::new(domain, best.len()),
                lbfgs,
                scale: Scale::ONE,
                budget,
                overrun: budget,
                evaluations,
                rounds: 0,
                best,
                best_value,
                polished: false,
            },
            chains,
            x,
            y,
            grad,
            v,
            base,
            g0,
            observer,
            seen: None,
            units: Units {
                length: F::ONE,
                energy: F::ONE,
            },
            a0: F::ONE,
            h: F::ONE,
            rules: Rules::new(),
            stall_from: (F::INFINITY, 0),
            converge_from: (F::INFINITY, 0),
            agree_from: 0,
            converge: None,
            spread: F::ZERO,
            ended: None,
            longest: F::ONE,
            scale: [F::ONE; SLOTS],
        })
    }

    /// The run with the problem's target, stall and round `rules`, and
    /// its convergence window.
    pub(super) fn with_rules(mut self, rules: Rules<F>, converge: Option<u64>) -> Self {
        self.rules = rules;
        self.converge = converge;
        self
    }

    /// Lets the first quench run on to `hard` evaluations (see
    /// [`Problem::soft_budget`](super::Problem::soft_budget)).
    pub(super) fn with_overrun(mut self, hard: u64) -> Self {
        self.tally.overrun = hard.max(self.tally.budget);
        self
    }

    /// The rule that ends the rounds before the next one, if any.
    fn rule(&mut self) -> Option<Termination> {
        let best = self.tally.best_value;
        let rounds = self.tally.rounds;
        let tolerance = self.rules.stall.map_or(F::ZERO, |(_, t)| t);
        if best < self.stall_from.0 - tolerance {
            self.stall_from = (best, rounds);
        }
        if best < self.converge_from.0 - F::from_f64(measure::CONVERGED) * self.spread {
            self.converge_from = (best, rounds);
        }
        // Every basin the best's: one basin found again and again.
        let agree = F::from_f64(measure::AGREE) * self.spread;
        if (0..self.chains.len()).any(|c| self.chains.value(c) - best > agree) {
            self.agree_from = rounds;
        }
        self.rules
            .holds(best, rounds, 0, 0, self.stall_from.1)
            .or_else(|| {
                let window = self.converge?;
                let quiet = rounds - self.converge_from.1;
                let agreed = rounds - self.agree_from.max(self.converge_from.1);
                (quiet >= window || agreed >= (window / measure::AGREED_SHARE).max(1))
                    .then_some(Termination::Converged)
            })
    }

    /// Why the run ended when it was not stopped: a rule, or the budget.
    pub(super) fn ended(&self) -> Termination {
        self.ended.unwrap_or(Termination::Evaluations)
    }

    /// Whether the potential stopped the run.
    pub(super) fn stopped(&self) -> bool {
        self.tally.potential.stopped.get()
    }

    /// The method: quench the initial points, measure the settings, then
    /// rounds until the budget is spent, then polish the best point.
    pub(super) fn solve(&mut self) -> Flow {
        self.spread = self.spread();
        self.observe()?;
        let mut values = [F::ZERO; 64];
        let m = self.sample_values(&mut values);
        self.units = Units::start(self.tally.unit.widest(), &mut values[..m]);
        self.tally.scale = self.scale(false);
        if self.tally.auto.parts.quenches {
            // The lowest initial point first: where the budget ends within
            // the quenches, the best start has been searched.
            let n = self.chains.len();
            let lowest = self.best_chain();
            let order = core::iter::once(lowest).chain((0..n).filter(move |&c| c != lowest));
            for c in order {
                self.x.copy_from_slice(self.chains.x(c));
                self.grad.copy_from_slice(self.chains.chain(c).grad);
                let start = Some((self.chains.value(c), &mut *self.grad));
                let cap = self.tally.auto.first_quench;
                // The best start's quench may overrun the soft budget; what
                // it spent past it is then the run's budget.
                let planned = self.tally.budget;
                if c == lowest {
                    self.tally.budget = self.tally.overrun;
                }
                let quenched = self.tally.quench(c, self.x, self.base, start, cap);
                self.tally.budget = planned.max(self.tally.evaluations);
                if let Some(value) = quenched? {
                    settle(self.chains.chain(c), self.x, value, self.grad);
                }
                self.observe()?;
            }
        }
        self.measure()?;
        self.stall_from = (self.tally.best_value, 0);
        self.converge_from = (self.tally.best_value, 0);
        while self.tally.remaining() > self.tally.reserve() {
            if let Some(rule) = self.rule() {
                self.ended = Some(rule);
                break;
            }
            let before = self.tally.evaluations;
            self.round()?;
            if self.tally.evaluations == before {
                // Nothing left that moves a chain (every part switched off).
                break;
            }
        }
        self.polish()
    }

    /// The values of up to 64 chains, evenly spaced, into `values`: how
    /// many.
    fn sample_values(&self, values: &mut [F; 64]) -> usize {
        let n = self.chains.len();
        let m = n.min(64);
        for (i, v) in values.iter_mut().take(m).enumerate() {
            *v = self.chains.value(i * n / m);
        }
        m
    }

    /// The problem's units as the quenches take them: their first step is
    /// one of unit curvature once the curvature is `measured`, and before,
    /// bounded by the box alone (the values at random points tell nothing
    /// of the basins' curvature).
    fn scale(&self, measured: bool) -> Scale<F> {
        let Units { length, energy } = self.units;
        Scale {
            length,
            energy,
            step: if measured {
                length * length / energy
            } else {
                F::INFINITY
            },
            resolution: F::from_f64(RESOLUTION),
        }
    }

    /// The problem's units and the settings in them: the curvature along
    /// a random direction at up to [`PROBES`] basins (one evaluation each),
    /// each coordinate displaced in proportion to its side of the box,
    /// sets the unit of energy; the ladder's centre comes from the basins'
    /// values in it, and the step from the box.
    fn measure(&mut self) -> Flow {
        let n = self.chains.len();
        let probes = n.min(PROBES);
        let domain = self.tally.domain;
        let delta = F::from_f64(1e-4);
        let mut curvature = [F::ZERO; PROBES];
        for (i, k) in curvature.iter_mut().take(probes).enumerate() {
            let c = i * n / probes;
            let chain = self.chains.chain(c);
            moves::direction(chain.rng, self.v);
            self.g0.copy_from_slice(chain.grad);
            self.base.copy_from_slice(chain.x);
            self.x.copy_from_slice(self.base);
            for (j, (xi, &vi)) in self.x.iter_mut().zip(&*self.v).enumerate() {
                let (lo, hi) = domain.side(j);
                *xi += delta * (hi - lo) * vi;
            }
            domain.project(self.x);
            // The basin's own gradient is the chain's (the quench's end):
            // the displaced end alone is evaluated.
            let Some(_) = self.tally.evaluate(self.x, self.grad)? else {
                continue;
            };
            // The curvature in the box's unit coordinates, where the
            // dynamics run.
            let unit = self.tally.unit;
            let mut dx2 = F::ZERO;
            let mut dg = F::ZERO;
            for j in 0..self.x.len() {
                let w = unit.w(j);
                let dx = (self.x[j] - self.base[j]) / w;
                dx2 += dx * dx;
                dg += (self.grad[j] - self.g0[j]) * w * dx;
            }
            *k = if dx2 > F::ZERO {
                (dg / dx2).abs()
            } else {
                F::ZERO
            };
        }
        let curvature = measure::median_curvature(&mut curvature[..probes]);
        let mut values = [F::ZERO; 64];
        let m = self.sample_values(&mut values);
        self.units = self.units.measured(curvature, &mut values[..m]);
        self.tally.scale = self.scale(true);
        // A quench before the measurement converged in the units of the
        // spread of values at random points, often orders of magnitude
        // coarser than the basins' own: its end is no minimum in these.
        self.tally.polished = false;
        self.a0 = measure::centre(&mut values[..m], self.units.energy);
        // The step's cap: a tenth of the narrowest side in unit coordinates.
        let mut width = F::INFINITY;
        for j in 0..self.x.len() {
            let (lo, hi) = self.tally.unit.side(j);
            if hi - lo < width {
                width = hi - lo;
            }
        }
        self.longest = measure::longest(width / self.units.length);
        self.h = measure::step(curvature, self.tally.auto.step_scale, self.longest);
        self.observe()
    }

    /// One round: every chain proposes and accepts or rejects a new basin,
    /// then the ladder's neighbours exchange.
    fn round(&mut self) -> Flow {
        let n = self.chains.len();
        for c in 0..n {
            if self.tally.remaining() <= self.tally.reserve() {
                return ControlFlow::Continue(());
            }
            self.propose(c)?;
            self.observe()?;
        }
        self.tally.rounds += 1;
        self.exchange();
        ControlFlow::Continue(())
    }

    /// Chain `c` leaves its basin by sampling, quenches, and accepts the
    /// new basin by Metropolis at its temperature: the three steps of a
    /// round, each its own method.
    fn propose(&mut self, c: usize) -> Flow {
        let a = self.rung(c);
        let Units { length, energy } = self.units;
        self.x.copy_from_slice(self.chains.x(c));
        self.y.copy_from_slice(self.chains.chain(c).y);
        self.grad.fill(F::ZERO);
        let point = Point::Known(self.chains.value(c));
        let n = self.chains.len();
        let slot = if n > SLOTS { c * SLOTS / n } else { c };
        let h = measure::clamp(self.h * self.scale[slot], measure::H_RANGE);
        let kernel = match Hrla::paper(h).and_then(|s| s.at(a)) {
            Ok(k) => k.in_units(length, energy),
            Err(e) => return ControlFlow::Break(Stop::Failed(e)),
        };
        let point = self.sample(c, &kernel, point)?;
        if !matches!(point, Point::Rejected) {
            self.chains.chain(c).y.copy_from_slice(self.y);
        }
        match self.settle(c, point)? {
            Point::Known(value) => self.accept(c, a / energy, slot, value),
            _ => self.reject(c),
        }
    }

    /// Langevin sampling: `steps` steps of `kernel` from the proposal's
    /// point, each new point evaluated.
    fn langevin(
        &mut self,
        c: usize,
        kernel: &OuKernel<F>,
        point: Point<F>,
        steps: u64,
    ) -> ControlFlow<Stop, Point<F>> {
        // Whether `self.grad` is the gradient evaluated at the point (at a
        // known basin it is taken as zero).
        let mut evaluated = !matches!(point, Point::Known(_));
        let mut value = match point {
            Point::Known(value) => value,
            _ => match self.tally.evaluate(self.x, self.grad)? {
                Some(value) => value,
                None => return ControlFlow::Continue(Point::Rejected),
            },
        };
        // The trajectory in unit coordinates (`self.x`, with the
        // momentum), each point evaluated at its place in the box
        // (`self.base`). In a box of equal sides they are the same, and
        // the maps are skipped.
        let unit = self.tally.unit;
        let identity = unit.is_identity();
        unit.scale_in(self.x);
        for _ in 0..steps {
            let g: &[F] = if identity {
                self.grad
            } else {
                unit.gradient(self.grad, self.g0);
                self.g0
            };
            self.v.copy_from_slice(self.x);
            kernel.step_slice(self.x, self.y, g, self.chains.chain(c).rng);
            unit.confine(self.x, self.y);
            if evaluated && *self.x == *self.v {
                // Held where it was (in a corner of the box, every
                // coordinate against its wall): the point's value and
                // gradient are known.
                self.observe()?;
                continue;
            }
            let at: &[F] = if identity {
                self.x
            } else {
                unit.point_of(self.x, self.base);
                self.base
            };
            match self.tally.evaluate(at, self.grad)? {
                Some(v) => value = v,
                None => return ControlFlow::Continue(Point::Rejected),
            }
            evaluated = true;
            self.observe()?;
        }
        if !identity {
            self.x.copy_from_slice(self.base);
        }
        ControlFlow::Continue(Point::Evaluated(value))
    }

    /// Step 1, sampling: [`Auto::steps`] steps of `kernel` from the
    /// proposal's point (each evaluated, with Langevin sampling), or free
    /// moves (jump sampling), or a differential move.
    fn sample(
        &mut self,
        c: usize,
        kernel: &OuKernel<F>,
        point: Point<F>,
    ) -> ControlFlow<Stop, Point<F>> {
        let steps = self.tally.auto.steps;
        match self.tally.auto.parts.sampling {
            Sampling::Langevin => self.langevin(c, kernel, point, steps),
            Sampling::Jump => {
                let unit = self.tally.unit;
                unit.scale_in(self.x);
                moves::free(
                    kernel,
                    self.x,
                    self.y,
                    self.g0,
                    steps,
                    &unit,
                    self.chains.chain(c).rng,
                );
                unit.scale_out(self.x);
                ControlFlow::Continue(Point::Unknown)
            }
            Sampling::Differential => {
                let n = self.chains.len();
                let rng = self.chains.chain(c).rng;
                let (i, j) = match n {
                    // A lone chain has no difference to move along.
                    1 => return ControlFlow::Continue(point),
                    2 => (1 - c, c),
                    _ => moves::pair(rng, c, n),
                };
                let gamma = moves::gamma(rng);
                moves::differential(
                    self.x,
                    self.chains.x(i),
                    self.chains.x(j),
                    gamma,
                    self.tally.domain,
                    self.g0,
                );
                ControlFlow::Continue(Point::Unknown)
            }
        }
    }

    /// Step 2, the quench: L-BFGS from the proposal's point to the bottom
    /// of its basin (or, without quenches, the point evaluated where its
    /// value is not known).
    fn settle(&mut self, c: usize, point: Point<F>) -> ControlFlow<Stop, Point<F>> {
        if let Point::Rejected = point {
            return ControlFlow::Continue(point);
        }
        let found = if self.tally.auto.parts.quenches {
            let start = match point {
                Point::Evaluated(value) => Some((value, &mut *self.grad)),
                _ => None,
            };
            let found = self
                .tally
                .quench(c, self.x, self.base, start, self.tally.auto.quench)?;
            if found.is_some() {
                self.grad.fill(F::ZERO);
            }
            found
        } else if let Point::Known(value) | Point::Evaluated(value) = point {
            Some(value)
        } else {
            self.tally.evaluate(self.x, self.grad)?
        };
        ControlFlow::Continue(found.map_or(Point::Rejected, Point::Known))
    }

    /// Step 3, acceptance: Metropolis on the quenched values at `a`; the
    /// rung's step then follows the verdict.
    fn accept(&mut self, c: usize, a: F, slot: usize, value: F) -> Flow {
        let chain = self.chains.chain(c);
        *chain.diverged = false;
        let old = *chain.value;
        // Drawn whatever the values: where they differ by their rounding
        // alone, the stream does not depend on which is lower.
        let draw: F = moves::uniform(chain.rng);
        let accept = value <= old || draw < (-a * (value - old)).exp();
        if accept {
            chain.x.copy_from_slice(self.x);
            *chain.value = value;
            chain.grad.copy_from_slice(self.grad);
        }
        self.adapt(slot, accept);
        ControlFlow::Continue(())
    }

    /// A rung's step follows its acceptance rate towards [`Auto::accept`]
    /// (a Robbins–Monro step on `ln h_c`, as adaptive Metropolis samplers
    /// steer their proposals): a rung that accepts too often barely leaves
    /// its basin, one that accepts too rarely jumps into worse ones. At the
    /// target rate the step stays put on average.
    fn adapt(&mut self, slot: usize, accept: bool) {
        let target = self.tally.auto.accept;
        if target <= F::ZERO {
            return;
        }
        let hit = if accept { F::ONE } else { F::ZERO };
        let scale = self.scale[slot] * (F::from_f64(KAPPA) * (hit - target)).exp();
        let (lo, hi) = (F::from_f64(1e-3), self.longest / self.h);
        self.scale[slot] = if scale > hi {
            hi
        } else if scale < lo {
            lo
        } else {
            scale
        };
    }

    /// A proposal that met an infeasible point: the chain stays in its
    /// basin, at rest.
    fn reject(&mut self, c: usize) -> Flow {
        let chain = self.chains.chain(c);
        *chain.diverged = true;
        chain.y.fill(F::ZERO);
        ControlFlow::Continue(())
    }

    /// Replica exchange: each pair of neighbouring rungs, hottest first,
    /// swaps basins with probability `min(1, exp((a_{c+1} - a_c)(U_{c+1} - U_c)))`.
    fn exchange(&mut self) {
        let n = self.chains.len();
        for c in 0..n.saturating_sub(1) {
            let (a, b) = (self.temperature(c), self.temperature(c + 1));
            let delta = (b - a) * (self.chains.value(c + 1) - self.chains.value(c));
            let draw: F = moves::uniform(self.chains.chain(c).rng);
            let swap = delta >= F::ZERO || draw < delta.exp();
            if swap {
                self.chains.swap(c);
            }
        }
    }

    /// The best point polished by L-BFGS until it converges, if no
    /// converged quench ended there, with what is left of the budget.
    fn polish(&mut self) -> Flow {
        let tally = &mut self.tally;
        if tally.polished || tally.remaining() == 0 {
            return ControlFlow::Continue(());
        }
        self.x.copy_from_slice(tally.best);
        // To the float type's precision: the quenches' resolution (and a
        // value tolerance) stops them while U still falls in a narrow
        // valley, many times the rounding of U where U's minimum is 0. The
        // search ends where the gradient vanishes or no step lowers U, at
        // most what is left of the budget.
        let mut settings = PolishSettings::new(tally.remaining());
        settings.value_tolerance = F::ZERO;
        let quenches = tally.scale;
        tally.scale.resolution = F::ZERO;
        let done = tally.local(self.x, self.base, None, settings);
        tally.scale = quenches;
        match done {
            Ok(done) => {
                tally.evaluations += done.evaluations;
                tally.record(self.x, done.value, done.end != PolishEnd::Budget);
            }
            Err(Error::NotFinite { .. }) => tally.evaluations += 1,
            Err(Error::UnboundedBelow { value, .. }) => {
                return ControlFlow::Break(Stop::Failed(Error::UnboundedBelow {
                    chain: self.best_chain(),
                    value,
                }));
            }
            Err(e) => return ControlFlow::Break(Stop::Failed(e)),
        }
        self.observe()
    }

    /// The spread of `U` at (up to 64 of) the chains' points: the
    /// problem's scale of values, before any quench (0 where `U` is 0 at
    /// every one).
    fn spread(&self) -> F {
        let n = self.chains.len();
        let m = n.min(64);
        let mut values = [F::ZERO; 64];
        for (i, v) in values.iter_mut().take(m).enumerate() {
            *v = self.chains.value(i * n / m);
        }
        measure::spread(&mut values[..m]).unwrap_or(F::ZERO)
    }

    /// Chain `c`'s inverse temperature in the problem's units.
    fn rung(&self, c: usize) -> F {
        measure::rung(self.a0, self.tally.auto.ladder, c, self.chains.len())
    }

    /// Chain `c`'s inverse temperature in `U`'s units.
    fn temperature(&self, c: usize) -> F {
        self.rung(c) / self.units.energy
    }

    fn best_chain(&self) -> usize {
        (0..self.chains.len())
            .min_by(|&i, &j| {
                self.chains
                    .value(i)
                    .partial_cmp(&self.chains.value(j))
                    .unwrap_or(core::cmp::Ordering::Equal)
            })
            .unwrap_or(0)
    }

    fn diverged(&self) -> usize {
        (0..self.chains.len())
            .filter(|&c| self.chains.diverged(c))
            .count()
    }

    fn observe(&mut self) -> Flow {
        let value = self.tally.best_value;
        if self.rules.target.is_some_and(|t| value <= t) {
            return ControlFlow::Break(Stop::Target);
        }
        let improved = self.seen.is_none_or(|v| value < v);
        self.seen = Some(value);
        let seen = Seen {
            evaluations: self.tally.evaluations,
            rounds: self.tally.rounds,
            x: self.tally.best,
            value,
            improved,
            inverse_temperature: self.temperature(self.chains.len() - 1),
            diverged_chains: self.diverged(),
        };
        match (self.observer)(&seen) {
            ControlFlow::Continue(()) => ControlFlow::Continue(()),
            ControlFlow::Break(()) => ControlFlow::Break(Stop::Observer),
        }
    }

    /// The run's outcome, ended for `termination`.
    pub(super) fn found(&self, termination: Termination) -> Found<F> {
        Found {
            value: self.tally.best_value,
            evaluations: self.tally.evaluations,
            rounds: self.tally.rounds,
            step: self.units.step(self.h),
            inverse_temperature: measure::clamp(self.rung(self.chains.len() - 1), A_RANGE)
                / self.units.energy,
            termination,
            diverged_chains: self.diverged(),
            chains: self.chains.len(),
        }
    }
}

/// `U` at the caller's start `x0`, copied into `x` (one evaluation):
/// where it is infeasible, an error naming `x0` rather than a redraw, since
/// the caller chose that point.
fn given_point<F, P>(x0: &[F], x: &mut [F], grad: &mut [F], potential: &P) -> Result<F, Error>
where
    F: Float,
    P: SlicePotential<F> + ?Sized,
{
    x.copy_from_slice(x0);
    let value = potential.value_and_gradient(x, grad);
    match judge(x, value, grad, floor()) {
        Verdict::Feasible => Ok(value),
        Verdict::Unbounded => Err(Error::UnboundedBelow {
            chain: 0,
            value: value.to_f64(),
        }),
        Verdict::Infeasible(what) => Err(Error::NotFinite {
            name: if what == "gradient" {
                "the gradient at x0"
            } else {
                "U at x0"
            },
            value: if what == "gradient" {
                grad.iter()
                    .copied()
                    .find(|g| !g.is_finite())
                    .unwrap_or(F::INFINITY)
                    .to_f64()
            } else {
                value.to_f64()
            },
        }),
    }
}

/// Chain `c` takes the basin `(x, value)` with its gradient `grad`, at
/// rest.
fn settle<F: Float, R>(chain: ChainMut<'_, F, R>, x: &[F], value: F, grad: &[F]) {
    chain.x.copy_from_slice(x);
    *chain.value = value;
    chain.grad.copy_from_slice(grad);
    chain.y.fill(F::ZERO);
    *chain.diverged = false;
}

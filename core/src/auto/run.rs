//! One run of [`Auto`]: its state, and each step of the method by name.

use core::ops::ControlFlow;

use rand_core::{Rng, SeedableRng};

use super::measure::{self, A_RANGE};
use super::moves;
use super::{Auto, AutoProgress, Sampling, Solution};
use crate::domain::{Domain, Interval};
use crate::error::{Error, floor};
use crate::float::Float;
use crate::optimizer::{Best, Chain, Termination, chain_seed, draw_start};
use crate::optimizer::{Verdict, judge};
use crate::polish::{Lbfgs, PolishEnd, PolishSettings};
use crate::potential::traits::Potential;
use crate::sampler::{Hrla, Sampler};
use crate::start::Start;

/// Why a run ended early.
pub(super) enum Stop {
    /// The evaluation budget is spent.
    Budget,
    /// The observer asked to stop.
    Observer,
    /// A failure to report (a potential unbounded below).
    Failed(Error),
}

type Flow = ControlFlow<Stop>;

/// Chains whose curvature is probed: their median suffices.
const PROBES: usize = 16;

/// A run in progress. Each chain's `x`, `value` and `grad` hold its basin
/// (the quenched point; the gradient there is taken as zero, its value at
/// a converged minimum), `y` the momentum its last trajectory ended with,
/// `diverged` whether its last proposal met an infeasible point.
pub(super) struct Run<'a, F, P: ?Sized, R, const D: usize, const M: usize, O> {
    auto: &'a Auto<F>,
    potential: &'a P,
    domain: Interval<F>,
    budget: u64,
    chains: &'a mut [Chain<F, D, R>],
    lbfgs: &'a mut Lbfgs<F, D, M>,
    observer: O,
    evaluations: u64,
    rounds: u64,
    /// The best feasible point evaluated, and whether a converged L-BFGS
    /// ended there.
    best: Best<F, D>,
    polished: bool,
    /// The best value at the observer's last call.
    seen: Option<F>,
    /// The measured settings: the ladder's centre and the step.
    a0: F,
    h: F,
    /// Rounds since the best last fell.
    stalled: u64,
}

impl<'a, F, P, R, const D: usize, const M: usize, O> Run<'a, F, P, R, D, M, O>
where
    F: Float,
    P: Potential<F, D> + ?Sized,
    R: Rng + SeedableRng + 'static,
    O: FnMut(&AutoProgress<'_, F, D>) -> ControlFlow<()>,
{
    /// Draws every chain's initial point uniformly in the box (redrawn
    /// where infeasible, up to [`START_TRIES`], within the budget).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn start(
        auto: &'a Auto<F>,
        potential: &'a P,
        domain: Interval<F>,
        budget: u64,
        seed: u64,
        chains: &'a mut [Chain<F, D, R>],
        lbfgs: &'a mut Lbfgs<F, D, M>,
        observer: O,
    ) -> Result<Self, Error> {
        let n = chains.len() as u64;
        let mut spare = budget - n;
        let mut evaluations = 0;
        let mut best = Best {
            x: [F::ZERO; D],
            value: F::INFINITY,
            iteration: 0,
        };
        let mut start = domain;
        for (c, chain) in chains.iter_mut().enumerate() {
            chain.rng = R::seed_from_u64(chain_seed(seed, c as u64));
            chain.y = [F::ZERO; D];
            chain.diverged = false;
            draw_start(
                c,
                chain,
                potential,
                &mut spare,
                &mut evaluations,
                |rng, x, _| start.initial_point(c, rng, x),
            )?;
            chain.best = Best {
                x: chain.x,
                value: chain.value,
                iteration: 0,
            };
            if chain.value < best.value {
                best = chain.best;
            }
        }
        Ok(Self {
            auto,
            potential,
            domain,
            budget,
            chains,
            lbfgs,
            observer,
            evaluations,
            rounds: 0,
            best,
            polished: false,
            seen: None,
            a0: F::ONE,
            h: F::ONE,
            stalled: 0,
        })
    }

    /// The method: quench the initial points, measure the settings, then
    /// rounds until the budget is spent, then polish the best point.
    pub(super) fn solve(&mut self) -> Flow {
        self.observe()?;
        if self.auto.parts.quenches {
            for c in 0..self.chains.len() {
                let x = self.chains[c].x;
                if let Some((x, value)) = self.quench(c, x)? {
                    self.settle(c, x, value);
                }
                self.observe()?;
            }
        }
        self.measure()?;
        while self.remaining() > self.reserve() {
            let before = self.evaluations;
            self.round()?;
            if self.evaluations == before {
                // Nothing left that moves a chain (every part switched off).
                break;
            }
        }
        self.polish()
    }

    /// The ladder's centre from the basins' values, the step from the
    /// curvature along a random direction at up to [`PROBES`] basins (one
    /// evaluation each).
    fn measure(&mut self) -> Flow {
        let n = self.chains.len();
        let m = n.min(64);
        let mut values = [F::ZERO; 64];
        for (i, v) in values.iter_mut().take(m).enumerate() {
            *v = self.chains[i * n / m].value;
        }
        self.a0 = measure::centre(&mut values[..m]);
        let probes = n.min(PROBES);
        let width = self.domain.hi() - self.domain.lo();
        let delta = F::from_f64(1e-4) * width;
        let mut curvature = [F::ZERO; PROBES];
        for (i, k) in curvature.iter_mut().take(probes).enumerate() {
            let c = i * n / probes;
            let v: [F; D] = moves::direction(&mut self.chains[c].rng);
            let base = self.chains[c].x;
            let mut g0 = [F::ZERO; D];
            let mut g1 = [F::ZERO; D];
            let mut x = base;
            for (xi, vi) in x.iter_mut().zip(v) {
                *xi += delta * vi;
            }
            self.domain.project(&mut x);
            // Both ends evaluated: the basin's gradient is not stored.
            let (Some(_), Some(_)) = (self.evaluate(&base, &mut g0)?, self.evaluate(&x, &mut g1)?)
            else {
                continue;
            };
            let mut dx2 = F::ZERO;
            let mut dg = F::ZERO;
            for j in 0..D {
                let dx = x[j] - base[j];
                dx2 += dx * dx;
                dg += (g1[j] - g0[j]) * dx;
            }
            *k = if dx2 > F::ZERO {
                (dg / dx2).abs()
            } else {
                F::ZERO
            };
        }
        self.h = measure::step(&mut curvature[..probes], self.auto.step_scale, width);
        self.observe()
    }

    /// One round: every chain proposes and accepts or rejects a new basin,
    /// then the ladder's neighbours exchange, then a stalled run restarts
    /// its hotter half.
    fn round(&mut self) -> Flow {
        let before = self.best.value;
        let n = self.chains.len();
        for c in 0..n {
            if self.remaining() <= self.reserve() {
                return ControlFlow::Continue(());
            }
            self.propose(c)?;
            self.observe()?;
        }
        self.rounds += 1;
        self.exchange();
        self.stalled = if self.best.value < before {
            0
        } else {
            self.stalled + 1
        };
        if self.auto.parts.global_moves && self.stalled >= self.auto.stall {
            self.stalled = 0;
            self.restart()?;
        }
        ControlFlow::Continue(())
    }

    /// Chain `c` leaves its basin (global move, then sampling), quenches,
    /// and accepts the new basin by Metropolis at its temperature.
    fn propose(&mut self, c: usize) -> Flow {
        let n = self.chains.len();
        let parts = self.auto.parts;
        let a = self.rung(c);
        let mut x = self.chains[c].x;
        let mut y = self.chains[c].y;
        let mut grad = [F::ZERO; D];
        let mut value = self.chains[c].value;
        let mut known = true;
        let jump = parts.global_moves
            && n >= 3
            && (parts.sampling == Sampling::Off
                || moves::chance(&mut self.chains[c].rng, self.auto.jump_rate));
        if jump {
            let rng = &mut self.chains[c].rng;
            let i = (c + 1 + moves::index(rng, n - 1)) % n;
            let mut j = (c + 1 + moves::index(rng, n - 2)) % n;
            if j == i {
                j = (i + 1) % n;
                if j == c {
                    j = (j + 1) % n;
                }
            }
            let (p, q) = (self.chains[i].x, self.chains[j].x);
            moves::differential(&mut x, &p, &q, self.domain, &mut self.chains[c].rng);
            known = false;
        }
        let kernel = match Hrla::paper(self.h).and_then(|s| s.at(a)) {
            Ok(k) => k,
            Err(e) => return ControlFlow::Break(Stop::Failed(e)),
        };
        match parts.sampling {
            Sampling::Langevin => {
                if !known {
                    match self.evaluate(&x, &mut grad)? {
                        Some(v) => value = v,
                        None => return self.reject(c),
                    }
                }
                for _ in 0..self.auto.steps {
                    crate::sampler::Kernel::step(
                        &kernel,
                        &mut x,
                        &mut y,
                        &grad,
                        &mut self.chains[c].rng,
                    );
                    self.domain.confine(&mut x, &mut y);
                    match self.evaluate(&x, &mut grad)? {
                        Some(v) => value = v,
                        None => return self.reject(c),
                    }
                    self.observe()?;
                }
                known = true;
            }
            Sampling::Jump => {
                moves::free(
                    &kernel,
                    &mut x,
                    &mut y,
                    self.auto.steps,
                    self.domain,
                    &mut self.chains[c].rng,
                );
                known = false;
            }
            Sampling::Off => {}
        }
        self.chains[c].y = y;
        if parts.quenches {
            match self.quench(c, x)? {
                Some((q, v)) => {
                    x = q;
                    value = v;
                    grad = [F::ZERO; D];
                }
                None => return self.reject(c),
            }
        } else if !known {
            match self.evaluate(&x, &mut grad)? {
                Some(v) => value = v,
                None => return self.reject(c),
            }
        }
        self.chains[c].diverged = false;
        let old = self.chains[c].value;
        let accept = value <= old || {
            let p = (-a * (value - old)).exp();
            moves::chance(&mut self.chains[c].rng, p)
        };
        if accept {
            let chain = &mut self.chains[c];
            chain.x = x;
            chain.value = value;
            chain.grad = grad;
        }
        ControlFlow::Continue(())
    }

    /// A proposal that met an infeasible point: the chain stays in its
    /// basin, at rest.
    fn reject(&mut self, c: usize) -> Flow {
        self.chains[c].diverged = true;
        self.chains[c].y = [F::ZERO; D];
        ControlFlow::Continue(())
    }

    /// Replica exchange: each pair of neighbouring rungs, hottest first,
    /// swaps basins with probability `min(1, exp((a_{c+1} - a_c)(U_{c+1} - U_c)))`.
    fn exchange(&mut self) {
        let n = self.chains.len();
        for c in 0..n.saturating_sub(1) {
            let (a, b) = (self.rung(c), self.rung(c + 1));
            let delta = (b - a) * (self.chains[c + 1].value - self.chains[c].value);
            let swap = delta >= F::ZERO || moves::chance(&mut self.chains[c].rng, delta.exp());
            if swap {
                let (lo, hi) = self.chains.split_at_mut(c + 1);
                let (p, q) = (&mut lo[c], &mut hi[0]);
                core::mem::swap(&mut p.x, &mut q.x);
                core::mem::swap(&mut p.value, &mut q.value);
                core::mem::swap(&mut p.grad, &mut q.grad);
                core::mem::swap(&mut p.y, &mut q.y);
            }
        }
    }

    /// The hotter half of the ladder starts again uniformly in the box.
    fn restart(&mut self) -> Flow {
        for c in 0..self.chains.len() / 2 {
            if self.remaining() <= self.reserve() {
                break;
            }
            let mut x = [F::ZERO; D];
            moves::anywhere(self.domain, &mut self.chains[c].rng, &mut x);
            let mut grad = [F::ZERO; D];
            let Some(mut value) = self.evaluate(&x, &mut grad)? else {
                continue;
            };
            if self.auto.parts.quenches {
                let Some((q, v)) = self.quench(c, x)? else {
                    continue;
                };
                (x, value, grad) = (q, v, [F::ZERO; D]);
            }
            self.settle(c, x, value);
            self.chains[c].grad = grad;
            self.observe()?;
        }
        ControlFlow::Continue(())
    }

    /// The best point polished by L-BFGS until it converges, if no
    /// converged quench ended there, with what is left of the budget.
    fn polish(&mut self) -> Flow {
        if self.polished || self.remaining() == 0 {
            return ControlFlow::Continue(());
        }
        let x = self.best.x;
        let settings = PolishSettings::new(self.remaining());
        let mut y = x;
        match self
            .lbfgs
            .minimize_in(self.potential, &self.domain, &mut y, settings)
        {
            Ok(done) => {
                self.evaluations += done.evaluations;
                self.record(&y, done.value, done.end != PolishEnd::Budget);
            }
            Err(Error::NotFinite { .. }) => self.evaluations += 1,
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

    /// L-BFGS from `x` for chain `c`, within [`Auto::quench`] and the
    /// budget: its end and value, or `None` where `x` is infeasible.
    fn quench(&mut self, c: usize, mut x: [F; D]) -> ControlFlow<Stop, Option<([F; D], F)>> {
        let cap = self.auto.quench.min(self.remaining());
        if cap == 0 {
            return ControlFlow::Break(Stop::Budget);
        }
        match self.lbfgs.minimize_in(
            self.potential,
            &self.domain,
            &mut x,
            PolishSettings::new(cap),
        ) {
            Ok(done) => {
                self.evaluations += done.evaluations;
                self.record(&x, done.value, done.end != PolishEnd::Budget);
                ControlFlow::Continue(Some((x, done.value)))
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

    /// One evaluation at `x` within the budget: its value where feasible,
    /// `None` where not.
    fn evaluate(&mut self, x: &[F; D], grad: &mut [F; D]) -> ControlFlow<Stop, Option<F>> {
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

    /// A feasible point evaluated: the new best if it is lower.
    fn record(&mut self, x: &[F; D], value: F, converged: bool) {
        if value < self.best.value {
            self.best = Best {
                x: *x,
                value,
                iteration: self.rounds,
            };
            self.polished = converged;
        } else if value == self.best.value && converged && *x == self.best.x {
            self.polished = true;
        }
    }

    /// Chain `c` takes the basin `(x, value)`, at rest.
    fn settle(&mut self, c: usize, x: [F; D], value: F) {
        let chain = &mut self.chains[c];
        chain.x = x;
        chain.value = value;
        chain.grad = [F::ZERO; D];
        chain.y = [F::ZERO; D];
        chain.diverged = false;
    }

    fn rung(&self, c: usize) -> F {
        measure::rung(self.a0, self.auto.ladder, c, self.chains.len())
    }

    fn remaining(&self) -> u64 {
        self.budget - self.evaluations
    }

    /// Evaluations kept for the final polish while the best point is not
    /// a converged minimum: 5% of the budget, whatever a quench may take
    /// (a quench cut short is why the best is not converged).
    fn reserve(&self) -> u64 {
        if self.polished { 0 } else { self.budget / 20 }
    }

    fn best_chain(&self) -> usize {
        (0..self.chains.len())
            .min_by(|&i, &j| {
                self.chains[i]
                    .value
                    .partial_cmp(&self.chains[j].value)
                    .unwrap_or(core::cmp::Ordering::Equal)
            })
            .unwrap_or(0)
    }

    fn diverged(&self) -> usize {
        self.chains.iter().filter(|c| c.diverged).count()
    }

    fn observe(&mut self) -> Flow {
        let improved = self.seen.is_none_or(|v| self.best.value < v);
        self.seen = Some(self.best.value);
        let progress = AutoProgress {
            evaluations: self.evaluations,
            rounds: self.rounds,
            x: &self.best.x,
            value: self.best.value,
            improved,
            inverse_temperature: self.rung(self.chains.len() - 1),
            diverged_chains: self.diverged(),
        };
        match (self.observer)(&progress) {
            ControlFlow::Continue(()) => ControlFlow::Continue(()),
            ControlFlow::Break(()) => ControlFlow::Break(Stop::Observer),
        }
    }

    pub(super) fn solution(&self, termination: Termination) -> Solution<F, D> {
        Solution {
            x: self.best.x,
            value: self.best.value,
            evaluations: self.evaluations,
            rounds: self.rounds,
            step: self.h,
            inverse_temperature: measure::clamp(self.rung(self.chains.len() - 1), A_RANGE),
            termination,
            diverged_chains: self.diverged(),
            chains: self.chains.len(),
        }
    }
}

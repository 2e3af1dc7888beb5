//! One step of a run of consecutive chains ([`sweep`]) and what it found
//! ([`Sweep`]), the unit that the optimiser's step is made of, serially or
//! in parallel parts ([`Executor`](super::Executor)).
//!
//! Chains are independent: a sweep of chains `i..j` touches nothing of any
//! other chain, and [`Sweep::then`] combines the findings of neighbouring
//! sweeps associatively, so one step gives the same bits however the
//! chains are cut into parts and wherever the parts run.
//!
//! Where the target has float vectors, the chains use the default
//! generator and the point is large enough to pay
//! ([`LOCKSTEP_F64_FROM`] for `f64`), a sweep steps groups of [`LANES`]
//! live chains in lockstep
//! ([`Kernel::step_lanes`]); elsewhere chain after chain. Each chain draws
//! the same words either way.

use core::any::{Any, TypeId};

use rand_core::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::chain::Chain;
use crate::domain::Domain;
use crate::float::Float;
use crate::lanes;
use crate::lockstep::{LANES, Xoshiro256Lanes};
use crate::potential::Potential;
use crate::sampler::{ChainState, Kernel};

/// The smallest point size at which `f64` chains step in lockstep. Measured
/// on 10-D Rastrigin (interleaved A/B, `bench/ab`, time in lockstep over
/// time one by one): built for AVX2, d = 2 1.07, d = 10 0.94, d = 32 0.88,
/// d = 100 0.93; built for AVX-512 on the same machine, d = 2 1.05, d = 10
/// 1.09-1.13, d = 32 0.89, d = 100 0.91-0.95 (why AVX-512 code loses at
/// d = 10 is not known). `f32` gains or breaks even everywhere measured.
/// Bits are the same either way.
pub(crate) const LOCKSTEP_F64_FROM: usize = if cfg!(target_feature = "avx512f") {
    16
} else {
    8
};

/// What one step of some chains found.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sweep<F> {
    /// The lowest new value that improved its chain's best, with its chain:
    /// the first such chain on ties.
    pub best: Option<(F, usize)>,
    /// Potential evaluations.
    pub evaluated: u64,
    /// Chains that diverged in this step.
    pub diverged: usize,
    /// The first chain whose potential fell below the floor, with its value.
    pub unbounded: Option<(usize, F)>,
}

impl<F: Float> Sweep<F> {
    pub(crate) const NOTHING: Self = Self {
        best: None,
        evaluated: 0,
        diverged: 0,
        unbounded: None,
    };

    /// The findings of this sweep followed by those of the chains after it.
    /// Associative, so any grouping of neighbouring parts gives the same.
    pub(crate) fn then(self, later: Self) -> Self {
        let best = match (self.best, later.best) {
            (Some(a), Some(b)) => Some(if b.0 < a.0 { b } else { a }),
            (a, b) => a.or(b),
        };
        Self {
            best,
            evaluated: self.evaluated + later.evaluated,
            diverged: self.diverged + later.diverged,
            unbounded: self.unbounded.or(later.unbounded),
        }
    }
}

/// The read-only context of a step: the kernel at `a_k`, the potential and
/// the domain, the new iterate's index and whether it is recorded.
pub(crate) struct Context<'a, K, P, B, F> {
    pub kernel: &'a K,
    pub potential: &'a P,
    pub domain: &'a B,
    pub k: u64,
    pub record: bool,
    pub floor: F,
}

/// Steps every live chain of `chains` (chain `first + i` of the run is
/// `chains[i]`) and evaluates it.
pub(crate) fn sweep<F, K, P, B, R, const D: usize>(
    cx: &Context<'_, K, P, B, F>,
    chains: &mut [Chain<F, D, R>],
    first: usize,
) -> Sweep<F>
where
    F: Float,
    K: Kernel<F>,
    P: Potential<F, D>,
    B: Domain<F, D>,
    R: Rng + 'static,
{
    let mut found = Sweep::NOTHING;
    let lockstep = lanes::VECTORS
        && TypeId::of::<R>() == TypeId::of::<Xoshiro256PlusPlus>()
        && (F::MANTISSA_DIGITS <= 24 || D >= LOCKSTEP_F64_FROM);
    let grouped = if lockstep {
        chains.len() / LANES * LANES
    } else {
        0
    };
    let (groups, rest) = chains.split_at_mut(grouped);
    for (g, group) in groups.chunks_exact_mut(LANES).enumerate() {
        let Ok(group) = <&mut [Chain<F, D, R>; LANES]>::try_from(group) else {
            continue;
        };
        if group.iter().any(|c| c.diverged) || !step_lockstep(cx.kernel, group) {
            for c in group.iter_mut().filter(|c| !c.diverged) {
                cx.kernel.step(&mut c.x, &mut c.y, &c.grad, &mut c.rng);
            }
        }
        let first = first + g * LANES;
        for (i, c) in group.iter_mut().enumerate() {
            if !c.diverged {
                evaluate(cx, c, first + i, &mut found);
            }
        }
    }
    let first = first + grouped;
    for (i, c) in rest.iter_mut().enumerate() {
        if !c.diverged {
            cx.kernel.step(&mut c.x, &mut c.y, &c.grad, &mut c.rng);
            evaluate(cx, c, first + i, &mut found);
        }
    }
    found
}

/// Steps a group of live chains in lockstep; `false` (nothing stepped) if
/// their generators are not xoshiro256++.
#[inline]
fn step_lockstep<F, K, R, const D: usize>(kernel: &K, group: &mut [Chain<F, D, R>; LANES]) -> bool
where
    F: Float,
    K: Kernel<F>,
    R: 'static,
{
    let generators = group
        .each_ref()
        .map(|c| (&c.rng as &dyn Any).downcast_ref::<Xoshiro256PlusPlus>());
    let [Some(g0), Some(g1), Some(g2), Some(g3)] = generators else {
        return false;
    };
    let mut rng = Xoshiro256Lanes::load([g0, g1, g2, g3]);
    kernel.step_lanes(
        group.each_mut().map(|c| ChainState {
            x: &mut c.x,
            y: &mut c.y,
            grad: &c.grad,
        }),
        &mut rng,
    );
    let generators = group
        .each_mut()
        .map(|c| (&mut c.rng as &mut dyn Any).downcast_mut::<Xoshiro256PlusPlus>());
    if let [Some(g0), Some(g1), Some(g2), Some(g3)] = generators {
        rng.store([g0, g1, g2, g3]);
    }
    true
}

/// Confines a stepped chain to the domain, evaluates `U` and `∇U` there and
/// updates its running best, or marks it diverged.
#[inline(always)]
fn evaluate<F, K, P, B, R, const D: usize>(
    cx: &Context<'_, K, P, B, F>,
    chain: &mut Chain<F, D, R>,
    c: usize,
    found: &mut Sweep<F>,
) where
    F: Float,
    P: Potential<F, D>,
    B: Domain<F, D>,
{
    cx.domain.confine(&mut chain.x, &mut chain.y);
    let value = cx.potential.value_and_gradient(&chain.x, &mut chain.grad);
    found.evaluated += 1;
    chain.value = value;
    match judge(&chain.x, value, &chain.grad, cx.floor) {
        Verdict::Feasible => {}
        verdict => {
            // Frozen, so that a non-finite value or one below the floor
            // never becomes the best.
            if verdict == Verdict::Unbounded {
                found.unbounded.get_or_insert((c, value));
            }
            chain.diverged = true;
            found.diverged += 1;
            return;
        }
    }
    if cx.record && value < chain.best.value {
        // Field by field: a whole `Best` would be built on the stack first,
        // `D` floats of it.
        chain.best.x = chain.x;
        chain.best.value = value;
        chain.best.iteration = cx.k;
        if found.best.is_none_or(|(b, _)| value < b) {
            found.best = Some((value, c));
        }
    }
}

/// Without short-circuit, so that the checks vectorise: this runs on every
/// chain at every step, and a chain is almost always finite.
#[inline(always)]
pub(crate) fn all_finite<F: Float>(v: &[F]) -> bool {
    v.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// What a freshly evaluated point is to a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Verdict {
    /// Finite position, value and gradient, the value above the floor.
    Feasible,
    /// The position, the value or the gradient (named) is not finite: the
    /// point is outside the region where `U` is defined.
    Infeasible(&'static str),
    /// The value is `-inf` or below the floor, at a finite position: the
    /// potential looks unbounded below.
    Unbounded,
}

/// The one judgement of every point the crate evaluates for a run: the
/// initial points, the steps, the restarts (the polish checks its own
/// values against the same [`floor`](crate::error::floor)).
#[inline(always)]
pub(crate) fn judge<F: Float>(x: &[F], value: F, grad: &[F], floor: F) -> Verdict {
    if value < floor && all_finite(x) {
        Verdict::Unbounded
    } else if value.is_finite() && all_finite(grad) && all_finite(x) {
        Verdict::Feasible
    } else if !all_finite(x) {
        Verdict::Infeasible("position")
    } else if !value.is_finite() {
        Verdict::Infeasible("value")
    } else {
        Verdict::Infeasible("gradient")
    }
}

//! What every store's step shares: what a step of consecutive chains
//! found ([`Sweep`]), the unit that the optimiser's step is made of,
//! serially or in parallel parts ([`Executor`](super::Executor)); its
//! read-only [`Context`]; and the one judgement of every point a run
//! evaluates ([`judge`], [`draw_point`]). Each store steps its chains in
//! its own hot loop (`chain.rs`, `flat.rs`).
//!
//! Chains are independent: a sweep of chains `i..j` touches nothing of any
//! other chain, and [`Sweep::then`] combines the findings of neighbouring
//! sweeps associatively, so one step gives the same bits however the
//! chains are cut into parts and wherever the parts run.
//!
//! Where the target has float vectors, the chains use the default
//! generator and the point is large enough to pay
//! ([`LOCKSTEP_F64_FROM`] for `f64`), a sweep steps groups of
//! [`LANES`](crate::LANES)
//! live chains in lockstep
//! ([`Kernel::step_lanes`](crate::Kernel::step_lanes)); elsewhere chain
//! after chain. Each chain draws the same words either way.

use crate::error::{Error, floor};
use crate::float::Float;
use crate::potential::SlicePotential;

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
pub struct Sweep<F> {
    /// The lowest new value that improved its chain's best, with its chain:
    /// the first such chain on ties.
    pub best: Option<(F, usize)>,
    /// Potential evaluations.
    pub evaluated: u64,
    /// Chains that diverged in this step.
    pub diverged: usize,
    /// The first chain whose potential fell below the floor, with its value.
    pub unbounded: Option<(usize, F)>,
    /// Whether the potential stopped the run (the chains after the group
    /// that asked are left unstepped).
    pub stopped: bool,
}

impl<F: Float> Sweep<F> {
    pub(crate) const NOTHING: Self = Self {
        best: None,
        evaluated: 0,
        diverged: 0,
        unbounded: None,
        stopped: false,
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
            stopped: self.stopped | later.stopped,
        }
    }
}

/// The read-only context of a step: the kernel at `a_k`, the potential and
/// the domain, the new iterate's index and whether it is recorded.
pub struct Context<'a, K, P, B, F> {
    pub kernel: &'a K,
    pub potential: &'a P,
    pub domain: &'a B,
    pub k: u64,
    pub record: bool,
    pub floor: F,
}

/// The most points drawn for one chain's start: a point where the
/// potential or its gradient is not finite (a NaN, `+inf`) is infeasible,
/// and the chain draws again from the start law, up to this many times in
/// all. With a fraction `p` of the start law feasible, a chain fails with
/// probability `(1 - p)^100`: below `1e-4` for `p = 0.09`.
pub const START_TRIES: u32 = 100;

/// Draws chain `c`'s initial point `x` with `place` (from the chain's
/// generator) and evaluates it into `grad`, drawing again where the point
/// is infeasible ([`settle_point`]): its value, or the error.
#[allow(clippy::too_many_arguments)]
pub(crate) fn draw_point<F, P, R>(
    c: usize,
    x: &mut [F],
    grad: &mut [F],
    rng: &mut R,
    potential: &P,
    spare: &mut u64,
    evaluations: &mut u64,
    mut place: impl FnMut(&mut R, &mut [F]),
) -> Result<F, Error>
where
    F: Float,
    P: SlicePotential<F> + ?Sized,
{
    // Written out here and in the redraw: one closure, called once and then
    // handed to `settle_point`, costs the Cortex-M4F f64 firmware 464 to
    // 752 bytes of flash (measured), over its 32 KiB budget.
    place(rng, x);
    let value = potential.value_and_gradient(x, grad);
    *evaluations += 1;
    settle_point(c, x, grad, value, spare, evaluations, |x, grad| {
        place(rng, x);
        potential.value_and_gradient(x, grad)
    })
}

/// Judges chain `c`'s first initial point, `x` of value `value` and
/// gradient `grad`, and while it is infeasible draws and evaluates
/// another with `redraw` (which returns its value): up to [`START_TRIES`]
/// points in all, each redraw counted in `evaluations` and taken from
/// `spare`. The feasible point's value, or [`Error::UnboundedBelow`] for a
/// point below the floor, [`Error::NonFiniteStart`] when no point was
/// feasible. Every store's start, one chain or a batch at a time, redraws
/// through here.
pub(crate) fn settle_point<F: Float>(
    c: usize,
    x: &mut [F],
    grad: &mut [F],
    mut value: F,
    spare: &mut u64,
    evaluations: &mut u64,
    mut redraw: impl FnMut(&mut [F], &mut [F]) -> F,
) -> Result<F, Error> {
    let mut tries = 1;
    loop {
        match judge(x, value, grad, floor()) {
            Verdict::Feasible => return Ok(value),
            Verdict::Unbounded => {
                return Err(Error::UnboundedBelow {
                    chain: c,
                    value: value.to_f64(),
                });
            }
            Verdict::Infeasible(what) => {
                if tries >= START_TRIES || *spare == 0 {
                    return Err(Error::NonFiniteStart {
                        chain: c,
                        what,
                        tries,
                    });
                }
                *spare -= 1;
            }
        }
        value = redraw(x, grad);
        *evaluations += 1;
        tries += 1;
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

//! The kernel's default solver, [`hrla::Auto`], on the layer's settings:
//! any dimension, a built-in or a user's function (called on batches
//! through the kernel's batch seam), a box with a side per coordinate.

use std::ops::ControlFlow;

use hrla::rand_core::SeedableRng;
use hrla::{Auto, AutoProgress, AutoStorage, Problem as Posed, Termination};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::{BoxSpec, Error, MEMORY, PotentialSpec, Progress, dimension};

/// What [`solve`] found: the kernel's [`hrla::Solution`] whatever the
/// dimension.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// The best point.
    pub x: Vec<f64>,
    /// `U(x)`.
    pub value: f64,
    /// Evaluations used, all included (at most the budget).
    pub evaluations: u64,
    /// Rounds of sampling done.
    pub rounds: u64,
    /// The step size chosen.
    pub step: f64,
    /// The inverse temperature at the end.
    pub inverse_temperature: f64,
    /// Chains run.
    pub chains: usize,
    /// Why it ended.
    pub termination: Termination,
    /// Chains diverged at the end.
    pub diverged_chains: usize,
    /// Whether every chain had diverged at the end.
    pub all_diverged: bool,
    /// The kernel's sentence for the solution.
    pub message: String,
}

/// A problem for [`solve`].
#[derive(Clone)]
pub struct Problem {
    /// The potential.
    pub potential: PotentialSpec,
    /// The box (the solver needs one).
    pub domain: BoxSpec,
    /// The evaluation budget, everything counted.
    pub budget: u64,
    /// The seed: chain `c` draws from the generator of `(seed, c)`.
    pub seed: u64,
    /// The chains (none: [`Auto::chains_for`] the budget).
    pub chains: Option<usize>,
    /// The dimension, when neither the potential nor the box fixes it.
    pub dim: Option<usize>,
    /// Chain 0's initial point (scipy's `x0`), in the box and where the
    /// potential is finite; the other chains draw theirs uniformly. None:
    /// every chain draws.
    pub x0: Option<Vec<f64>>,
    /// End the run once the best value is at or below this.
    pub target: Option<f64>,
    /// `(window, tolerance)`: end the rounds once the best value has not
    /// fallen by more than `tolerance` over `window` rounds.
    pub stall: Option<(u64, f64)>,
    /// End the rounds after this many.
    pub rounds: Option<u64>,
    /// The convergence rule's window of rounds ([`hrla::Problem::converge`]).
    pub converge: Option<u64>,
    /// The budget the run plans within, the first quench free to go on to
    /// `budget` ([`hrla::Problem::soft_budget`]); the default chains are
    /// those of this budget.
    pub soft: Option<u64>,
}

/// Minimises `problem` with `auto` at the problem's dimension, any
/// `d >= 1`, in a box with the same sides in every coordinate or its own
/// in each, chain 0 from `problem.x0` where given. `observer` sees the run after every step of the chains,
/// quench and restart (`iteration` counts rounds) and ends it by
/// returning `Break`: the solution is then the best so far,
/// [`Termination::Observer`]. A user's function that fails ends the run
/// at once with its error.
pub fn solve(
    auto: &Auto<f64>,
    problem: &Problem,
    observer: &mut dyn FnMut(&Progress) -> ControlFlow<()>,
) -> Result<Solution, Error> {
    let d = dimension(&[
        ("dim", problem.dim),
        ("the potential", problem.potential.dimension()),
        ("the box", problem.domain.dimension()),
        ("x0", problem.x0.as_ref().map(Vec::len)),
    ])?;
    let planned = problem
        .soft
        .map_or(problem.budget, |s| s.min(problem.budget));
    let n = problem
        .chains
        .unwrap_or_else(|| Auto::<f64>::chains_for(planned));
    let domain = problem.domain.sides()?;
    let pot = problem.potential.build(d)?;
    let mut storage = Storage::new(n, d)?;
    let mut lent = storage.lend()?;
    let observe = |p: &AutoProgress<'_, f64>| {
        observer(&Progress {
            iteration: p.rounds,
            evaluations: p.evaluations,
            value: p.value,
            x: p.x,
            dim: d,
            chains: n,
        })
    };
    let mut posed = Posed::new(&pot, &domain, problem.budget).seed(problem.seed);
    if let Some(x0) = &problem.x0 {
        posed = posed.x0(x0);
    }
    if let Some(target) = problem.target {
        posed = posed.target(target);
    }
    if let Some((window, tolerance)) = problem.stall {
        posed = posed.stall(window, tolerance);
    }
    if let Some(rounds) = problem.rounds {
        posed = posed.rounds(rounds);
    }
    if let Some(window) = problem.converge {
        posed = posed.converge(window);
    }
    if let Some(soft) = problem.soft {
        posed = posed.soft_budget(soft);
    }
    let found = auto.minimize_with(&posed, &mut lent, observe);
    pot.finish()?;
    let s = found?;
    Ok(Solution {
        x: s.x.to_vec(),
        value: s.value,
        evaluations: s.evaluations,
        rounds: s.rounds,
        step: s.step,
        inverse_temperature: s.inverse_temperature,
        chains: s.chains,
        termination: s.termination,
        diverged_chains: s.diverged_chains,
        all_diverged: s.all_diverged(),
        message: s.to_string(),
    })
}

/// Whether `pot` is a user's function, for a front end that must call it
/// with its runtime held.
pub fn is_user(potential: &PotentialSpec) -> bool {
    matches!(potential, PotentialSpec::User(_))
}

/// The arrays [`AutoStorage`] borrows, owned for one run.
struct Storage {
    d: usize,
    floats: Vec<f64>,
    diverged: Vec<bool>,
    rngs: Vec<Xoshiro256PlusPlus>,
}

impl Storage {
    /// Storage for `n` chains of dimension `d`, or [`Error::Memory`]: the
    /// size is checked and reserved before anything is written, so a huge
    /// count allocates nothing.
    fn new(n: usize, d: usize) -> Result<Self, Error> {
        let floats = AutoStorage::<f64, Xoshiro256PlusPlus>::floats(n, d, memory(d));
        let bytes = n
            .checked_mul(size_of::<bool>() + size_of::<Xoshiro256PlusPlus>())
            .and_then(|b| floats.checked_mul(size_of::<f64>())?.checked_add(b));
        let refuse = |address_space| Error::Memory {
            chains: n,
            dim: d,
            bytes: bytes.map_or(usize::MAX, |b| b / n.max(1)),
            address_space,
        };
        match bytes {
            Some(total) if total <= isize::MAX as usize => {}
            _ => return Err(refuse(true)),
        }
        let mut storage = Self {
            d,
            floats: Vec::new(),
            diverged: Vec::new(),
            rngs: Vec::new(),
        };
        storage
            .floats
            .try_reserve_exact(floats)
            .and_then(|()| storage.diverged.try_reserve_exact(n))
            .and_then(|()| storage.rngs.try_reserve_exact(n))
            .map_err(|_| refuse(false))?;
        storage.floats.resize(floats, 0.0);
        storage.diverged.resize(n, false);
        storage
            .rngs
            .extend((0..n).map(|_| Xoshiro256PlusPlus::seed_from_u64(0)));
        Ok(storage)
    }

    fn lend(&mut self) -> Result<AutoStorage<'_, f64, Xoshiro256PlusPlus>, Error> {
        Ok(AutoStorage::new(
            self.d,
            memory(self.d),
            &mut self.floats,
            &mut self.diverged,
            &mut self.rngs,
        )?)
    }
}

/// The L-BFGS memory of `Auto`'s quenches at dimension `d`: two pairs a
/// coordinate, at least [`MEMORY`] and at most 64. A memory of `d` pairs
/// or more holds the curvature of every direction of an ill-conditioned
/// basin: on a 10-D ellipsoid of condition `10^6` in bbob's f2 form
/// (its oscillating `T_osz` transformation), from one start and with
/// central differences, L-BFGS reached `1e-8` after 1 781 evaluations
/// with 8 pairs, 1 217 with 10 and 232 with 20 (scipy's L-BFGS-B, 10
/// pairs, on forward differences: 7 025 calls, about 640 gradients).
fn memory(d: usize) -> usize {
    d.saturating_mul(2).clamp(MEMORY, 64)
}

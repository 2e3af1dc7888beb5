//! The kernel's default solver, [`hrla::Auto`], on the layer's settings:
//! any compiled dimension, a built-in or a user's function, a box.

use std::ops::ControlFlow;

use std::sync::Arc;

use hrla::{Auto, AutoProgress, Chain, Lbfgs, Potential, Termination};

use crate::dims::with_dim;
use crate::potential::Builtin;
use crate::user::UserPotential;
use crate::{BoxSpec, Error, MEMORY, PointFunction, PotentialSpec, Progress, dimension};

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
}

/// Minimises `problem` with `auto`. `observer` sees the run after every
/// step of the chains, quench and restart (`iteration` counts rounds) and
/// ends it by returning `Break`: the solution is then the best so far,
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
    ])?;
    let n = problem
        .chains
        .unwrap_or_else(|| Auto::<f64>::chains_for(problem.budget));
    with_dim!(d, D => {
        let domain = problem.domain.interval()?;
        let pot = AutoPot::<D>::new(&problem.potential)?;
        let mut chains = storage::<D>(n)?;
        let mut lbfgs: Box<Lbfgs<f64, D, MEMORY>> = Box::default();
        let observe = |p: &AutoProgress<'_, f64, D>| {
            if pot.failed() {
                return ControlFlow::Break(());
            }
            observer(&Progress {
                iteration: p.rounds,
                evaluations: p.evaluations,
                value: p.value,
                dim: D,
                chains: n,
            })
        };
        let found = auto.minimize_with(
            &pot,
            domain,
            problem.budget,
            problem.seed,
            &mut chains,
            &mut lbfgs,
            observe,
        );
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
    })
}

/// Whether `pot` is a user's function, for a front end that must call it
/// with its runtime held.
pub fn is_user(potential: &PotentialSpec) -> bool {
    matches!(potential, PotentialSpec::User(_))
}

/// The potential in dimension `D`, for [`Auto`], which is typed by its
/// dimension; a user's function is called one point at a time.
enum AutoPot<const D: usize> {
    Builtin(Builtin<D>),
    User(UserPotential<D>),
    Native(Arc<dyn PointFunction>),
}

impl<const D: usize> AutoPot<D> {
    fn new(spec: &PotentialSpec) -> Result<Self, Error> {
        Ok(match spec {
            PotentialSpec::Builtin(b) => Self::Builtin(b.build::<D>()?),
            PotentialSpec::User(f) => Self::User(UserPotential::new(f.clone())),
            PotentialSpec::Native(f) => Self::Native(f.clone()),
        })
    }

    /// The user function's first error since the last call, if any.
    fn finish(&self) -> Result<(), Error> {
        match self {
            Self::User(p) => p.finish(),
            Self::Builtin(_) | Self::Native(_) => Ok(()),
        }
    }

    /// Whether a user function failed since the last [`finish`](Self::finish).
    fn failed(&self) -> bool {
        matches!(self, Self::User(p) if p.failed())
    }
}

impl<const D: usize> Potential<f64, D> for AutoPot<D> {
    #[inline]
    fn value_and_gradient(&self, x: &[f64; D], grad: &mut [f64; D]) -> f64 {
        match self {
            Self::Builtin(p) => p.value_and_gradient(x, grad),
            Self::User(p) => p.value_and_gradient(x, grad),
            Self::Native(p) => p.value_and_gradient(x, grad),
        }
    }
}

/// Storage for `n` chains of dimension `D`, or [`Error::Memory`]: the size
/// is checked and reserved before anything is written, so a huge count
/// allocates nothing.
fn storage<const D: usize>(n: usize) -> Result<Vec<Chain<f64, D>>, Error> {
    let bytes = size_of::<Chain<f64, D>>();
    let refuse = |address_space| Error::Memory {
        chains: n,
        dim: D,
        bytes,
        address_space,
    };
    match n.checked_mul(bytes) {
        Some(total) if total <= isize::MAX as usize => {}
        _ => return Err(refuse(true)),
    }
    let mut chains = Vec::new();
    chains.try_reserve_exact(n).map_err(|_| refuse(false))?;
    chains.extend((0..n).map(|_| Chain::new()));
    Ok(chains)
}

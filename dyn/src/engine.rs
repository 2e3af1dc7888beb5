//! One run loop for every front end: the kernel's optimiser in one of the
//! compiled dimensions, behind the object-safe [`Engine`].

use std::ops::ControlFlow;

use hrla::{
    AnyKernel, AnySampler, AnySchedule, Builder, Chain, Domain, Kernel, Lbfgs, Optimizer,
    PolishSettings, Polished, Report, Sampler, Schedule, Start, Termination, chain_seed,
};
use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::dims::with_dim;
use crate::error::RanAway;
use crate::settings::{Bounds, Pot};
use crate::{Error, MEMORY, Progress, Settings};

/// Where the fields of the chains are, for a front end that shows them
/// without a copy (numpy views): the address of the first chain, and each
/// field's offset from a chain's start and the stride between chains, in
/// units of `f64`. Fixed for the engine's life: the chains are never moved
/// or resized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// The address of the first chain (0 when there is none).
    pub base: usize,
    /// The number of chains.
    pub n: usize,
    /// The dimension.
    pub d: usize,
    /// The distance from one chain to the next.
    pub stride: usize,
    /// The position `x`.
    pub x: usize,
    /// The velocity `y`.
    pub y: usize,
    /// The gradient at `x`.
    pub gradient: usize,
    /// The chain's best point.
    pub best_x: usize,
    /// The chain's best value.
    pub best_value: usize,
}

fn layout_of<const D: usize, R>(chains: &[Chain<f64, D, R>]) -> Layout {
    // A chain holds f64 fields, so it is aligned to (and a multiple of) 8
    // bytes, and every f64 field lies a whole number of f64s from its start.
    const { assert!(size_of::<Chain<f64, 1>>().is_multiple_of(size_of::<f64>())) };
    let stride = size_of::<Chain<f64, D, R>>() / size_of::<f64>();
    let Some(first) = chains.first() else {
        return Layout {
            base: 0,
            n: 0,
            d: D,
            stride,
            x: 0,
            y: 0,
            gradient: 0,
            best_x: 0,
            best_value: 0,
        };
    };
    // Measured from the fields' addresses: Rust does not fix a struct's
    // field order.
    let start = std::ptr::from_ref(first) as usize;
    let offset = |p: *const f64| (p as usize - start) / size_of::<f64>();
    Layout {
        base: start,
        n: chains.len(),
        d: D,
        stride,
        x: offset(first.x().as_ptr()),
        y: offset(first.y().as_ptr()),
        gradient: offset(first.gradient().as_ptr()),
        best_x: offset(first.best().x.as_ptr()),
        best_value: offset(&first.best().value),
    }
}

/// The bytes of one chain in dimension `d`, or [`Error::Dimension`].
pub fn storage_bytes(d: usize) -> Result<usize, Error> {
    with_dim!(d, D => Ok(size_of::<Chain<f64, D>>()))
}

/// Storage for `n` chains of dimension `D`, or [`Error::Memory`]: the size
/// is checked and reserved before anything is written, so a huge count
/// allocates nothing.
pub(crate) fn storage<const D: usize>(n: usize) -> Result<Vec<Chain<f64, D>>, Error> {
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

/// A run, whatever its dimension: what every front end drives.
///
/// A run that failed (every chain diverged, the potential unbounded below,
/// a potential that panicked) keeps failing: every later step, run,
/// polish, quench or restart returns the same error, `run` too when a
/// stopping rule holds, so a failed run never turns into a report, and a
/// user's function is not called again.
pub trait Engine: Send + Sync {
    /// Advances every live chain by `steps` steps, without consulting the
    /// stopping rules.
    fn step(&mut self, steps: u64) -> Result<(), Error>;
    /// Steps until a stopping rule holds and returns the report;
    /// `observer` is called on every improvement and every `every` steps
    /// (a user's function: after every step), and ends the run with
    /// [`Termination::Observer`] by returning `Break`. A run without a
    /// stopping rule is refused ([`hrla::Error::NoStoppingRule`]).
    fn run(
        &mut self,
        every: u64,
        observer: &mut dyn FnMut(&Progress) -> ControlFlow<()>,
    ) -> Result<Report<f64>, Error>;
    /// The first stopping rule that holds now.
    fn termination(&self) -> Option<Termination>;
    /// The report of the state now, when a stopping rule holds.
    fn report_now(&self) -> Option<Report<f64>>;
    /// Where the chains' fields are.
    fn layout(&self) -> Layout;
    /// `U(x_k)` per chain.
    fn values(&self) -> Vec<f64>;
    /// The positions `x_k`, `n x d` row-major.
    fn positions(&self) -> Vec<f64>;
    /// The velocities `y_k` (zero for OLA), `n x d` row-major.
    fn velocities(&self) -> Vec<f64>;
    /// The gradients `∇U(x_k)`, `n x d` row-major.
    fn gradients(&self) -> Vec<f64>;
    /// Each chain's generator where the run has left it, for a baseline
    /// that goes on from the same draws.
    fn generators(&self) -> Vec<Xoshiro256PlusPlus>;
    /// The sampler's step at the inverse temperature the next step runs at
    /// (`a_k` of the schedule at the current iteration `k`): the law of
    /// every chain's next move ([`Kernel::moments`]); the sampler's
    /// refusal of `a_k` when it refuses it.
    fn next_kernel(&self) -> Result<AnyKernel<f64>, Error>;
    /// Whether each chain has diverged.
    fn diverged(&self) -> Vec<bool>;
    /// The global running best: `(x, value, iteration)`.
    fn best(&self) -> (Vec<f64>, f64, u64);
    /// The chain holding the global running best.
    fn best_chain(&self) -> usize;
    /// `(chain, U(x_k))` of the live chain lowest now.
    fn current_best(&self) -> Option<(usize, f64)>;
    /// Steps done.
    fn iteration(&self) -> u64;
    /// Evaluations so far.
    fn evaluations(&self) -> u64;
    /// Chains diverged so far.
    fn diverged_chains(&self) -> usize;
    /// The inverse temperature of the last step (`a_0` before the first).
    fn inverse_temperature(&self) -> f64;
    /// L-BFGS from chain `chain`'s best point (`quench`: from a copy of
    /// its current point), within the evaluation budget.
    fn local_search(
        &mut self,
        chain: usize,
        settings: PolishSettings<f64>,
        quench: bool,
    ) -> Result<Polished<f64>, Error>;
    /// Moves chain `chain` to `x` (confined) with zero velocity and
    /// evaluates it; `false` when no evaluation is left.
    fn restart(&mut self, chain: usize, x: &[f64]) -> Result<bool, Error>;
    /// The dimension.
    fn dim(&self) -> usize;
    /// The number of chains.
    fn len(&self) -> usize;
    /// Whether there is no chain.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Whether the potential is a user's function (which a front end may
    /// need to call with its runtime held, say Python's GIL).
    fn is_user(&self) -> bool;
}

impl Settings {
    /// The run these settings describe, its initial points drawn and
    /// evaluated: the kernel's checks, and the layer's of the dimension
    /// ([`Settings::dimension`]) and the storage.
    pub fn build(&self) -> Result<Box<dyn Engine>, Error> {
        let d = self.dimension()?;
        with_dim!(d, D => Ok(Box::new(Run::<D>::build(self)?) as Box<dyn Engine>))
    }
}

type Opt<const D: usize> = Optimizer<
    f64,
    Pot<D>,
    AnySampler<f64>,
    AnySchedule<f64>,
    Vec<Chain<f64, D>>,
    D,
    Xoshiro256PlusPlus,
    Bounds,
>;

struct Run<const D: usize> {
    opt: Opt<D>,
    /// The error that ended the run, returned by every later call.
    failed: Option<Failure>,
    /// The escape radius, squared ([`Settings::escape`]).
    escape2: Option<f64>,
}

/// What ends a run for good.
#[derive(Clone, Copy, Debug)]
enum Failure {
    Kernel(hrla::Error),
    RanAway(RanAway),
}

impl From<Failure> for Error {
    fn from(f: Failure) -> Self {
        match f {
            Failure::Kernel(e) => Error::Kernel(e),
            Failure::RanAway(r) => Error::RanAway(r),
        }
    }
}

impl<const D: usize> Run<D> {
    fn build(s: &Settings) -> Result<Self, Error> {
        let escape2 = s.escape2()?;
        let domain = s.bounds()?;
        let potential = s.potential.build::<D>()?;
        let mut start = s.start.build::<D>()?;
        let chains = storage::<D>(s.chains)?;
        if let (Pot::User(p), true) = (&potential, s.chains > 0) {
            // The initial points, as the builder will draw them. A chain
            // holds its position, so `chains * D` floats fit in less than
            // the storage just allocated: the product cannot overflow.
            let mut points = Vec::new();
            points
                .try_reserve_exact(s.chains * D)
                .map_err(|_| Error::Memory {
                    chains: s.chains,
                    dim: D,
                    bytes: D * size_of::<f64>(),
                    address_space: false,
                })?;
            for c in 0..s.chains {
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(chain_seed(s.seed, c as u64));
                let (mut x, mut y) = ([0.0; D], [0.0; D]);
                let mut draw = start;
                draw.initial_point(c, &mut rng, &mut x);
                domain.confine(&mut x, &mut y);
                points.extend_from_slice(&x);
            }
            p.load(points)?;
        }
        let opt = Builder::new(potential, s.sampler, s.schedule, &mut start)
            .domain(domain)
            .seed(s.seed)
            .stride(s.stride)
            .stop(s.stop)
            .build(chains)?;
        let run = Self {
            opt,
            failed: None,
            escape2,
        };
        run.opt.potential().finish()?;
        Ok(run)
    }

    fn is_user(&self) -> bool {
        matches!(self.opt.potential(), Pot::User(_))
    }

    /// For a user's function: the next positions of the live chains, by
    /// the step the optimiser is about to take, evaluated in one call.
    fn prepare(&self) -> Result<(), Error> {
        let Pot::User(p) = self.opt.potential() else {
            return Ok(());
        };
        if self.failed.is_some() {
            return Ok(());
        }
        let a = self
            .opt
            .schedule()
            .inverse_temperature(self.opt.iteration());
        let fresh;
        let step = if a == self.opt.kernel().inverse_temperature() {
            self.opt.kernel()
        } else {
            // The optimiser's step will refuse the same `a` the same way.
            fresh = self.opt.sampler().at(a)?;
            &fresh
        };
        let mut points = Vec::with_capacity(self.opt.chains().len() * D);
        for chain in self.opt.chains().iter().filter(|c| !c.is_diverged()) {
            let (mut x, mut y, mut rng) = (*chain.x(), *chain.y(), chain.rng().clone());
            step.step(&mut x, &mut y, chain.gradient(), &mut rng);
            self.opt.domain().confine(&mut x, &mut y);
            points.extend_from_slice(&x);
        }
        if points.is_empty() {
            return Ok(());
        }
        p.load(points)
    }

    fn step_once(&mut self) -> Result<(), Error> {
        self.prepare()?;
        let stepped = self.opt.step();
        let stepped = self.keep(stepped);
        self.opt.potential().finish()?;
        stepped?;
        self.escaped()
    }

    /// [`Error::RanAway`] when every chain has diverged or lies beyond the
    /// escape radius and at least one ran away (every chain diverged is
    /// the kernel's own error); the run then keeps failing.
    fn escaped(&mut self) -> Result<(), Error> {
        let Some(r2) = self.escape2 else {
            return Ok(());
        };
        let chains = self.opt.chains();
        let mut farthest2 = 0.0_f64;
        let mut diverged = 0;
        for chain in chains {
            if chain.is_diverged() {
                diverged += 1;
                continue;
            }
            let d2 = chain.x().iter().fold(0.0, |s, v| s + v * v);
            // A NaN distance is not beyond the radius: such a chain is not away.
            if d2.is_nan() || d2 <= r2 {
                return Ok(());
            }
            farthest2 = farthest2.max(d2);
        }
        if diverged == chains.len() {
            return Ok(());
        }
        let away = RanAway {
            chains: chains.len(),
            radius: r2.sqrt(),
            farthest: farthest2.sqrt(),
            diverged,
        };
        self.failed = Some(Failure::RanAway(away));
        Err(Error::RanAway(away))
    }

    /// The error that ended the run, if it has.
    fn check(&self) -> Result<(), Error> {
        self.failed.map_or(Ok(()), |e| Err(e.into()))
    }

    /// `result`, keeping its error when it ends the run.
    fn keep<T>(&mut self, result: Result<T, hrla::Error>) -> Result<T, Error> {
        if let Err(
            e @ (hrla::Error::AllDiverged { .. }
            | hrla::Error::UnboundedBelow { .. }
            | hrla::Error::Poisoned),
        ) = result
        {
            self.failed = Some(Failure::Kernel(e));
        }
        result.map_err(Error::Kernel)
    }

    fn report(&self, termination: Termination) -> Report<f64> {
        Report {
            value: self.opt.best().value,
            chain: self.opt.best_chain(),
            found_at: self.opt.best().iteration,
            iterations: self.opt.iteration(),
            evaluations: self.opt.evaluations(),
            diverged_chains: self.opt.diverged_chains(),
            chains: self.opt.chains().len(),
            termination,
        }
    }

    fn progress(&self) -> Progress {
        Progress {
            iteration: self.opt.iteration(),
            evaluations: self.opt.evaluations(),
            value: self.opt.best().value,
            dim: D,
            chains: self.opt.chains().len(),
        }
    }
}

impl<const D: usize> Engine for Run<D> {
    fn step(&mut self, steps: u64) -> Result<(), Error> {
        self.check()?;
        if self.is_user() || self.escape2.is_some() {
            return (0..steps).try_for_each(|_| self.step_once());
        }
        let opt = &mut self.opt;
        let stepped = (0..steps).try_for_each(|_| opt.step());
        self.keep(stepped)
    }

    fn run(
        &mut self,
        every: u64,
        observer: &mut dyn FnMut(&Progress) -> ControlFlow<()>,
    ) -> Result<Report<f64>, Error> {
        if self.opt.stop().is_empty() {
            return Err(hrla::Error::NoStoppingRule.into());
        }
        self.check()?;
        if !self.is_user() && self.escape2.is_none() {
            let chains = self.opt.chains().len();
            let report = self.opt.run_with(every, |p| {
                observer(&Progress {
                    iteration: p.iteration,
                    evaluations: p.evaluations,
                    value: p.best.value,
                    dim: D,
                    chains,
                })
            });
            return self.keep(report);
        }
        // The kernel's `run`, with the batched call before each step and
        // the escape radius checked after it.
        loop {
            if let Some(t) = self.opt.termination() {
                return Ok(self.report(t));
            }
            self.step_once()?;
            if observer(&self.progress()).is_break() {
                return Ok(self.report(Termination::Observer));
            }
        }
    }

    fn termination(&self) -> Option<Termination> {
        self.opt.termination()
    }

    fn report_now(&self) -> Option<Report<f64>> {
        self.opt.termination().map(|t| self.report(t))
    }

    fn layout(&self) -> Layout {
        layout_of(self.opt.chains())
    }

    fn values(&self) -> Vec<f64> {
        self.opt.chains().iter().map(|c| c.value()).collect()
    }

    fn positions(&self) -> Vec<f64> {
        self.opt.chains().iter().flat_map(|c| *c.x()).collect()
    }

    fn velocities(&self) -> Vec<f64> {
        self.opt.chains().iter().flat_map(|c| *c.y()).collect()
    }

    fn gradients(&self) -> Vec<f64> {
        self.opt
            .chains()
            .iter()
            .flat_map(|c| *c.gradient())
            .collect()
    }

    fn generators(&self) -> Vec<Xoshiro256PlusPlus> {
        self.opt.chains().iter().map(|c| c.rng().clone()).collect()
    }

    fn next_kernel(&self) -> Result<AnyKernel<f64>, Error> {
        let a = self
            .opt
            .schedule()
            .inverse_temperature(self.opt.iteration());
        Ok(self.opt.sampler().at(a)?)
    }

    fn diverged(&self) -> Vec<bool> {
        self.opt.chains().iter().map(|c| c.is_diverged()).collect()
    }

    fn best(&self) -> (Vec<f64>, f64, u64) {
        let b = self.opt.best();
        (b.x.to_vec(), b.value, b.iteration)
    }

    fn best_chain(&self) -> usize {
        self.opt.best_chain()
    }

    fn current_best(&self) -> Option<(usize, f64)> {
        self.opt.current_best()
    }

    fn iteration(&self) -> u64 {
        self.opt.iteration()
    }

    fn evaluations(&self) -> u64 {
        self.opt.evaluations()
    }

    fn diverged_chains(&self) -> usize {
        self.opt.diverged_chains()
    }

    fn inverse_temperature(&self) -> f64 {
        self.opt.kernel().inverse_temperature()
    }

    fn local_search(
        &mut self,
        chain: usize,
        settings: PolishSettings<f64>,
        quench: bool,
    ) -> Result<Polished<f64>, Error> {
        self.check()?;
        let mut lbfgs: Box<Lbfgs<f64, D, MEMORY>> = Box::default();
        let done = if quench {
            self.opt.quench(chain, &mut lbfgs, settings)
        } else {
            self.opt.polish(chain, &mut lbfgs, settings)
        };
        let done = self.keep(done);
        self.opt.potential().finish()?;
        done
    }

    fn restart(&mut self, chain: usize, x: &[f64]) -> Result<bool, Error> {
        let x: [f64; D] = x.try_into().map_err(|_| Error::Length {
            what: "x",
            len: x.len(),
            dim: D,
        })?;
        self.check()?;
        let done = self.opt.restart(chain, &x);
        let done = self.keep(done);
        self.opt.potential().finish()?;
        done
    }

    fn dim(&self) -> usize {
        D
    }

    fn len(&self) -> usize {
        self.opt.chains().len()
    }

    fn is_user(&self) -> bool {
        Run::is_user(self)
    }
}

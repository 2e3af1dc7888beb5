//! The run every front end drives: the kernel's optimiser over flat
//! storage at a run-time dimension, as one concrete [`Engine`].

use std::ops::ControlFlow;

use hrla::{
    AnyKernel, AnySampler, AnySchedule, Builder, FlatChains, Kernel, LbfgsIn, Observe, Optimizer,
    PolishSettings, Polished, Report, Sampler, Schedule, Store, Termination,
};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::error::RanAway;
use crate::settings::{Bounds, Pot};
use crate::{Error, MEMORY, Progress, Settings, UserBatch};

/// Where the fields of the chains are, for a front end that shows them
/// without a copy (numpy views): each field of every chain is one
/// contiguous block, `(n, d)` row-major for the points, `(n,)` for the
/// values. `base` is the address of the positions; each field is given by
/// its offset from `base`, in units of `f64`. Fixed for the engine's life:
/// the storage is never moved or resized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// The address of the positions (`x` of the first chain).
    pub base: usize,
    /// The number of chains.
    pub n: usize,
    /// The dimension.
    pub d: usize,
    /// The positions `x`, `(n, d)`.
    pub x: usize,
    /// The velocities `y`, `(n, d)`.
    pub y: usize,
    /// The gradients at `x`, `(n, d)`.
    pub gradient: usize,
    /// The chains' best points, `(n, d)`.
    pub best_x: usize,
    /// The values at `x`, `(n,)`.
    pub value: usize,
    /// The chains' best values, `(n,)`.
    pub best_value: usize,
}

/// The bytes of one kernel chain of the const-generic path
/// ([`hrla::Chain`]`<f64, d>`), for a front end that runs those: its fixed
/// fields and four vectors of `d` floats (the layout adds no padding that
/// depends on `d`: tested against `size_of` for several `d`), or
/// [`Error::Memory`] for a size past the address space.
pub fn storage_bytes(d: usize) -> Result<usize, Error> {
    d.checked_mul(4 * size_of::<f64>())
        .and_then(|v| v.checked_add(size_of::<hrla::Chain<f64, 0>>()))
        .filter(|&b| b <= isize::MAX as usize)
        .ok_or(Error::Memory {
            chains: 1,
            dim: d,
            bytes: usize::MAX,
            address_space: true,
        })
}

/// The bytes of one chain of the engine's flat storage in dimension `d`
/// (its floats, iteration count, divergence flag and generator),
/// saturating at `usize::MAX`.
fn flat_bytes(d: usize) -> usize {
    Chains::floats(1, d)
        .saturating_mul(size_of::<f64>())
        .saturating_add(size_of::<u64>() + size_of::<bool>() + size_of::<Rng>())
}

/// A `Vec` of `len` copies of `value`, or [`Error::Memory`] for `n` chains
/// of dimension `d`: the size is checked and reserved before anything is
/// written, so a huge count allocates nothing.
fn filled<T: Clone>(len: usize, value: T, n: usize, d: usize) -> Result<Vec<T>, Error> {
    let refuse = |address_space| Error::Memory {
        chains: n,
        dim: d,
        bytes: flat_bytes(d),
        address_space,
    };
    match len.checked_mul(size_of::<T>()) {
        Some(total) if total <= isize::MAX as usize => {}
        _ => return Err(refuse(true)),
    }
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| refuse(false))?;
    v.resize(len, value);
    Ok(v)
}

/// A run, whatever its dimension: what every front end drives. Its
/// stepping and its run go through the kernel's one loop
/// ([`Optimizer::run_with`]): the layer adds only what is its own, the
/// escape radius and a user's failure, as stops the loop's observer sees.
///
/// A run that failed (every chain diverged, the potential unbounded below,
/// a potential that panicked) keeps failing: every later step, run,
/// polish, quench or restart returns the same error, `run` too when a
/// stopping rule holds, so a failed run never turns into a report, and a
/// user's function is not called again.
pub struct Engine {
    opt: Opt,
    /// A user's function, whose failure ends the run.
    user: Option<UserBatch>,
    /// The error that ended the run, returned by every later call.
    failed: Option<Failure>,
    /// The escape radius, squared ([`Settings::escape`]).
    escape2: Option<f64>,
    /// The polish's L-BFGS storage, made at the first polish.
    lbfgs: Vec<f64>,
}

type Rng = Xoshiro256PlusPlus;
type Chains = FlatChains<f64, Rng, Vec<f64>, Vec<u64>, Vec<bool>, Vec<Rng>>;
type Opt = Optimizer<f64, Pot, AnySampler<f64>, AnySchedule<f64>, Chains, Bounds>;

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

impl Settings {
    /// The run these settings describe, its initial points drawn and
    /// evaluated: the kernel's checks, and the layer's of the dimension
    /// ([`Settings::dimension`]) and the storage.
    pub fn build(&self) -> Result<Engine, Error> {
        Engine::build(self)
    }
}

/// [`RanAway`] when every chain of `chains` has diverged or lies beyond
/// the escape radius (squared, `r2`) and at least one ran away (every
/// chain diverged is the kernel's own error).
fn ran_away(chains: &dyn Store<f64>, r2: f64) -> Option<RanAway> {
    let mut farthest2 = 0.0_f64;
    let mut diverged = 0;
    for c in 0..chains.len() {
        if chains.is_diverged(c) {
            diverged += 1;
            continue;
        }
        let d2 = chains.point(c).0.iter().fold(0.0, |s, v| s + v * v);
        // A NaN distance is not beyond the radius: such a chain is not away.
        if d2.is_nan() || d2 <= r2 {
            return None;
        }
        farthest2 = farthest2.max(d2);
    }
    (diverged < chains.len()).then(|| RanAway {
        chains: chains.len(),
        radius: r2.sqrt(),
        farthest: farthest2.sqrt(),
        diverged,
    })
}

impl Engine {
    fn build(s: &Settings) -> Result<Self, Error> {
        let d = s.dimension()?;
        let n = s.chains;
        let escape2 = s.escape2()?;
        let domain = s.bounds()?;
        let potential = s.potential.build(d)?;
        let user = match &potential {
            Pot::User(u) => Some(u.clone()),
            Pot::Builtin(_) | Pot::Native(_) => None,
        };
        let mut start = s.start.at(d)?;
        // The kernel refuses no chains or no dimension with its own error;
        // the storage is then empty.
        let floats = if n == 0 || d == 0 {
            0
        } else {
            Chains::floats(n, d)
        };
        let chains = FlatChains::new(
            d,
            filled(floats, 0.0, n, d)?,
            filled(n, 0, n, d)?,
            filled(n, false, n, d)?,
            // Placeholders: the builder seeds every chain's generator.
            filled(n, <Rng as rand_core::SeedableRng>::seed_from_u64(0), n, d)?,
        )?;
        let opt = Builder::new(potential, s.sampler, s.schedule, &mut start)
            .domain(domain)
            .seed(s.seed)
            .stride(s.stride)
            .stop(s.stop)
            .build(chains);
        let engine = Self {
            opt: match opt {
                Ok(opt) => opt,
                // A user's failure makes every point infeasible, and the
                // build then fails: the user's error is the cause.
                Err(e) => {
                    if let Some(u) = &user {
                        u.finish()?;
                    }
                    return Err(e.into());
                }
            },
            user,
            failed: None,
            escape2,
            lbfgs: Vec::new(),
        };
        engine.finish()?;
        Ok(engine)
    }

    /// A user's failure since the last call, if any.
    fn finish(&self) -> Result<(), Error> {
        self.user.as_ref().map_or(Ok(()), UserBatch::finish)
    }

    /// The error that ended the run, if it has.
    fn check(&self) -> Result<(), Error> {
        self.failed.map_or(Ok(()), |e| Err(e.into()))
    }

    /// The run as it is before a call that evaluates a user's function,
    /// to go back to if the function fails in it.
    fn snapshot(&self) -> Option<Opt> {
        self.user.is_some().then(|| self.opt.clone())
    }

    /// `result` of a call that started from `before`. A user's failure in
    /// it is the cause, reported in its place, and the call is undone:
    /// the run is as it was before, so that going on gives the bits of a
    /// run never interrupted. Otherwise an error that ends the run is kept.
    fn keep<T>(&mut self, result: Result<T, hrla::Error>, before: Option<Opt>) -> Result<T, Error> {
        if let Err(e) = self.finish() {
            // Into the same storage: a front end's views of the chains
            // stay where they were.
            if let Some(before) = before {
                self.opt.clone_from(&before);
            }
            return Err(e);
        }
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

    /// Advances every live chain by `steps` steps, without consulting the
    /// stopping rules; [`Error::RanAway`] after the first step at which
    /// every chain has run away beyond the escape radius or diverged.
    pub fn step(&mut self, steps: u64) -> Result<(), Error> {
        self.check()?;
        for _ in 0..steps {
            let before = self.snapshot();
            let stepped = self
                .opt
                .step()
                .map(|p| self.escape2.and_then(|r2| ran_away(p.chains, r2)));
            if let Some(away) = self.keep(stepped, before)? {
                self.failed = Some(Failure::RanAway(away));
                return Err(Error::RanAway(away));
            }
        }
        Ok(())
    }

    /// The kernel's loop until a stopping rule holds, `steps` more steps
    /// are done (`None`: no bound) or `observer` returns `Break`: the
    /// report when a stopping rule or the observer ended it, `None` when
    /// the steps ran out. `observer` is called as `when` says.
    fn drive(
        &mut self,
        steps: Option<u64>,
        when: Observe,
        observer: &mut dyn FnMut(&Progress) -> ControlFlow<()>,
    ) -> Result<Option<Report<f64>>, Error> {
        self.check()?;
        if steps == Some(0) {
            return Ok(self.report_now());
        }
        let end = steps.map(|k| self.opt.iteration().saturating_add(k));
        let before = self.snapshot();
        let escape2 = self.escape2;
        let (chains, dim) = (self.opt.chains().len(), self.opt.dim());
        let (mut away, mut ran_out) = (None, false);
        // The layer's own stops look after every step; the caller's
        // observer, as it asked.
        let report = self.opt.run_with(Observe::Always, |p| {
            away = escape2.and_then(|r2| ran_away(p.chains, r2));
            if away.is_some() {
                return ControlFlow::Break(());
            }
            if when.wants(p.iteration, p.improved)
                && observer(&Progress {
                    iteration: p.iteration,
                    evaluations: p.evaluations,
                    value: p.best.value,
                    x: p.best.x,
                    dim,
                    chains,
                })
                .is_break()
            {
                return ControlFlow::Break(());
            }
            ran_out = end.is_some_and(|end| p.iteration >= end);
            if ran_out {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        let report = self.keep(report, before)?;
        if let Some(away) = away {
            self.failed = Some(Failure::RanAway(away));
            return Err(Error::RanAway(away));
        }
        Ok((!ran_out).then_some(report))
    }

    /// Steps until a stopping rule holds and returns the report;
    /// `observer` is called after the steps `when` says, and ends the run
    /// with [`Termination::Observer`] by returning `Break`. A run without
    /// a stopping rule is refused ([`hrla::Error::NoStoppingRule`]).
    pub fn run(
        &mut self,
        when: Observe,
        observer: &mut dyn FnMut(&Progress) -> ControlFlow<()>,
    ) -> Result<Report<f64>, Error> {
        if self.opt.stop().is_empty() {
            return Err(hrla::Error::NoStoppingRule.into());
        }
        match self.drive(None, when, observer)? {
            Some(report) => Ok(report),
            None => unreachable!("a run without a step bound never runs out of steps"),
        }
    }

    /// At most `steps` steps of [`run`](Engine::run)'s loop, without an
    /// observer: the stopping rule that ended them, if one held (a run
    /// without stopping rules steps `steps` times).
    pub fn run_for(&mut self, steps: u64) -> Result<Option<Termination>, Error> {
        let report = self.drive(Some(steps), Observe::Never, &mut |_| {
            ControlFlow::Continue(())
        })?;
        Ok(report.map(|r| r.termination))
    }

    /// The first stopping rule that holds now.
    pub fn termination(&self) -> Option<Termination> {
        self.opt.termination()
    }

    /// The report of the state now, when a stopping rule holds.
    pub fn report_now(&self) -> Option<Report<f64>> {
        self.opt.termination().map(|t| self.opt.report(t))
    }

    /// Where the chains' fields are.
    pub fn layout(&self) -> Layout {
        let c = self.opt.chains();
        let base = c.positions().as_ptr();
        // Every field lies in the one `floats` array, after the positions.
        let offset = |p: *const f64| (p as usize - base as usize) / size_of::<f64>();
        Layout {
            base: base as usize,
            n: c.len(),
            d: c.dim(),
            x: 0,
            y: offset(c.y(0).as_ptr()),
            gradient: offset(c.gradient(0).as_ptr()),
            best_x: offset(c.best_positions().as_ptr()),
            value: offset(c.values().as_ptr()),
            best_value: offset(c.best_values().as_ptr()),
        }
    }

    /// `U(x_k)` per chain.
    pub fn values(&self) -> Vec<f64> {
        self.opt.chains().values().to_vec()
    }

    /// The positions `x_k`, `n x d` row-major.
    pub fn positions(&self) -> Vec<f64> {
        self.opt.chains().positions().to_vec()
    }

    /// The velocities `y_k` (zero for OLA), `n x d` row-major.
    pub fn velocities(&self) -> Vec<f64> {
        let c = self.opt.chains();
        (0..c.len()).flat_map(|i| c.y(i).iter().copied()).collect()
    }

    /// The gradients `∇U(x_k)`, `n x d` row-major.
    pub fn gradients(&self) -> Vec<f64> {
        let c = self.opt.chains();
        (0..c.len())
            .flat_map(|i| c.gradient(i).iter().copied())
            .collect()
    }

    /// Each chain's generator where the run has left it, for a baseline
    /// that goes on from the same draws.
    pub fn generators(&self) -> Vec<Xoshiro256PlusPlus> {
        let c = self.opt.chains();
        (0..c.len()).map(|i| c.rng(i).clone()).collect()
    }

    /// The sampler's step at the inverse temperature the next step runs at
    /// (`a_k` of the schedule at the current iteration `k`): the law of
    /// every chain's next move ([`Kernel::moments`]); the sampler's
    /// refusal of `a_k` when it refuses it.
    pub fn next_kernel(&self) -> Result<AnyKernel<f64>, Error> {
        let a = self
            .opt
            .schedule()
            .inverse_temperature(self.opt.iteration());
        Ok(self.opt.sampler().at(a)?)
    }

    /// Whether each chain has diverged.
    pub fn diverged(&self) -> Vec<bool> {
        let c = self.opt.chains();
        (0..c.len()).map(|i| c.is_diverged(i)).collect()
    }

    /// The global running best: `(x, value, iteration)`.
    pub fn best(&self) -> (Vec<f64>, f64, u64) {
        let b = self.opt.best();
        (b.x.to_vec(), b.value, b.iteration)
    }

    /// The chain holding the global running best.
    pub fn best_chain(&self) -> usize {
        self.opt.best_chain()
    }

    /// `(chain, U(x_k))` of the live chain lowest now.
    pub fn current_best(&self) -> Option<(usize, f64)> {
        self.opt.current_best()
    }

    /// Steps done.
    pub fn iteration(&self) -> u64 {
        self.opt.iteration()
    }

    /// Evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.opt.evaluations()
    }

    /// Chains diverged so far.
    pub fn diverged_chains(&self) -> usize {
        self.opt.diverged_chains()
    }

    /// Replaces the sampler and the schedule between steps (a page's
    /// slider moving `h` or `a` of a running run), keeping every chain's
    /// state, running best and random stream: the next step runs the new
    /// sampler's kernel at the new schedule's `a_k`, its exact-step
    /// coefficients computed afresh. The sampler's refusal of that `a_k`
    /// leaves the run unchanged; a failed run returns its error.
    pub fn retune(
        &mut self,
        sampler: AnySampler<f64>,
        schedule: AnySchedule<f64>,
    ) -> Result<(), Error> {
        self.check()?;
        let old = core::mem::replace(self.opt.schedule_mut(), schedule);
        if let Err(e) = self.opt.set_sampler(sampler) {
            *self.opt.schedule_mut() = old;
            return Err(Error::Kernel(e));
        }
        Ok(())
    }

    /// The inverse temperature of the last step (`a_0` before the first).
    pub fn inverse_temperature(&self) -> f64 {
        self.opt.kernel().inverse_temperature()
    }

    /// L-BFGS from chain `chain`'s best point (`quench`: from a copy of
    /// its current point), within the evaluation budget.
    pub fn local_search(
        &mut self,
        chain: usize,
        settings: PolishSettings<f64>,
        quench: bool,
    ) -> Result<Polished<f64>, Error> {
        self.check()?;
        let d = self.opt.dim();
        let floats = LbfgsIn::<f64>::floats(d, MEMORY);
        if self.lbfgs.len() != floats {
            self.lbfgs = filled(floats, 0.0, 1, d)?;
        }
        let before = self.snapshot();
        let mut lbfgs = LbfgsIn::new(d, MEMORY, &mut self.lbfgs)?;
        let done = if quench {
            self.opt.quench(chain, &mut lbfgs, settings)
        } else {
            self.opt.polish(chain, &mut lbfgs, settings)
        };
        self.keep(done, before)
    }

    /// Moves chain `chain` to `x` (confined) with zero velocity and
    /// evaluates it; `false` when no evaluation is left.
    pub fn restart(&mut self, chain: usize, x: &[f64]) -> Result<bool, Error> {
        let d = self.opt.dim();
        if x.len() != d {
            return Err(Error::Length {
                what: "x",
                len: x.len(),
                dim: d,
            });
        }
        self.check()?;
        let before = self.snapshot();
        let done = self.opt.restart(chain, x);
        self.keep(done, before)
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.opt.dim()
    }

    /// The number of chains.
    pub fn len(&self) -> usize {
        self.opt.chains().len()
    }

    /// Whether there is no chain.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the potential is a user's function (which a front end may
    /// need to call with its runtime held, say Python's GIL).
    pub fn is_user(&self) -> bool {
        self.user.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn storage_bytes_is_the_size_of_a_chain() {
        fn at<const D: usize>() {
            assert_eq!(storage_bytes(D).unwrap(), size_of::<hrla::Chain<f64, D>>());
        }
        at::<0>();
        at::<1>();
        at::<2>();
        at::<5>();
        at::<17>();
        at::<100>();
        assert!(matches!(
            storage_bytes(usize::MAX),
            Err(Error::Memory { .. })
        ));
    }
}

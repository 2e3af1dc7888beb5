//! `hrla.Optimizer`: the kernel's optimiser in one of the compiled
//! dimensions, behind an object-safe [`Engine`], with its chains readable
//! as numpy arrays.

use hrla::{
    AnySampler, AnySchedule, Builder, Chain, Domain, Interval, Kernel, Lbfgs, Optimizer,
    PolishSettings, Sampler, Schedule, Start, Termination, chain_seed,
};
use std::ops::ControlFlow;
use std::sync::{Mutex, MutexGuard, TryLockError};

use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;
use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::config::{self, PyInterval, PyPolishSettings, PyPolished, PyReport, PyStop, StartSpec};
use crate::dims::with_dim;
use crate::errors::{busy, guard, internal, kernel};
use crate::potential::{Pot, PotentialSpec};
use crate::views::{Layout, layout_of};

/// The L-BFGS memory of the polish (the kernel's `M`).
pub const MEMORY: usize = 8;

/// Coordinate-steps (chains x `D` per step) of a built-in potential's
/// run between two checks for a signal (Ctrl-C): a few milliseconds at
/// the kernel's 5 to 20 ns per coordinate-step. Counted in work, not
/// time, so that where a run checks never depends on the machine.
pub const SIGNAL_WORK: u64 = 1 << 18;

/// Steps between two checks for a signal, for `n` chains of dimension `d`.
pub fn signal_steps(n: usize, d: usize) -> u64 {
    (SIGNAL_WORK / (n as u64).saturating_mul(d as u64).max(1)).max(1)
}

/// Storage for `n` chains of dimension `D`, or `MemoryError` naming
/// `chains` when it cannot be allocated: the size is checked and reserved
/// before anything is written, so a huge count allocates nothing.
pub fn storage<const D: usize>(n: usize) -> PyResult<Vec<Chain<f64, D>>> {
    let size = size_of::<Chain<f64, D>>();
    let refuse = |why: &str| {
        PyMemoryError::new_err(format!(
            "chains={n}: {n} chains of dimension {D} ({size} bytes each) {why}"
        ))
    };
    match n.checked_mul(size) {
        Some(bytes) if bytes <= isize::MAX as usize => {}
        _ => return Err(refuse("need more bytes than an address space holds")),
    }
    let mut chains = Vec::new();
    chains
        .try_reserve_exact(n)
        .map_err(|_| refuse("cannot be allocated"))?;
    chains.extend((0..n).map(|_| Chain::new()));
    Ok(chains)
}

/// Where the chains may go: all of `R^D`, or a box.
#[derive(Clone, Copy)]
pub enum Bounds {
    Unbounded,
    Box(Interval<f64>),
}

impl<const D: usize> Domain<f64, D> for Bounds {
    #[inline]
    fn confine(&self, x: &mut [f64; D], y: &mut [f64; D]) {
        if let Self::Box(b) = self {
            b.confine(x, y);
        }
    }
    #[inline]
    fn project(&self, x: &mut [f64; D]) {
        if let Self::Box(b) = self {
            Domain::<f64, D>::project(b, x);
        }
    }
    #[inline]
    fn feasible_direction(&self, x: &[f64; D], d: &mut [f64; D]) {
        if let Self::Box(b) = self {
            b.feasible_direction(x, d);
        }
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

/// What `hrla.Optimizer` needs of a run, whatever its dimension.
pub trait Engine: Send + Sync {
    fn step(&mut self, py: Python<'_>, steps: u64) -> PyResult<()>;
    fn run(&mut self, py: Python<'_>) -> PyResult<PyReport>;
    fn termination(&self) -> Option<Termination>;
    /// The report of the state now, when a stopping rule holds.
    fn report_now(&self) -> Option<PyReport>;
    fn layout(&self) -> Layout;
    fn values(&self) -> Vec<f64>;
    fn diverged(&self) -> Vec<bool>;
    fn best(&self) -> (Vec<f64>, f64, u64);
    fn best_chain(&self) -> usize;
    fn current_best(&self) -> Option<(usize, f64)>;
    fn iteration(&self) -> u64;
    fn evaluations(&self) -> u64;
    fn diverged_chains(&self) -> usize;
    fn inverse_temperature(&self) -> f64;
    fn local_search(
        &mut self,
        py: Python<'_>,
        chain: usize,
        settings: PolishSettings<f64>,
        quench: bool,
    ) -> PyResult<PyPolished>;
    fn restart(&mut self, py: Python<'_>, chain: usize, x: &[f64]) -> PyResult<bool>;
    fn dim(&self) -> usize;
    fn len(&self) -> usize;
}

/// The settings of a run, before its dimension is fixed.
pub struct Settings {
    pub potential: PotentialSpec,
    pub sampler: AnySampler<f64>,
    pub schedule: AnySchedule<f64>,
    pub start: StartSpec,
    pub domain: Bounds,
    pub seed: u64,
    pub stride: u64,
    pub stop: hrla::Stop<f64>,
    pub chains: usize,
}

impl Settings {
    pub fn build(&self, py: Python<'_>, dim: Option<usize>) -> PyResult<Box<dyn Engine>> {
        let d = dimension(&[
            ("dim", dim),
            ("the potential", self.potential.dimension()),
            ("the start", self.start.dimension()),
        ])?;
        with_dim!(d, D => Ok(Box::new(Run::<D>::build(py, self)?) as Box<dyn Engine>))
    }
}

/// The one dimension that every source that fixes one agrees on.
pub fn dimension(sources: &[(&str, Option<usize>)]) -> PyResult<usize> {
    let mut found: Option<(&str, usize)> = None;
    for &(name, d) in sources {
        match (found, d) {
            (None, Some(d)) => found = Some((name, d)),
            (Some((first, d0)), Some(d)) if d != d0 => {
                return Err(PyValueError::new_err(format!(
                    "{first} has dimension {d0} but {name} has {d}"
                )));
            }
            _ => {}
        }
    }
    found.map(|(_, d)| d).ok_or_else(|| {
        PyValueError::new_err("the dimension is not fixed by the potential or the start: give dim=")
    })
}

struct Run<const D: usize> {
    opt: Opt<D>,
    /// The error that ended the run (a step, polish, quench or restart
    /// that found every chain diverged or the potential unbounded below):
    /// every later step, run, polish, quench or restart returns it, `run`
    /// too when a stopping rule holds, so a failed run never turns into a
    /// report; and a Python potential is not called again.
    failed: Option<hrla::Error>,
}

impl<const D: usize> Run<D> {
    fn build(py: Python<'_>, s: &Settings) -> PyResult<Self> {
        let potential = s.potential.build::<D>(py)?;
        let mut start = s.start.build::<D>()?;
        let chains = storage::<D>(s.chains)?;
        if let (Pot::Python(p), true) = (&potential, s.chains > 0) {
            // The initial points, as the builder will draw them. A chain
            // holds its position, so `chains * D` floats fit in less than
            // the storage just allocated: the product cannot overflow.
            let mut points = Vec::new();
            points
                .try_reserve_exact(s.chains * D)
                .map_err(|_| PyMemoryError::new_err("the initial points cannot be allocated"))?;
            for c in 0..s.chains {
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(chain_seed(s.seed, c as u64));
                let (mut x, mut y) = ([0.0; D], [0.0; D]);
                let mut draw = start;
                draw.initial_point(c, &mut rng, &mut x);
                s.domain.confine(&mut x, &mut y);
                points.extend_from_slice(&x);
            }
            p.load(py, points)?;
        }
        let built = Builder::new(potential, s.sampler, s.schedule, &mut start)
            .domain(s.domain)
            .seed(s.seed)
            .stride(s.stride)
            .stop(s.stop)
            .build(chains);
        let opt = match built {
            Ok(opt) => opt,
            Err(e) => return Err(kernel(e)),
        };
        let run = Self { opt, failed: None };
        run.finish()?;
        Ok(run)
    }

    /// The Python potential's first error since the last call, if any.
    fn finish(&self) -> PyResult<()> {
        match self.opt.potential() {
            Pot::Python(p) => p.finish(),
            Pot::Builtin(_) => Ok(()),
        }
    }

    fn is_python(&self) -> bool {
        matches!(self.opt.potential(), Pot::Python(_))
    }

    /// For a Python potential: the next positions of the live chains, by
    /// the step the optimiser is about to take, evaluated in one call.
    fn prepare(&self, py: Python<'_>) -> PyResult<()> {
        let Pot::Python(p) = self.opt.potential() else {
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
            fresh = self.opt.sampler().at(a).map_err(kernel)?;
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
        p.load(py, points)
    }

    fn step_once(&mut self, py: Python<'_>) -> PyResult<()> {
        self.prepare(py)?;
        let stepped = self.opt.step();
        let stepped = self.keep(stepped);
        self.finish()?;
        stepped
    }

    /// The error that ended the run, if it has.
    fn check(&self) -> PyResult<()> {
        self.failed.map_or(Ok(()), |e| Err(kernel(e)))
    }

    /// `result`, keeping its error when it ends the run.
    fn keep<T>(&mut self, result: Result<T, hrla::Error>) -> PyResult<T> {
        if let Err(
            e @ (hrla::Error::AllDiverged { .. }
            | hrla::Error::UnboundedBelow { .. }
            | hrla::Error::Poisoned),
        ) = result
        {
            self.failed = Some(e);
        }
        result.map_err(kernel)
    }

    fn report(&self, termination: Termination) -> PyReport {
        hrla::Report {
            value: self.opt.best().value,
            chain: self.opt.best_chain(),
            found_at: self.opt.best().iteration,
            iterations: self.opt.iteration(),
            evaluations: self.opt.evaluations(),
            diverged_chains: self.opt.diverged_chains(),
            chains: self.opt.chains().len(),
            termination,
        }
        .into()
    }
}

impl<const D: usize> Engine for Run<D> {
    fn step(&mut self, py: Python<'_>, steps: u64) -> PyResult<()> {
        self.check()?;
        if self.is_python() {
            for _ in 0..steps {
                self.step_once(py)?;
                py.check_signals()?;
            }
            return Ok(());
        }
        // Chunks of steps with the GIL released, a check for Ctrl-C
        // between two: an interrupted call leaves the optimiser after a
        // whole step, so that going on gives the bits of a run never
        // interrupted.
        let chunk = signal_steps(self.opt.chains().len(), D);
        let mut left = steps;
        while left > 0 {
            let n = left.min(chunk);
            let opt = &mut self.opt;
            let stepped = py.detach(|| (0..n).try_for_each(|_| opt.step()));
            self.keep(stepped)?;
            left -= n;
            if left > 0 {
                py.check_signals()?;
            }
        }
        Ok(())
    }

    fn run(&mut self, py: Python<'_>) -> PyResult<PyReport> {
        // The kernel's `run` refuses a run with no stopping rule, and so
        // does this one, whose loop is `run_with`'s or its own.
        if self.opt.stop().is_empty() {
            return Err(kernel(hrla::Error::NoStoppingRule));
        }
        self.check()?;
        if !self.is_python() {
            // The kernel's loop, with the GIL released; its observer,
            // called every `every` steps (and on improvements, which it
            // lets pass), looks for Ctrl-C and ends the run after a whole
            // step when one came.
            let every = signal_steps(self.opt.chains().len(), D);
            let mut interrupted = None;
            let opt = &mut self.opt;
            let report = py.detach(|| {
                opt.run_with(every, |p| {
                    if !p.iteration.is_multiple_of(every) {
                        return ControlFlow::Continue(());
                    }
                    match Python::attach(|py| py.check_signals()) {
                        Ok(()) => ControlFlow::Continue(()),
                        Err(e) => {
                            interrupted = Some(e);
                            ControlFlow::Break(())
                        }
                    }
                })
            });
            let report = self.keep(report);
            return match interrupted {
                Some(e) => Err(e),
                None => report.map(Into::into),
            };
        }
        // The kernel's `run`, with the batched call before each step.
        loop {
            if let Some(t) = self.opt.termination() {
                return Ok(self.report(t));
            }
            self.step_once(py)?;
            py.check_signals()?;
        }
    }

    fn termination(&self) -> Option<Termination> {
        self.opt.termination()
    }

    fn report_now(&self) -> Option<PyReport> {
        self.opt.termination().map(|t| self.report(t))
    }

    fn layout(&self) -> Layout {
        layout_of(self.opt.chains())
    }

    fn values(&self) -> Vec<f64> {
        self.opt.chains().iter().map(|c| c.value()).collect()
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
        py: Python<'_>,
        chain: usize,
        settings: PolishSettings<f64>,
        quench: bool,
    ) -> PyResult<PyPolished> {
        self.check()?;
        let mut lbfgs: Box<Lbfgs<f64, D, MEMORY>> = Box::default();
        let python = self.is_python();
        let opt = &mut self.opt;
        let mut search = || {
            if quench {
                opt.quench(chain, &mut lbfgs, settings)
            } else {
                opt.polish(chain, &mut lbfgs, settings)
            }
        };
        let done = if python { search() } else { py.detach(search) };
        let done = self.keep(done);
        self.finish()?;
        done.map(Into::into)
    }

    fn restart(&mut self, _py: Python<'_>, chain: usize, x: &[f64]) -> PyResult<bool> {
        let x: [f64; D] = x.try_into().map_err(|_| {
            PyValueError::new_err(format!("x has {} coordinates, the run {D}", x.len()))
        })?;
        self.check()?;
        let done = self.opt.restart(chain, &x);
        let done = self.keep(done);
        self.finish()?;
        done
    }

    fn dim(&self) -> usize {
        D
    }

    fn len(&self) -> usize {
        self.opt.chains().len()
    }
}

/// Algorithm 1 of the paper, step by step: `N` independent chains of a
/// sampler on a potential at the inverse temperatures of a schedule,
/// keeping the best point visited. The chains are readable at any time as
/// numpy arrays that look into the optimiser's own storage (`x`, `y`,
/// `gradient`, `best_x`, `best_value`: read-only, no copy, updated in
/// place by every step).
///
/// One call at a time: while `run`, `step`, `polish`, `quench` or
/// `restart` runs, any other call but the views (from the potential, or
/// another thread) raises `BusyError` and does nothing.
#[pyclass(frozen, module = "hrla", name = "Optimizer")]
pub struct PyOptimizer {
    engine: Mutex<Box<dyn Engine>>,
    /// Where the chains are: fixed for the optimiser's life (the kernel
    /// never moves or resizes its chains), so the views need no lock.
    layout: Layout,
    dim: usize,
    len: usize,
}

impl PyOptimizer {
    /// The `(N, D)` field `field` of the chains, as a view.
    fn rows(slf: Bound<'_, Self>, field: fn(&Layout) -> usize) -> Bound<'_, PyArray2<f64>> {
        let offset = field(&slf.get().layout);
        crate::views::rows(slf.clone().into_any(), &slf.get().layout, offset)
    }

    /// Runs `body` on the engine: `BusyError` when a call is running,
    /// `InternalError` when a panic interrupted an earlier one (the
    /// panic poisons the lock, since the state it left is not known) or
    /// this one.
    fn with<T>(&self, body: impl FnOnce(&mut dyn Engine) -> PyResult<T>) -> PyResult<T> {
        guard(|| {
            let mut engine: MutexGuard<'_, Box<dyn Engine>> = match self.engine.try_lock() {
                Ok(e) => e,
                Err(TryLockError::WouldBlock) => {
                    return Err(busy(
                        "the optimiser is running (called from its potential or another thread \
                         while run, step, polish, quench or restart runs); nothing was done",
                    ));
                }
                Err(TryLockError::Poisoned(_)) => {
                    return Err(internal(
                        "the optimiser is unusable: an internal error interrupted an earlier call",
                    ));
                }
            };
            body(&mut **engine)
        })
    }
}

#[pymethods]
impl PyOptimizer {
    #[new]
    #[pyo3(signature = (potential, sampler, schedule, start, *, chains = 10, seed = 0, stride = 1, stop = None, domain = None, dim = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        potential: &Bound<'_, PyAny>,
        sampler: &Bound<'_, PyAny>,
        schedule: &Bound<'_, PyAny>,
        start: &Bound<'_, PyAny>,
        chains: usize,
        seed: u64,
        stride: u64,
        stop: Option<PyStop>,
        domain: Option<PyInterval>,
        dim: Option<usize>,
    ) -> PyResult<Self> {
        guard(|| {
            let settings = Settings {
                potential: PotentialSpec::from_py(potential)?,
                sampler: config::sampler(sampler)?,
                schedule: config::schedule(schedule)?,
                start: config::start(start)?,
                domain: domain.map_or(Bounds::Unbounded, |b| Bounds::Box(b.0)),
                seed,
                stride,
                stop: stop.unwrap_or_default().0,
                chains,
            };
            let engine = settings.build(py, dim)?;
            Ok(Self {
                layout: engine.layout(),
                dim: engine.dim(),
                len: engine.len(),
                engine: Mutex::new(engine),
            })
        })
    }

    /// Advances every live chain by `steps` steps (default 1), without
    /// consulting the stopping rules. Ctrl-C interrupts it after a whole
    /// step (`KeyboardInterrupt`); calling it again goes on as if
    /// uninterrupted.
    #[pyo3(signature = (steps = 1))]
    fn step(&self, py: Python<'_>, steps: u64) -> PyResult<()> {
        self.with(|e| e.step(py, steps))
    }

    /// Steps until a stopping rule holds; returns the `Report`. Ctrl-C
    /// interrupts it after a whole step (`KeyboardInterrupt`); calling it
    /// again goes on as if uninterrupted.
    fn run(&self, py: Python<'_>) -> PyResult<PyReport> {
        self.with(|e| e.run(py))
    }

    /// The first stopping rule that holds now (`"Steps"`, `"Evaluations"`,
    /// `"Target"`, `"Stalled"`), or `None`.
    fn termination(&self) -> PyResult<Option<&'static str>> {
        self.with(|e| Ok(e.termination().map(config::termination_name)))
    }

    /// The `Report` of the state now, as `run` would return it, when a
    /// stopping rule holds (after a `polish`, the polished best); `None`
    /// when none holds.
    fn report(&self) -> PyResult<Option<PyReport>> {
        self.with(|e| Ok(e.report_now()))
    }

    /// L-BFGS from chain `chain`'s best point; the result replaces that
    /// best when lower. Within the evaluation budget.
    #[pyo3(signature = (chain, settings = None))]
    fn polish(
        &self,
        py: Python<'_>,
        chain: usize,
        settings: Option<PyPolishSettings>,
    ) -> PyResult<PyPolished> {
        let s = settings.map_or(PolishSettings::new(1000), |s| s.0);
        self.with(|e| e.local_search(py, chain, s, false))
    }

    /// L-BFGS from a copy of chain `chain`'s current point (the bottom of
    /// its basin); the chain's state is untouched.
    #[pyo3(signature = (chain, settings = None))]
    fn quench(
        &self,
        py: Python<'_>,
        chain: usize,
        settings: Option<PyPolishSettings>,
    ) -> PyResult<PyPolished> {
        let s = settings.map_or(PolishSettings::new(1000), |s| s.0);
        self.with(|e| e.local_search(py, chain, s, true))
    }

    /// Moves chain `chain` to `x` (confined) with zero velocity and
    /// evaluates it: one evaluation; `False` when none is left.
    fn restart(&self, py: Python<'_>, chain: usize, x: Vec<f64>) -> PyResult<bool> {
        self.with(|e| e.restart(py, chain, &x))
    }

    /// Positions `x_k`, shape `(N, D)`: a read-only view, no copy.
    #[getter]
    fn x<'py>(slf: Bound<'py, Self>) -> Bound<'py, PyArray2<f64>> {
        Self::rows(slf, |l| l.x)
    }

    /// Velocities `y_k`, shape `(N, D)` (zero for OLA): a view.
    #[getter]
    fn y<'py>(slf: Bound<'py, Self>) -> Bound<'py, PyArray2<f64>> {
        Self::rows(slf, |l| l.y)
    }

    /// Gradients `∇U(x_k)`, shape `(N, D)`: a view.
    #[getter]
    fn gradient<'py>(slf: Bound<'py, Self>) -> Bound<'py, PyArray2<f64>> {
        Self::rows(slf, |l| l.gradient)
    }

    /// Each chain's best point, shape `(N, D)`: a view.
    #[getter]
    fn best_x<'py>(slf: Bound<'py, Self>) -> Bound<'py, PyArray2<f64>> {
        Self::rows(slf, |l| l.best_x)
    }

    /// Each chain's best value, shape `(N,)`: a view.
    #[getter]
    fn best_value<'py>(slf: Bound<'py, Self>) -> Bound<'py, PyArray1<f64>> {
        let offset = slf.get().layout.best_value;
        crate::views::column(slf.clone().into_any(), &slf.get().layout, offset)
    }

    /// `U(x_k)` per chain, shape `(N,)` (a new array).
    #[getter]
    fn value<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = self.with(|e| Ok(e.values()))?;
        Ok(PyArray1::from_vec(py, v))
    }

    /// Whether each chain has diverged (frozen, excluded), shape `(N,)`.
    #[getter]
    fn diverged<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let v = self.with(|e| Ok(e.diverged()))?;
        Ok(PyArray1::from_vec(py, v))
    }

    /// The global running best: `(x, value, iteration)`.
    #[getter]
    fn best<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyArray1<f64>>, f64, u64)> {
        let (x, v, k) = self.with(|e| Ok(e.best()))?;
        Ok((PyArray1::from_vec(py, x), v, k))
    }

    /// The chain holding the global running best.
    #[getter]
    fn best_chain(&self) -> PyResult<usize> {
        self.with(|e| Ok(e.best_chain()))
    }

    /// `(chain, U(x_k))` of the live chain lowest now, or `None`.
    fn current_best(&self) -> PyResult<Option<(usize, f64)>> {
        self.with(|e| Ok(e.current_best()))
    }

    /// Steps done (the current iterate `k`).
    #[getter]
    fn iteration(&self) -> PyResult<u64> {
        self.with(|e| Ok(e.iteration()))
    }

    /// Potential-and-gradient evaluations so far.
    #[getter]
    fn evaluations(&self) -> PyResult<u64> {
        self.with(|e| Ok(e.evaluations()))
    }

    /// Chains diverged so far.
    #[getter]
    fn diverged_chains(&self) -> PyResult<usize> {
        self.with(|e| Ok(e.diverged_chains()))
    }

    /// The inverse temperature of the last step (`a_0` before the first).
    #[getter]
    fn inverse_temperature(&self) -> PyResult<f64> {
        self.with(|e| Ok(e.inverse_temperature()))
    }

    /// The dimension `D`.
    #[getter]
    fn dim(&self) -> usize {
        self.dim
    }

    /// The number of chains `N`.
    fn __len__(&self) -> usize {
        self.len
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyOptimizer>()
}

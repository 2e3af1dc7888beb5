//! `hrla.Optimizer`: the kernel's optimiser in one of the compiled
//! dimensions, behind an object-safe [`Engine`], with its chains readable
//! as numpy arrays.

use hrla::{
    AnySampler, AnySchedule, Builder, Chain, Domain, Interval, Kernel, Lbfgs, Optimizer,
    PolishSettings, Sampler, Schedule, Start, Termination, chain_seed,
};
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::config::{self, PyInterval, PyPolishSettings, PyPolished, PyReport, PyStop, StartSpec};
use crate::dims::with_dim;
use crate::errors::kernel;
use crate::potential::{Pot, PotentialSpec};
use crate::views::{Layout, layout_of};

/// The L-BFGS memory of the polish (the kernel's `M`).
pub const MEMORY: usize = 8;

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
    /// A step failed with a run-ending error: later steps return it
    /// without calling a Python potential first.
    failed: bool,
}

impl<const D: usize> Run<D> {
    fn build(py: Python<'_>, s: &Settings) -> PyResult<Self> {
        let potential = s.potential.build::<D>(py)?;
        let mut start = s.start.build::<D>()?;
        if let (Pot::Python(p), true) = (&potential, s.chains > 0) {
            // The initial points, as the builder will draw them.
            let mut points = Vec::with_capacity(s.chains * D);
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
        let chains: Vec<Chain<f64, D>> = (0..s.chains).map(|_| Chain::new()).collect();
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
        let run = Self { opt, failed: false };
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
        if self.failed {
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
        self.finish()?;
        if let Err(e) = stepped {
            self.failed |= matches!(
                e,
                hrla::Error::AllDiverged { .. } | hrla::Error::UnboundedBelow { .. }
            );
            return Err(kernel(e));
        }
        Ok(())
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
        if self.is_python() {
            for _ in 0..steps {
                self.step_once(py)?;
                py.check_signals()?;
            }
            return Ok(());
        }
        let opt = &mut self.opt;
        py.detach(|| (0..steps).try_for_each(|_| opt.step()))
            .map_err(kernel)
    }

    fn run(&mut self, py: Python<'_>) -> PyResult<PyReport> {
        if !self.is_python() {
            let opt = &mut self.opt;
            return py.detach(|| opt.run()).map(Into::into).map_err(kernel);
        }
        // The kernel's `run`, with the batched call before each step.
        if self.opt.stop().is_empty() {
            return Err(kernel(hrla::Error::NoStoppingRule));
        }
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
        self.finish()?;
        done.map(Into::into).map_err(kernel)
    }

    fn restart(&mut self, _py: Python<'_>, chain: usize, x: &[f64]) -> PyResult<bool> {
        let x: [f64; D] = x.try_into().map_err(|_| {
            PyValueError::new_err(format!("x has {} coordinates, the run {D}", x.len()))
        })?;
        let done = self.opt.restart(chain, &x);
        self.finish()?;
        done.map_err(kernel)
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
#[pyclass(module = "hrla", name = "Optimizer")]
pub struct PyOptimizer {
    engine: Box<dyn Engine>,
}

impl PyOptimizer {
    /// The `(N, D)` field `field` of the chains, as a view.
    fn rows(slf: Bound<'_, Self>, field: fn(&Layout) -> usize) -> Bound<'_, PyArray2<f64>> {
        let l = slf.borrow().engine.layout();
        crate::views::rows(slf.into_any(), &l, field(&l))
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
        Ok(Self {
            engine: settings.build(py, dim)?,
        })
    }

    /// Advances every live chain by `steps` steps (default 1), without
    /// consulting the stopping rules.
    #[pyo3(signature = (steps = 1))]
    fn step(&mut self, py: Python<'_>, steps: u64) -> PyResult<()> {
        self.engine.step(py, steps)
    }

    /// Steps until a stopping rule holds; returns the `Report`.
    fn run(&mut self, py: Python<'_>) -> PyResult<PyReport> {
        self.engine.run(py)
    }

    /// The first stopping rule that holds now (`"Steps"`, `"Evaluations"`,
    /// `"Target"`, `"Stalled"`), or `None`.
    fn termination(&self) -> Option<&'static str> {
        self.engine.termination().map(config::termination_name)
    }

    /// L-BFGS from chain `chain`'s best point; the result replaces that
    /// best when lower. Within the evaluation budget.
    #[pyo3(signature = (chain, settings = None))]
    fn polish(
        &mut self,
        py: Python<'_>,
        chain: usize,
        settings: Option<PyPolishSettings>,
    ) -> PyResult<PyPolished> {
        let s = settings.map_or(PolishSettings::new(1000), |s| s.0);
        self.engine.local_search(py, chain, s, false)
    }

    /// L-BFGS from a copy of chain `chain`'s current point (the bottom of
    /// its basin); the chain's state is untouched.
    #[pyo3(signature = (chain, settings = None))]
    fn quench(
        &mut self,
        py: Python<'_>,
        chain: usize,
        settings: Option<PyPolishSettings>,
    ) -> PyResult<PyPolished> {
        let s = settings.map_or(PolishSettings::new(1000), |s| s.0);
        self.engine.local_search(py, chain, s, true)
    }

    /// Moves chain `chain` to `x` (confined) with zero velocity and
    /// evaluates it: one evaluation; `False` when none is left.
    fn restart(&mut self, py: Python<'_>, chain: usize, x: Vec<f64>) -> PyResult<bool> {
        self.engine.restart(py, chain, &x)
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
        let l = slf.borrow().engine.layout();
        crate::views::column(slf.into_any(), &l, l.best_value)
    }

    /// `U(x_k)` per chain, shape `(N,)` (a new array).
    #[getter]
    fn value<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.engine.values())
    }

    /// Whether each chain has diverged (frozen, excluded), shape `(N,)`.
    #[getter]
    fn diverged<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_vec(py, self.engine.diverged())
    }

    /// The global running best: `(x, value, iteration)`.
    #[getter]
    fn best<'py>(&self, py: Python<'py>) -> (Bound<'py, PyArray1<f64>>, f64, u64) {
        let (x, v, k) = self.engine.best();
        (PyArray1::from_vec(py, x), v, k)
    }

    /// The chain holding the global running best.
    #[getter]
    fn best_chain(&self) -> usize {
        self.engine.best_chain()
    }

    /// `(chain, U(x_k))` of the live chain lowest now, or `None`.
    fn current_best(&self) -> Option<(usize, f64)> {
        self.engine.current_best()
    }

    /// Steps done (the current iterate `k`).
    #[getter]
    fn iteration(&self) -> u64 {
        self.engine.iteration()
    }

    /// Potential-and-gradient evaluations so far.
    #[getter]
    fn evaluations(&self) -> u64 {
        self.engine.evaluations()
    }

    /// Chains diverged so far.
    #[getter]
    fn diverged_chains(&self) -> usize {
        self.engine.diverged_chains()
    }

    /// The inverse temperature of the last step (`a_0` before the first).
    #[getter]
    fn inverse_temperature(&self) -> f64 {
        self.engine.inverse_temperature()
    }

    /// The dimension `D`.
    #[getter]
    fn dim(&self) -> usize {
        self.engine.dim()
    }

    /// The number of chains `N`.
    fn __len__(&self) -> usize {
        self.engine.len()
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyOptimizer>()
}

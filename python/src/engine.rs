//! `hrla.Optimizer`: the layer's run ([`hrla_dyn::Engine`]), with its
//! chains readable as numpy arrays; this module adds only what Python
//! needs around it: the GIL released while the kernel runs a built-in,
//! Ctrl-C between steps, one call at a time, and the end of a run whose
//! Python potential raised.

use std::sync::{Mutex, MutexGuard, TryLockError};

use hrla::{Observe, PolishSettings};
use hrla_dyn::{Engine, Layout, Settings};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::config::{self, PyPolishSettings, PyPolished, PyReport, PyStop};
use crate::errors::{busy, guard, internal, layer};
use crate::observer::{observer_of, signal_steps};
use crate::potential;

/// Steps the engine: a built-in's in chunks with the GIL released, a
/// check for Ctrl-C between two; a Python function's one at a time (it
/// needs the GIL), a check after each. A call interrupted by a check
/// leaves the optimiser after a whole step, so that going on gives the
/// bits of a run never interrupted; an exception of the potential ends it
/// at once, and the layer undoes the step it was in, so that going on
/// does too.
fn step(py: Python<'_>, engine: &mut Engine, steps: u64) -> PyResult<()> {
    if engine.is_user() {
        for _ in 0..steps {
            engine.step(1).map_err(layer)?;
            py.check_signals()?;
        }
        return Ok(());
    }
    let chunk = signal_steps(engine.len(), engine.dim());
    let mut left = steps;
    while left > 0 {
        let n = left.min(chunk);
        py.detach(|| engine.step(n)).map_err(layer)?;
        left -= n;
        if left > 0 {
            py.check_signals()?;
        }
    }
    Ok(())
}

/// Runs the engine to its end: the layer's loop, with the GIL released for
/// a built-in; its observer looks for Ctrl-C (a built-in's every
/// `signal_steps`, a Python function's after every step) and ends the run
/// after a whole step when one came. The user's `observer`, when given,
/// is called at the same steps (once a step), after the check:
/// `observer(iteration, evaluations, best_value[, best_x])`; a true answer ends the
/// run ([`hrla::Termination::Observer`]), an exception ends it with that
/// exception. An exception of the potential ends it at once, and the
/// layer undoes the call it was in: the optimiser is as before `run`.
fn run(
    py: Python<'_>,
    engine: &mut Engine,
    user_observer: Option<&Py<PyAny>>,
    with_x: bool,
) -> PyResult<PyReport> {
    let user = engine.is_user();
    let every = if user {
        1
    } else {
        signal_steps(engine.len(), engine.dim())
    };
    let mut interrupted = None;
    let mut observer = |p: &hrla_dyn::Progress| {
        Python::attach(|py| crate::observer::look(py, user_observer, p, with_x, &mut interrupted))
    };
    let report = if user {
        engine.run(Observe::Every(every), &mut observer)
    } else {
        py.detach(|| engine.run(Observe::Every(every), &mut observer))
    };
    match interrupted {
        Some(e) => Err(e),
        None => report.map(Into::into).map_err(layer),
    }
}

/// A polish or quench, with the GIL released for a built-in.
fn local_search(
    py: Python<'_>,
    engine: &mut Engine,
    chain: usize,
    settings: PolishSettings<f64>,
    quench: bool,
) -> PyResult<PyPolished> {
    let done = if engine.is_user() {
        engine.local_search(chain, settings, quench)
    } else {
        py.detach(|| engine.local_search(chain, settings, quench))
    };
    done.map(Into::into).map_err(layer)
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
    engine: Mutex<Engine>,
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
    fn with<T>(&self, body: impl FnOnce(&mut Engine) -> PyResult<T>) -> PyResult<T> {
        guard(|| {
            let mut engine: MutexGuard<'_, Engine> = match self.engine.try_lock() {
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
            body(&mut engine)
        })
    }
}

#[pymethods]
impl PyOptimizer {
    #[new]
    #[pyo3(signature = (potential, sampler, schedule, start, *, chains = None, seed = None, stride = None, stop = None, domain = None, dim = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        potential: &Bound<'_, PyAny>,
        sampler: &Bound<'_, PyAny>,
        schedule: &Bound<'_, PyAny>,
        start: &Bound<'_, PyAny>,
        chains: Option<&Bound<'_, PyAny>>,
        seed: Option<&Bound<'_, PyAny>>,
        stride: Option<&Bound<'_, PyAny>>,
        stop: Option<PyStop>,
        domain: Option<&Bound<'_, PyAny>>,
        dim: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        guard(|| {
            let chains = config::unsigned_opt(chains, "chains")?.unwrap_or(10);
            let seed = config::unsigned_opt(seed, "seed")?.unwrap_or(0);
            let stride = config::unsigned_opt(stride, "stride")?.unwrap_or(1);
            let dim = config::unsigned_opt(dim, "dim")?;
            let settings = Settings {
                potential: potential::from_py(potential)?,
                sampler: config::sampler(sampler)?,
                schedule: config::schedule(schedule)?,
                start: config::start(start)?,
                domain: domain.map(config::domain).transpose()?,
                seed,
                stride,
                stop: stop.unwrap_or_default().0,
                chains,
                dim,
                escape: None,
            };
            let engine = settings.build().map_err(layer)?;
            Ok(Self {
                layout: engine.layout(),
                dim: engine.dim(),
                len: engine.len(),
                engine: Mutex::new(engine),
            })
        })
    }

    /// Advances every live chain by `steps` steps (default 1), without
    /// consulting the stopping rules. Ctrl-C seen between two steps
    /// interrupts it after a whole step (`KeyboardInterrupt`), and calling
    /// it again goes on as if uninterrupted. An exception of a Python
    /// potential (`KeyboardInterrupt` raised while it runs included) ends
    /// the call at once, the potential not called again, and undoes the
    /// step it was in: calling it again goes on as if uninterrupted.
    #[pyo3(signature = (steps = None))]
    fn step(&self, py: Python<'_>, steps: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let steps = config::unsigned_opt(steps, "steps")?.unwrap_or(1);
        self.with(|e| step(py, e, steps))
    }

    /// Steps until a stopping rule holds; returns the `Report`. Ctrl-C
    /// and the potential's exceptions end it as they end `step`.
    ///
    /// `observer(iteration, evaluations, best_value)`, when given, is
    /// called after every step of a Python potential's run and every few
    /// thousand coordinate-steps of a built-in's; a true answer ends the
    /// run (termination `"Observer"`), an exception ends it with that
    /// exception. The bits of the run do not depend on it. With
    /// `with_x=True` it gets the best point too, a copy:
    /// `observer(iteration, evaluations, best_value, best_x)`.
    #[pyo3(signature = (observer = None, *, with_x = false))]
    fn run(
        &self,
        py: Python<'_>,
        observer: Option<&Bound<'_, PyAny>>,
        with_x: bool,
    ) -> PyResult<PyReport> {
        let observer = observer_of(observer)?;
        self.with(|e| run(py, e, observer.as_ref(), with_x))
    }

    /// The first stopping rule that holds now (`"Steps"`, `"Evaluations"`,
    /// `"Target"`, `"Stalled"`), or `None`.
    fn termination(&self) -> PyResult<Option<&'static str>> {
        self.with(|e| Ok(e.termination().map(hrla_dyn::termination_name)))
    }

    /// The `Report` of the state now, as `run` would return it, when a
    /// stopping rule holds (after a `polish`, the polished best); `None`
    /// when none holds.
    fn report(&self) -> PyResult<Option<PyReport>> {
        self.with(|e| Ok(e.report_now().map(Into::into)))
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
        self.with(|e| local_search(py, e, chain, s, false))
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
        self.with(|e| local_search(py, e, chain, s, true))
    }

    /// Moves chain `chain` to `x` (confined) with zero velocity and
    /// evaluates it: one evaluation; `False` when none is left.
    fn restart(&self, chain: usize, x: Vec<f64>) -> PyResult<bool> {
        self.with(|e| e.restart(chain, &x).map_err(layer))
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

/// How a sampler's run of `budget` evaluations with `chains` chains
/// shares it with the polish at its end (`polish` evaluations, or the
/// default share; `x0`: a start of the caller's, one evaluation more):
/// `(steps, polish)`, `steps` `None` where only the budget ends the
/// sampling; `None` where the polish leaves no whole step.
#[pyfunction]
#[pyo3(signature = (budget, chains, polish = None, x0 = false))]
fn split_budget(
    budget: u64,
    chains: usize,
    polish: Option<u64>,
    x0: bool,
) -> Option<(Option<u64>, u64)> {
    hrla_dyn::budget::split(budget, chains, polish, x0).map(|s| (s.steps, s.polish))
}

/// `Auto`'s budget, in gradients, in a run without a gradient of `budget`
/// gradients of `cost` calls each (`spare` kept back), whose ensemble
/// takes the rest; `None` where the ensemble takes no part (`dim` beyond
/// `ENSEMBLE_MAX_DIM`).
#[pyfunction]
#[pyo3(signature = (budget, dim, cost, spare, chains = None))]
fn auto_share(
    budget: u64,
    dim: usize,
    cost: u64,
    spare: u64,
    chains: Option<usize>,
) -> Option<u64> {
    hrla_dyn::budget::auto_share(budget, dim, cost, spare, chains)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyOptimizer>()?;
    m.add_function(wrap_pyfunction!(split_budget, m)?)?;
    m.add_function(wrap_pyfunction!(auto_share, m)?)
}

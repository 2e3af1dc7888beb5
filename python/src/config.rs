//! The pieces of a run, as Python values: samplers, schedules, starts,
//! stopping rules, the box and the polish's settings. Each constructor
//! checks its numbers with the kernel's own constructor where that needs
//! no dimension, so a bad value raises the kernel's message at once.

use hrla::{
    AnySampler, AnySchedule, Constant, Geometric, Hrla, HrlaParams, Linear, Ola, OlaParams,
    PolishEnd, PolishSettings, Stop, Ula, UlaParams,
};
use hrla_dyn::{BoxSpec, StartSpec, termination_name};
use pyo3::exceptions::{PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::errors::kernel;

/// A count or seed argument `name`: a Python integer (or anything with
/// `__index__`, a numpy integer say) in `0..=T::MAX`. A negative value is
/// `ValueError` and one too large `OverflowError`, each naming the
/// argument (Python's own conversion names neither).
pub fn unsigned<T: TryFrom<u64>>(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<T> {
    let int = obj.call_method0("__index__").map_err(|_| {
        PyTypeError::new_err(format!(
            "{name} must be an int, got {}",
            obj.get_type()
                .name()
                .map_or_else(|_| "?".into(), |s| s.to_string())
        ))
    })?;
    if int.lt(0)? {
        return Err(PyValueError::new_err(format!(
            "{name} must be >= 0, got {int}"
        )));
    }
    let too_large =
        || PyOverflowError::new_err(format!("{name} = {int} is too large (at most 2**64 - 1)"));
    let wide: u64 = int.extract().map_err(|_| too_large())?;
    T::try_from(wide).map_err(|_| too_large())
}

/// [`unsigned`] for an optional argument (`None` is `None`).
pub fn unsigned_opt<T: TryFrom<u64>>(
    obj: Option<&Bound<'_, PyAny>>,
    name: &str,
) -> PyResult<Option<T>> {
    obj.filter(|o| !o.is_none())
        .map(|o| unsigned(o, name))
        .transpose()
}

/// HRLA, the paper's sampler: the exact step of the high-resolution
/// Langevin dynamics with the gradient frozen over the step,
///
/// ```text
/// dX = (-beta ∇U(X) + Y) dt + sqrt(2 beta / a) dB^x
/// dY = (-(a/b) ∇U(X) - alpha Y) dt + sqrt(2 alpha / b) dB^y
/// ```
///
/// whose invariant law is `exp(-a U(x) - b |y|^2 / 2)`.
#[pyclass(frozen, module = "hrla", name = "Hrla")]
#[derive(Clone)]
pub struct PyHrla(pub Hrla<f64>);

#[pymethods]
impl PyHrla {
    #[new]
    #[pyo3(signature = (h, *, b = 10.0, alpha = 1.0, beta = 1.0))]
    fn new(h: f64, b: f64, alpha: f64, beta: f64) -> PyResult<Self> {
        Hrla::new(HrlaParams { b, alpha, beta, h })
            .map(Self)
            .map_err(kernel)
    }

    /// The paper's setting (`b = 10`, `alpha = beta = 1`) at step `h`.
    #[staticmethod]
    fn paper(h: f64) -> PyResult<Self> {
        Hrla::paper(h).map(Self).map_err(kernel)
    }

    fn __repr__(&self) -> String {
        let p = self.0.params();
        format!(
            "Hrla(h={}, b={}, alpha={}, beta={})",
            p.h, p.b, p.alpha, p.beta
        )
    }
}

/// ULA, the paper's underdamped baseline: HRLA with `beta = 0` (no gradient
/// and no noise in the position's equation).
#[pyclass(frozen, module = "hrla", name = "Ula")]
#[derive(Clone)]
pub struct PyUla(pub Ula<f64>);

#[pymethods]
impl PyUla {
    #[new]
    #[pyo3(signature = (h, *, b = 10.0, alpha = 1.0))]
    fn new(h: f64, b: f64, alpha: f64) -> PyResult<Self> {
        Ula::new(UlaParams { b, alpha, h })
            .map(Self)
            .map_err(kernel)
    }

    /// The paper's setting (`b = 10`, `alpha = 1`) at step `h`.
    #[staticmethod]
    fn paper(h: f64) -> PyResult<Self> {
        Ula::paper(h).map(Self).map_err(kernel)
    }

    fn __repr__(&self) -> String {
        let p = self.0.params();
        format!("Ula(h={}, b={}, alpha={})", p.h, p.b, p.alpha)
    }
}

/// OLA, the paper's overdamped baseline (Euler–Maruyama):
/// `x' = x - alpha h ∇U(x) + sqrt(2 alpha h / a) xi`, `xi ~ N(0, I)`.
#[pyclass(frozen, module = "hrla", name = "Ola")]
#[derive(Clone)]
pub struct PyOla(pub Ola<f64>);

#[pymethods]
impl PyOla {
    #[new]
    #[pyo3(signature = (h, *, alpha = 1.0))]
    fn new(h: f64, alpha: f64) -> PyResult<Self> {
        Ola::new(OlaParams { alpha, h }).map(Self).map_err(kernel)
    }

    /// The paper's setting (`alpha = 1`) at step `h`.
    #[staticmethod]
    fn paper(h: f64) -> PyResult<Self> {
        Ola::paper(h).map(Self).map_err(kernel)
    }

    fn __repr__(&self) -> String {
        let p = self.0.params();
        format!("Ola(h={}, alpha={})", p.h, p.alpha)
    }
}

/// A sampler argument: `Hrla`, `Ula` or `Ola`.
pub fn sampler(obj: &Bound<'_, PyAny>) -> PyResult<AnySampler<f64>> {
    if let Ok(s) = obj.extract::<PyRef<PyHrla>>() {
        Ok(AnySampler::Hrla(s.0))
    } else if let Ok(s) = obj.extract::<PyRef<PyUla>>() {
        Ok(AnySampler::Ula(s.0))
    } else if let Ok(s) = obj.extract::<PyRef<PyOla>>() {
        Ok(AnySampler::Ola(s.0))
    } else {
        Err(PyTypeError::new_err(format!(
            "sampler must be hrla.Hrla, hrla.Ula or hrla.Ola, got {}",
            obj.get_type().name()?
        )))
    }
}

/// A constant inverse temperature `a_k = a` (no annealing); a plain float
/// means the same.
#[pyclass(frozen, module = "hrla", name = "Constant")]
#[derive(Clone)]
pub struct PyConstant(Constant<f64>);

#[pymethods]
impl PyConstant {
    #[new]
    fn new(a: f64) -> PyResult<Self> {
        Constant::new(a).map(Self).map_err(kernel)
    }
}

/// Linear annealing: `a_k = a_low + (a_high - a_low) k / K` for `k < K`,
/// then `a_high`. Its length `K` is the run's step budget unless a longer
/// one is given.
#[pyclass(frozen, module = "hrla", name = "Linear")]
#[derive(Clone)]
pub struct PyLinear(Linear<f64>);

#[pymethods]
impl PyLinear {
    #[new]
    fn new(a_low: f64, a_high: f64, steps: u64) -> PyResult<Self> {
        Linear::new(a_low, a_high, steps).map(Self).map_err(kernel)
    }
}

/// Geometric annealing: `a_k = a_low (a_high / a_low)^(k / K)` for `k < K`,
/// then `a_high`.
#[pyclass(frozen, module = "hrla", name = "Geometric")]
#[derive(Clone)]
pub struct PyGeometric(Geometric<f64>);

#[pymethods]
impl PyGeometric {
    #[new]
    fn new(a_low: f64, a_high: f64, steps: u64) -> PyResult<Self> {
        Geometric::new(a_low, a_high, steps)
            .map(Self)
            .map_err(kernel)
    }
}

/// A schedule argument: a float (constant `a`), `Constant`, `Linear` or
/// `Geometric`.
pub fn schedule(obj: &Bound<'_, PyAny>) -> PyResult<AnySchedule<f64>> {
    if let Ok(s) = obj.extract::<PyRef<PyConstant>>() {
        Ok(AnySchedule::Constant(s.0))
    } else if let Ok(s) = obj.extract::<PyRef<PyLinear>>() {
        Ok(AnySchedule::Linear(s.0))
    } else if let Ok(s) = obj.extract::<PyRef<PyGeometric>>() {
        Ok(AnySchedule::Geometric(s.0))
    } else if let Ok(a) = obj.extract::<f64>() {
        Constant::new(a).map(AnySchedule::Constant).map_err(kernel)
    } else {
        Err(PyTypeError::new_err(format!(
            "schedule must be a float, hrla.Constant, hrla.Linear or hrla.Geometric, got {}",
            obj.get_type().name()?
        )))
    }
}

/// The box `[lo, hi]^D`, the same interval in every coordinate. As a
/// domain the chains are reflected into it (and the polish projected); as
/// a start every chain starts uniformly in it.
#[pyclass(frozen, module = "hrla", name = "Interval")]
#[derive(Clone, Copy)]
pub struct PyInterval(pub hrla::Interval<f64>);

#[pymethods]
impl PyInterval {
    #[new]
    fn new(lo: f64, hi: f64) -> PyResult<Self> {
        hrla::Interval::new(lo, hi).map(Self).map_err(kernel)
    }
    #[getter]
    fn lo(&self) -> f64 {
        self.0.lo()
    }
    #[getter]
    fn hi(&self) -> f64 {
        self.0.hi()
    }
    fn __repr__(&self) -> String {
        format!("Interval({}, {})", self.0.lo(), self.0.hi())
    }
}

/// Independent Gaussian starts `x_0 ~ N(mean, std_dev^2 I)`; `D` is the
/// length of `mean`.
#[pyclass(frozen, module = "hrla", name = "Gaussian")]
#[derive(Clone)]
pub struct PyGaussian {
    mean: Vec<f64>,
    std_dev: f64,
}

#[pymethods]
impl PyGaussian {
    #[new]
    fn new(mean: Vec<f64>, std_dev: f64) -> Self {
        Self { mean, std_dev }
    }
}

/// Every chain starts at the point `x`; `D` is its length.
#[pyclass(frozen, module = "hrla", name = "Point")]
#[derive(Clone)]
pub struct PyPoint(Vec<f64>);

#[pymethods]
impl PyPoint {
    #[new]
    fn new(x: Vec<f64>) -> Self {
        Self(x)
    }
}

/// A box argument: an `Interval` (the same `[lo, hi]` in every
/// coordinate), or a sequence of `D` pairs `(lo_i, hi_i)`, one per
/// coordinate (the layer checks them).
pub fn domain(obj: &Bound<'_, PyAny>) -> PyResult<BoxSpec> {
    if let Ok(i) = obj.extract::<PyRef<PyInterval>>() {
        return Ok(i.0.into());
    }
    obj.extract::<Vec<(f64, f64)>>()
        .map(BoxSpec::PerCoordinate)
        .map_err(|_| {
            PyTypeError::new_err(format!(
                "a box must be hrla.Interval or a sequence of (lo, hi) pairs, got {}",
                obj.get_type()
                    .name()
                    .map_or_else(|_| "?".into(), |s| s.to_string())
            ))
        })
}

/// A start argument: `Gaussian`, `Point`, `Interval` or a box of `(lo_i,
/// hi_i)` pairs (uniform in it).
pub fn start(obj: &Bound<'_, PyAny>) -> PyResult<StartSpec> {
    if let Ok(s) = obj.extract::<PyRef<PyGaussian>>() {
        Ok(StartSpec::Gaussian {
            mean: s.mean.clone(),
            std_dev: s.std_dev,
        })
    } else if let Ok(s) = obj.extract::<PyRef<PyPoint>>() {
        Ok(StartSpec::Point(s.0.clone()))
    } else if let Ok(s) = obj.extract::<PyRef<PyInterval>>() {
        Ok(StartSpec::Box(s.0.into()))
    } else if let Ok(pairs) = obj.extract::<Vec<(f64, f64)>>() {
        Ok(StartSpec::Box(BoxSpec::PerCoordinate(pairs)))
    } else {
        Err(PyTypeError::new_err(format!(
            "start must be hrla.Gaussian, hrla.Point or hrla.Interval, got {}",
            obj.get_type().name()?
        )))
    }
}

/// When a run ends: any of a step budget, an evaluation budget (every
/// evaluation counted, the initial points' too), a target value and a
/// stall rule; the first that holds ends it. Built by chaining, as in
/// Rust: `Stop().evaluations(125_000).target(1e-6)`.
#[pyclass(frozen, module = "hrla", name = "Stop")]
#[derive(Clone, Copy, Default)]
pub struct PyStop(pub Stop<f64>);

#[pymethods]
impl PyStop {
    #[new]
    fn new() -> Self {
        Self(Stop::new())
    }
    /// At most `k` steps.
    fn steps(&self, k: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(Self(self.0.steps(unsigned(k, "steps")?)))
    }
    /// At most `n` potential-and-gradient evaluations in all.
    fn evaluations(&self, n: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(Self(self.0.evaluations(unsigned(n, "evaluations")?)))
    }
    /// As soon as the best value is `<= target`.
    fn target(&self, target: f64) -> Self {
        Self(self.0.target(target))
    }
    /// When the best value has not fallen by more than `tolerance` over
    /// the last `window` steps.
    fn stall(&self, window: &Bound<'_, PyAny>, tolerance: f64) -> PyResult<Self> {
        Ok(Self(self.0.stall(unsigned(window, "window")?, tolerance)))
    }
    /// Whether no rule is set.
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// The L-BFGS polish's limits: at most `evaluations` evaluations; converged
/// when `max_j |dU/dx_j| <= gradient_tolerance` or when an iteration lowers
/// `U` by no more than `value_tolerance * max(1, |U|)` (defaults: 0 and
/// 4 machine epsilons, so it ends when `U` stops falling in its last bits).
#[pyclass(frozen, module = "hrla", name = "PolishSettings")]
#[derive(Clone, Copy)]
pub struct PyPolishSettings(pub PolishSettings<f64>);

#[pymethods]
impl PyPolishSettings {
    #[new]
    #[pyo3(signature = (evaluations, *, gradient_tolerance = None, value_tolerance = None))]
    fn new(
        evaluations: &Bound<'_, PyAny>,
        gradient_tolerance: Option<f64>,
        value_tolerance: Option<f64>,
    ) -> PyResult<Self> {
        let mut s = PolishSettings::new(unsigned(evaluations, "evaluations")?);
        if let Some(g) = gradient_tolerance {
            s.gradient_tolerance = g;
        }
        if let Some(v) = value_tolerance {
            s.value_tolerance = v;
        }
        Ok(Self(s))
    }
    #[getter]
    fn evaluations(&self) -> u64 {
        self.0.evaluations
    }
    #[getter]
    fn gradient_tolerance(&self) -> f64 {
        self.0.gradient_tolerance
    }
    #[getter]
    fn value_tolerance(&self) -> f64 {
        self.0.value_tolerance
    }
}

/// The outcome of a run that ended normally (a failed run raises instead).
#[pyclass(frozen, module = "hrla", name = "Report", get_all)]
#[derive(Clone)]
pub struct PyReport {
    /// The best value found.
    pub value: f64,
    /// The chain that found it.
    pub chain: usize,
    /// The iterate at which it was found.
    pub found_at: u64,
    /// Steps done.
    pub iterations: u64,
    /// Evaluations, the initial points' included.
    pub evaluations: u64,
    /// Chains that diverged.
    pub diverged_chains: usize,
    /// Chains in the run.
    pub chains: usize,
    /// Why it ended: the kernel's `Termination` variant name.
    pub termination: &'static str,
    /// The kernel's sentence for the report.
    pub message: String,
}

#[pymethods]
impl PyReport {
    fn __repr__(&self) -> String {
        format!("Report({})", self.message)
    }
    fn __str__(&self) -> String {
        self.message.clone()
    }
}

impl From<hrla::Report<f64>> for PyReport {
    fn from(r: hrla::Report<f64>) -> Self {
        Self {
            value: r.value,
            chain: r.chain,
            found_at: r.found_at,
            iterations: r.iterations,
            evaluations: r.evaluations,
            diverged_chains: r.diverged_chains,
            chains: r.chains,
            termination: termination_name(r.termination),
            message: r.to_string(),
        }
    }
}

/// What a polish or quench did.
#[pyclass(frozen, module = "hrla", name = "Polished", get_all)]
#[derive(Clone)]
pub struct PyPolished {
    /// `U` at the final point.
    pub value: f64,
    /// Evaluations used.
    pub evaluations: u64,
    /// Accepted L-BFGS steps.
    pub iterations: u64,
    /// Why it ended: `Gradient`, `Value`, `Budget` or `LineSearch`.
    pub end: &'static str,
}

#[pymethods]
impl PyPolished {
    fn __repr__(&self) -> String {
        format!(
            "Polished(value={:?}, evaluations={}, iterations={}, end={:?})",
            self.value, self.evaluations, self.iterations, self.end
        )
    }
}

impl From<hrla::Polished<f64>> for PyPolished {
    fn from(p: hrla::Polished<f64>) -> Self {
        Self {
            value: p.value,
            evaluations: p.evaluations,
            iterations: p.iterations,
            end: match p.end {
                PolishEnd::Gradient => "Gradient",
                PolishEnd::Value => "Value",
                PolishEnd::Budget => "Budget",
                PolishEnd::LineSearch => "LineSearch",
            },
        }
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyHrla>()?;
    m.add_class::<PyUla>()?;
    m.add_class::<PyOla>()?;
    m.add_class::<PyConstant>()?;
    m.add_class::<PyLinear>()?;
    m.add_class::<PyGeometric>()?;
    m.add_class::<PyInterval>()?;
    m.add_class::<PyGaussian>()?;
    m.add_class::<PyPoint>()?;
    m.add_class::<PyStop>()?;
    m.add_class::<PyPolishSettings>()?;
    m.add_class::<PyReport>()?;
    m.add_class::<PyPolished>()?;
    Ok(())
}

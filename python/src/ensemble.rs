//! The layer's gradient-free solver, [`hrla_dyn::Ensemble`], on a Python
//! function of values: `hrla.minimize`'s second phase without a gradient.

use hrla_dyn::{Ensemble, EnsembleEnd, EnsembleRules, Progress, UserError};
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::{guard, layer};
use crate::observer::{look, observer_of};
use crate::potential::real;

/// `values(X) -> U` on the rows of `points` (`n x d`), checked for shape.
fn call(
    py: Python<'_>,
    values: &Py<PyAny>,
    points: &[f64],
    d: usize,
    out: &mut [f64],
) -> PyResult<()> {
    let n = points.len() / d;
    let x = PyArray1::from_slice(py, points).reshape([n, d])?;
    let u = values.bind(py).call1((x,))?;
    let numpy = py.import("numpy")?;
    // Refused as the batch seam refuses them: booleans, complex, strings.
    let u = real(&numpy, &u, "U")?;
    let u = numpy.call_method1("ascontiguousarray", (u, "float64"))?;
    let u = u.cast_into::<numpy::PyArrayDyn<f64>>()?;
    if u.shape() != [n] {
        return Err(PyValueError::new_err(format!(
            "values must return shape ({n},), got {:?}",
            u.shape()
        )));
    }
    out.copy_from_slice(u.readonly().as_slice()?);
    Ok(())
}

/// The ensemble solver on `values(X (n, d)) -> U (n,)` in the box `[lo,
/// hi]`, with the rules of [`EnsembleRules`] (`target`, `stall`,
/// `iterations`, after `elapsed` iterations that reached `known` at
/// `known_at`): `(x, value, evaluations, generations, restarts,
/// population, end)` with `end`
/// one of `"Budget"`, `"Converged"`, `"Observer"`, `"Target"`,
/// `"Stalled"`, `"Iterations"`.
/// `observer(generation, evaluations, best[, x])` is called after each
/// generation (with `x` when `with_x`); a true answer ends the run.
/// Ctrl-C is looked for after every generation.
#[pyfunction]
#[pyo3(signature = (values, lo, hi, budget, seed, observer=None, with_x=false, target=None, stall=None, iterations=None, elapsed=0, known=f64::INFINITY, known_at=None, spread=6.0, population=2.0, cool=1.5, cool_every=10, converge=true))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn ensemble_minimize<'py>(
    py: Python<'py>,
    values: Py<PyAny>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    budget: u64,
    seed: u64,
    observer: Option<&Bound<'py, PyAny>>,
    with_x: bool,
    target: Option<f64>,
    stall: Option<(u64, f64)>,
    iterations: Option<u64>,
    elapsed: u64,
    known: f64,
    known_at: Option<Vec<f64>>,
    spread: f64,
    population: f64,
    cool: f64,
    cool_every: u32,
    converge: bool,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    f64,
    u64,
    u64,
    u32,
    usize,
    &'static str,
)> {
    guard(|| {
        let observer = observer_of(observer)?;
        let settings = Ensemble {
            spread,
            population,
            cool,
            cool_every,
            converge,
        };
        let mut stopped: Option<PyErr> = None;
        let evaluate = |points: &[f64], d: usize, out: &mut [f64]| {
            call(py, &values, points, d, out).map_err(UserError::from)
        };
        let watch = |p: &Progress<'_>| look(py, observer.as_ref(), p, with_x, &mut stopped);
        let rules = EnsembleRules {
            target,
            stall,
            iterations,
            elapsed,
            known,
            known_at: known_at.as_deref().unwrap_or(&[]),
        };
        let found = settings.minimize(&lo, &hi, budget, seed, rules, evaluate, watch);
        if let Some(e) = stopped {
            return Err(e);
        }
        let s = found.map_err(layer)?;
        let end = match s.end {
            EnsembleEnd::Budget => "Budget",
            EnsembleEnd::Converged => "Converged",
            EnsembleEnd::Observer => "Observer",
            EnsembleEnd::Target => "Target",
            EnsembleEnd::Stalled => "Stalled",
            EnsembleEnd::Iterations => "Iterations",
        };
        Ok((
            PyArray1::from_vec(py, s.x),
            s.value,
            s.evaluations,
            s.generations,
            s.restarts,
            s.population,
            end,
        ))
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(ensemble_minimize, m)?)?;
    m.add("ENSEMBLE_MAX_DIM", Ensemble::MAX_DIM)
}

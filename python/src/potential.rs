//! Potentials: the kernel's built-ins (their classes generated from the
//! layer's one list), and a user's batched Python function, which the
//! layer calls through [`hrla_dyn::BatchFunction`].

use std::sync::Arc;

use hrla_dyn::{BatchFunction, BuiltinKind, BuiltinSpec, PotentialSpec, UserError};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::errors::{guard, layer};

/// `(U, G)` for a batch of points: shapes `(N,)` and `(N, D)`.
type Batch<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>);

/// A potential of the kernel, run in Rust with no Python in the loop. The
/// subclasses are the kernel's built-ins; `value_and_gradient` evaluates
/// one on a batch of points (with the GIL released).
#[pyclass(subclass, frozen, module = "hrla", name = "Potential")]
pub struct PyBuiltin(pub BuiltinSpec);

#[pymethods]
impl PyBuiltin {
    /// `(U(X), ∇U(X))` for the rows of `X`, of shape `(N, D)`: arrays of
    /// shapes `(N,)` and `(N, D)`.
    fn value_and_gradient<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Batch<'py>> {
        guard(|| {
            let (n, d) = (x.shape()[0], x.shape()[1]);
            let points: Vec<f64> = x.as_array().iter().copied().collect();
            let (values, grads) = py.detach(|| self.0.evaluate(d, &points)).map_err(layer)?;
            let grads = PyArray1::from_vec(py, grads).reshape([n, d])?;
            Ok((PyArray1::from_vec(py, values), grads))
        })
    }

    /// The global minimum `U*` in dimension `dim`.
    fn global_minimum(&self, dim: usize) -> PyResult<f64> {
        self.0.minimum(dim).map(|m| m.0).map_err(layer)
    }

    /// A global minimiser `x*` in dimension `dim`.
    fn global_minimiser<'py>(
        &self,
        py: Python<'py>,
        dim: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (_, x) = self.0.minimum(dim).map_err(layer)?;
        Ok(PyArray1::from_vec(py, x))
    }

    fn __repr__(&self) -> String {
        self.0.to_string()
    }
}

/// One class per parameter-free built-in of the layer's list, named as
/// the kernel's type, with its description.
macro_rules! py_builtins {
    ($( $(#[$doc:meta])* $variant:ident = $name:literal ),+ $(,)?) => {
        mod builtins {
            use super::*;
            $(
                $(#[$doc])*
                #[pyclass(extends = PyBuiltin, frozen, module = "hrla")]
                pub struct $variant;

                #[pymethods]
                impl $variant {
                    #[new]
                    fn new() -> ($variant, PyBuiltin) {
                        ($variant, PyBuiltin(BuiltinSpec::Named(BuiltinKind::$variant)))
                    }
                }
            )+

            pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
                $( m.add_class::<$variant>()?; )+
                Ok(())
            }
        }
    };
}

hrla_dyn::for_each_builtin!(py_builtins);

/// The isotropic quadratic `U(x) = (k/2) |x - m|^2`, stiffness `k > 0`,
/// centre `m` (its length fixes `D`); `exp(-a U)` is `N(m, I/(a k))`.
#[pyclass(extends = PyBuiltin, frozen, module = "hrla", name = "Quadratic")]
pub struct PyQuadratic;

#[pymethods]
impl PyQuadratic {
    #[new]
    fn new(stiffness: f64, centre: Vec<f64>) -> PyResult<(Self, PyBuiltin)> {
        let spec = BuiltinSpec::Quadratic { stiffness, centre };
        // The kernel's checks, in the dimension of the centre.
        spec.check().map_err(layer)?;
        Ok((PyQuadratic, PyBuiltin(spec)))
    }
}

/// A potential argument: a built-in, or a Python callable.
pub fn from_py(obj: &Bound<'_, PyAny>) -> PyResult<PotentialSpec> {
    if let Ok(b) = obj.extract::<PyRef<PyBuiltin>>() {
        Ok(PotentialSpec::Builtin(b.0.clone()))
    } else if obj.is_callable() {
        Ok(PotentialSpec::User(Arc::new(PyFunction(
            obj.clone().unbind(),
        ))))
    } else {
        Err(PyTypeError::new_err(format!(
            "the potential must be a built-in (hrla.Rastrigin(), ...) or a callable \
             X -> (U, G) on arrays of shape (N, D), got {}",
            obj.get_type().name()?
        )))
    }
}

/// A batched Python function `X (N, D) -> (U (N,), G (N, D))`.
struct PyFunction(Py<PyAny>);

impl BatchFunction for PyFunction {
    fn evaluate(
        &self,
        points: &[f64],
        d: usize,
        values: &mut [f64],
        grads: &mut [f64],
    ) -> Result<(), UserError> {
        // An exception of the function (Ctrl-C's `KeyboardInterrupt`
        // included) is handed back as it was raised, with no second call:
        // the batch seam keeps it, makes the rest of the run's evaluations
        // no-ops, and the run ends at once with it.
        let (u, g) = Python::attach(|py| call(py, &self.0, points, d)).map_err(UserError::from)?;
        values.copy_from_slice(&u);
        grads.copy_from_slice(&g);
        Ok(())
    }
}

/// One call of a batched function on the rows of `points`: `(U, G)` as
/// flat vectors, after checking their shapes.
fn call(
    py: Python<'_>,
    function: &Py<PyAny>,
    points: &[f64],
    d: usize,
) -> PyResult<(Vec<f64>, Vec<f64>)> {
    let n = points.len() / d;
    let x = PyArray1::from_slice(py, points).reshape([n, d])?;
    let result = function.bind(py).call1((x,))?;
    let pair = |what: &str| {
        PyTypeError::new_err(format!(
            "the potential must return a pair (U, G) with U of shape ({n},) and G of shape \
             ({n}, {d}); {what}"
        ))
    };
    let (u, g): (Bound<'_, PyAny>, Bound<'_, PyAny>) = result.extract().map_err(|_| {
        pair(&format!(
            "got {}",
            result
                .get_type()
                .name()
                .map_or_else(|_| "?".into(), |s| s.to_string())
        ))
    })?;
    let numpy = py.import("numpy")?;
    let u = real(&numpy, &u, "U")?;
    let g = real(&numpy, &g, "G")?;
    let u_shape: Vec<usize> = u.getattr("shape")?.extract()?;
    let g_shape: Vec<usize> = g.getattr("shape")?.extract()?;
    if u_shape != [n] || g_shape != [n, d] {
        return Err(PyValueError::new_err(format!(
            "the potential must return U of shape ({n},) and G of shape ({n}, {d}); \
             got {u_shape:?} and {g_shape:?}"
        )));
    }
    let flat = |a: &Bound<'_, PyAny>| -> PyResult<Vec<f64>> {
        let a = numpy.call_method1("ascontiguousarray", (a, "float64"))?;
        let a = a.cast_into::<numpy::PyArrayDyn<f64>>()?;
        Ok(a.readonly().as_slice()?.to_vec())
    };
    Ok((flat(&u)?, flat(&g)?))
}

/// `v` as a numpy array of real numbers: a float or integer dtype (numpy
/// arrays, Python floats and ints, sequences of them). Booleans, complex
/// numbers, strings and objects are refused with `TypeError`: numpy would
/// turn `True` into 1, drop an imaginary part, or parse `"1.5"`, each a
/// wrong value that would pass unnoticed.
pub(crate) fn real<'py>(
    numpy: &Bound<'py, PyModule>,
    v: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let a = numpy.call_method1("asarray", (v,))?;
    let dtype = a.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    if matches!(kind.as_str(), "f" | "i" | "u") {
        Ok(a)
    } else {
        Err(PyTypeError::new_err(format!(
            "the potential's {what} must be real numbers (a float or integer array), got dtype {}",
            dtype.str()?
        )))
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyBuiltin>()?;
    builtins::register(m)?;
    m.add_class::<PyQuadratic>()?;
    // The names of the built-ins, in the layer's order, for `hrla.BUILTINS`.
    let names: Vec<&str> = BuiltinKind::ALL.iter().map(|k| k.title()).collect();
    m.add("BUILTINS", names)
}

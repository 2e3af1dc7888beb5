//! Potentials: the kernel's built-ins, and a user's batched Python
//! function.
//!
//! The kernel's optimiser evaluates `U` once per live chain, right after
//! that chain's step. A Python function is instead called once per step
//! for all live chains: before each step the engine computes every live
//! chain's next position with the same kernel step, confinement and a copy
//! of the chain's generator (so the same bits as the step itself), calls
//! the function once on the `(N, D)` array of them, and the optimiser's
//! step then reads the answers back in chain order ([`PyPotential`] in
//! batch mode, which answers a point from the batch only when it is, bit
//! for bit, the next point it was given, and checks at the end that every
//! answer was read). Outside steps (initial points excepted, which are
//! batched the same way, an infeasible one's redraws called alone) — the
//! polish, quenches, restarts, [`hrla::Auto`] — the function is called
//! with one row at a time.

use std::sync::Mutex;

use hrla::{
    Ackley, DoubleWell, KnownMinimum, Levy, Potential, Quadratic, Rastrigin, StyblinskiTang,
};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::dims::with_dim;
use crate::errors::{guard, internal, kernel};

/// A built-in potential whose dimension is not yet fixed.
#[derive(Clone, Debug)]
pub enum BuiltinSpec {
    Rastrigin,
    Quadratic { stiffness: f64, centre: Vec<f64> },
    DoubleWell,
    StyblinskiTang,
    Levy,
    Ackley,
}

impl BuiltinSpec {
    /// The dimension it fixes, if any.
    pub fn dimension(&self) -> Option<usize> {
        match self {
            Self::Quadratic { centre, .. } => Some(centre.len()),
            _ => None,
        }
    }

    pub fn build<const D: usize>(&self) -> PyResult<Builtin<D>> {
        Ok(match self {
            Self::Rastrigin => Builtin::Rastrigin(Rastrigin),
            Self::Quadratic { stiffness, centre } => {
                let centre: [f64; D] = centre.as_slice().try_into().map_err(|_| {
                    PyValueError::new_err(format!(
                        "the quadratic's centre has {} coordinates, the run {D}",
                        centre.len()
                    ))
                })?;
                Builtin::Quadratic(Quadratic::new(*stiffness, centre).map_err(kernel)?)
            }
            Self::DoubleWell => Builtin::DoubleWell(DoubleWell),
            Self::StyblinskiTang => Builtin::StyblinskiTang(StyblinskiTang),
            Self::Levy => Builtin::Levy(Levy),
            Self::Ackley => Builtin::Ackley(Ackley),
        })
    }
}

/// The kernel's built-in potentials in dimension `D`, as one type: the
/// match per evaluation is outside the loop over coordinates and
/// perfectly predicted.
#[derive(Clone, Copy, Debug)]
pub enum Builtin<const D: usize> {
    Rastrigin(Rastrigin),
    Quadratic(Quadratic<f64, D>),
    DoubleWell(DoubleWell),
    StyblinskiTang(StyblinskiTang),
    Levy(Levy),
    Ackley(Ackley),
}

impl<const D: usize> Potential<f64, D> for Builtin<D> {
    #[inline]
    fn value_and_gradient(&self, x: &[f64; D], grad: &mut [f64; D]) -> f64 {
        match self {
            Self::Rastrigin(p) => p.value_and_gradient(x, grad),
            Self::Quadratic(p) => p.value_and_gradient(x, grad),
            Self::DoubleWell(p) => p.value_and_gradient(x, grad),
            Self::StyblinskiTang(p) => p.value_and_gradient(x, grad),
            Self::Levy(p) => p.value_and_gradient(x, grad),
            Self::Ackley(p) => p.value_and_gradient(x, grad),
        }
    }
}

impl<const D: usize> Builtin<D> {
    fn minimum(&self) -> (f64, [f64; D]) {
        fn of<P: KnownMinimum<f64, D>, const D: usize>(p: &P) -> (f64, [f64; D]) {
            (p.global_minimum(), p.global_minimiser())
        }
        match self {
            Self::Rastrigin(p) => of(p),
            Self::Quadratic(p) => of(p),
            Self::DoubleWell(p) => of(p),
            Self::StyblinskiTang(p) => of(p),
            Self::Levy(p) => of(p),
            Self::Ackley(p) => of(p),
        }
    }
}

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
            let (values, grads) = with_dim!(d, D => {
                let p = self.0.build::<D>()?;
                Ok::<_, PyErr>(py.detach(|| evaluate_rows::<D>(&p, &points)))
            })?;
            let grads = PyArray1::from_vec(py, grads).reshape([n, d])?;
            Ok((PyArray1::from_vec(py, values), grads))
        })
    }

    /// The global minimum `U*` in dimension `dim`.
    fn global_minimum(&self, dim: usize) -> PyResult<f64> {
        with_dim!(dim, D => Ok(self.0.build::<D>()?.minimum().0))
    }

    /// A global minimiser `x*` in dimension `dim`.
    fn global_minimiser<'py>(
        &self,
        py: Python<'py>,
        dim: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = with_dim!(dim, D => Ok::<_, PyErr>(self.0.build::<D>()?.minimum().1.to_vec()))?;
        Ok(PyArray1::from_vec(py, x))
    }

    fn __repr__(&self) -> String {
        match &self.0 {
            BuiltinSpec::Quadratic { stiffness, centre } => {
                format!("Quadratic({stiffness}, {centre:?})")
            }
            other => format!("{other:?}()"),
        }
    }
}

fn evaluate_rows<const D: usize>(p: &Builtin<D>, points: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut values = Vec::with_capacity(points.len() / D);
    let mut grads = vec![0.0; points.len()];
    for (row, g) in points.chunks_exact(D).zip(grads.chunks_exact_mut(D)) {
        let x: &[f64; D] = row.try_into().expect("rows of D");
        let g: &mut [f64; D] = g.try_into().expect("rows of D");
        values.push(p.value_and_gradient(x, g));
    }
    (values, grads)
}

macro_rules! builtins {
    ($( $(#[$doc:meta])* $name:ident = $py:literal => $spec:expr ),+ $(,)?) => {
        $(
            $(#[$doc])*
            #[pyclass(extends = PyBuiltin, frozen, module = "hrla", name = $py)]
            pub struct $name;

            #[pymethods]
            impl $name {
                #[new]
                fn new() -> (Self, PyBuiltin) {
                    ($name, PyBuiltin($spec))
                }
            }
        )+

        fn register_builtins(m: &Bound<'_, PyModule>) -> PyResult<()> {
            $( m.add_class::<$name>()?; )+
            Ok(())
        }
    };
}

builtins! {
    /// Rastrigin in the paper's form: `U(x) = D + |x|^2 - sum_i cos(2π x_i)`,
    /// `∇U(x) = 2x + 2π sin(2π x)`; `U* = 0` at `x* = 0`.
    PyRastrigin = "Rastrigin" => BuiltinSpec::Rastrigin,
    /// The separable double well `U(x) = sum_i (x_i^2 - 1)^2`; `U* = 0` at
    /// every `x_i = ±1`.
    PyDoubleWell = "DoubleWell" => BuiltinSpec::DoubleWell,
    /// Styblinski–Tang, `U(x) = (1/2) sum_i (x_i^4 - 16 x_i^2 + 5 x_i)`;
    /// `U* ≈ -39.166 D` at `x_i ≈ -2.9035`.
    PyStyblinskiTang = "StyblinskiTang" => BuiltinSpec::StyblinskiTang,
    /// Levy's function, `w_i = 1 + (x_i - 1)/4`:
    /// `sin^2(π w_1) + sum_{i<D} (w_i - 1)^2 (1 + 10 sin^2(π w_i + 1))
    /// + (w_D - 1)^2 (1 + sin^2(2π w_D))`; `U* = 0` at `x* = 1`.
    PyLevy = "Levy" => BuiltinSpec::Levy,
    /// Ackley's function with `(20, 0.2, 2π)`; `U* = 0` at `x* = 0`.
    PyAckley = "Ackley" => BuiltinSpec::Ackley,
}

/// The isotropic quadratic `U(x) = (k/2) |x - m|^2`, stiffness `k > 0`,
/// centre `m` (its length fixes `D`); `exp(-a U)` is `N(m, I/(a k))`.
#[pyclass(extends = PyBuiltin, frozen, module = "hrla", name = "Quadratic")]
pub struct PyQuadratic;

#[pymethods]
impl PyQuadratic {
    #[new]
    fn new(stiffness: f64, centre: Vec<f64>) -> PyResult<(Self, PyBuiltin)> {
        // The kernel's checks, in the dimension of the centre.
        with_dim!(centre.len(), D => {
            BuiltinSpec::Quadratic { stiffness, centre: centre.clone() }.build::<D>().map(drop)
        })?;
        Ok((
            PyQuadratic,
            PyBuiltin(BuiltinSpec::Quadratic { stiffness, centre }),
        ))
    }
}

/// A potential argument: a built-in, or a Python callable.
pub enum PotentialSpec {
    Builtin(BuiltinSpec),
    Python(Py<PyAny>),
}

impl PotentialSpec {
    pub fn from_py(obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        if let Ok(b) = obj.extract::<PyRef<PyBuiltin>>() {
            Ok(Self::Builtin(b.0.clone()))
        } else if obj.is_callable() {
            Ok(Self::Python(obj.clone().unbind()))
        } else {
            Err(PyTypeError::new_err(format!(
                "the potential must be a built-in (hrla.Rastrigin(), ...) or a callable \
                 X -> (U, G) on arrays of shape (N, D), got {}",
                obj.get_type().name()?
            )))
        }
    }

    pub fn dimension(&self) -> Option<usize> {
        match self {
            Self::Builtin(b) => b.dimension(),
            Self::Python(_) => None,
        }
    }

    pub fn build<const D: usize>(&self, py: Python<'_>) -> PyResult<Pot<D>> {
        Ok(match self {
            Self::Builtin(b) => Pot::Builtin(b.build::<D>()?),
            Self::Python(f) => Pot::Python(PyPotential::new(f.clone_ref(py))),
        })
    }
}

/// The potential of a run: a built-in, or a Python function.
pub enum Pot<const D: usize> {
    Builtin(Builtin<D>),
    Python(PyPotential<D>),
}

impl<const D: usize> Potential<f64, D> for Pot<D> {
    #[inline]
    fn value_and_gradient(&self, x: &[f64; D], grad: &mut [f64; D]) -> f64 {
        match self {
            Self::Builtin(p) => p.value_and_gradient(x, grad),
            Self::Python(p) => p.value_and_gradient(x, grad),
        }
    }
}

/// A batched Python function `X (N, D) -> (U (N,), G (N, D))`.
pub struct PyPotential<const D: usize> {
    function: Py<PyAny>,
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    /// The batch the next evaluations read, in order.
    batch: Option<Answers>,
    /// The first failure since the last [`PyPotential::take_error`]: later
    /// evaluations return NaN without calling Python.
    error: Option<PyErr>,
}

/// The answers of one batched call, read in order.
struct Answers {
    points: Vec<f64>,
    values: Vec<f64>,
    grads: Vec<f64>,
    next: usize,
}

impl<const D: usize> PyPotential<D> {
    pub fn new(function: Py<PyAny>) -> Self {
        Self {
            function,
            state: Mutex::new(State::default()),
        }
    }

    fn state(&self) -> std::sync::MutexGuard<'_, State> {
        // A panic while the lock was held cannot leave the state invalid
        // (every field is replaced whole).
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Calls the function once on the rows of `points` (row-major,
    /// `N x D`) and keeps the answers for the next `N` evaluations, which
    /// must be at those points, in that order.
    pub fn load(&self, py: Python<'_>, points: Vec<f64>) -> PyResult<()> {
        let (values, grads) = call(py, &self.function, &points, D)?;
        self.state().batch = Some(Answers {
            points,
            values,
            grads,
            next: 0,
        });
        Ok(())
    }

    /// Whether an evaluation failed since the last [`finish`](Self::finish)
    /// (the evaluations since return NaN without calling the function).
    pub fn failed(&self) -> bool {
        self.state().error.is_some()
    }

    /// Ends batch mode, checking that every answer was read; then returns
    /// the first error of any evaluation since the last call.
    pub fn finish(&self) -> PyResult<()> {
        let mut state = self.state();
        if let Some(b) = state.batch.take()
            && b.next != b.values.len()
            && state.error.is_none()
        {
            state.error = Some(internal(&format!(
                "hrla internal error: the step read {} of the {} batched answers",
                b.next,
                b.values.len()
            )));
        }
        state.error.take().map_or(Ok(()), Err)
    }

    fn value_and_gradient(&self, x: &[f64; D], grad: &mut [f64; D]) -> f64 {
        let mut state = self.state();
        if state.error.is_some() {
            *grad = [f64::NAN; D];
            return f64::NAN;
        }
        if let Some(b) = state.batch.as_mut() {
            let row = b.next;
            let at = row * D..(row + 1) * D;
            let batched = b
                .points
                .get(at.clone())
                .is_some_and(|p| p.iter().zip(x).all(|(a, b)| a.to_bits() == b.to_bits()));
            if batched {
                b.next += 1;
                grad.copy_from_slice(&b.grads[at]);
                return b.values[row];
            }
            // A point the batch did not foresee: the redraw of an
            // infeasible initial point, which the builder evaluates
            // before the next chain's. Called alone, answered exactly.
        }
        drop(state);
        let answer = Python::attach(|py| call(py, &self.function, x, D)).map(|(v, g)| {
            grad.copy_from_slice(&g);
            v[0]
        });
        state = self.state();
        answer.unwrap_or_else(|e| {
            state.error = Some(e);
            *grad = [f64::NAN; D];
            f64::NAN
        })
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
fn real<'py>(
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
    register_builtins(m)?;
    m.add_class::<PyQuadratic>()?;
    Ok(())
}

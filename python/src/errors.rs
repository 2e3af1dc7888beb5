//! The exceptions of the package: one hierarchy under `hrla.HrlaError`.
//!
//! ```text
//! HrlaError (ValueError)           the kernel refused its input, or the run failed
//! ├── DivergedError                every chain diverged
//! ├── UnboundedBelowError          U fell below -sqrt(MAX)
//! ├── BusyError (also RuntimeError)      the optimiser is running
//! └── InternalError (also RuntimeError)  a bug in hrla (a caught panic)
//! ```
//!
//! Besides these, a storage that cannot be allocated raises `MemoryError`,
//! Ctrl-C raises `KeyboardInterrupt`, a Python potential's own exception
//! propagates, a wrong type `TypeError` and a bad shape or argument
//! `ValueError`. No call raises pyo3's `PanicException`: [`guard`] turns a
//! panic into `InternalError`.

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::create_exception;
use pyo3::exceptions::{PyMemoryError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyType};

create_exception!(
    hrla,
    HrlaError,
    PyValueError,
    "The kernel refused its input or the run failed; the message is the kernel's."
);
create_exception!(
    hrla,
    DivergedError,
    HrlaError,
    "Every chain diverged (non-finite position, potential or gradient)."
);
create_exception!(
    hrla,
    UnboundedBelowError,
    HrlaError,
    "The potential fell below -sqrt(MAX): it looks unbounded below."
);

/// `BusyError(HrlaError, RuntimeError)`, made at import.
static BUSY: PyOnceLock<Py<PyType>> = PyOnceLock::new();
/// `InternalError(HrlaError, RuntimeError)`, made at import.
static INTERNAL: PyOnceLock<Py<PyType>> = PyOnceLock::new();

const BUSY_DOC: &str = "The optimiser is running: a call from inside its potential, or from \
another thread, while `run`, `step`, `polish`, `quench` or `restart` runs. Nothing was done; \
the views (`x`, `y`, `gradient`, `best_x`, `best_value`) can always be read.";
const INTERNAL_DOC: &str = "A bug in hrla (a Rust panic, caught): the message says where. An \
optimiser it interrupted refuses every later call with this error.";

/// The Python exception for a kernel error: its `Display` text, in the
/// subclass that says what kind of failure it is.
pub fn kernel(e: hrla::Error) -> PyErr {
    let message = e.to_string();
    match e {
        hrla::Error::AllDiverged { .. } => DivergedError::new_err(message),
        hrla::Error::UnboundedBelow { .. } => UnboundedBelowError::new_err(message),
        // Only a panic poisons a run, and a panic is hrla's bug here (a
        // Python potential's errors are exceptions).
        hrla::Error::Poisoned => internal(&message),
        _ => HrlaError::new_err(message),
    }
}

/// The Python exception for an error of the run-time layer: the kernel's
/// as [`kernel`], a user function's own exception as it was raised, and
/// the layer's refusals as the kind of error each is.
pub fn layer(e: hrla_dyn::Error) -> PyErr {
    use hrla_dyn::Error;
    let message = e.to_string();
    match e {
        Error::Kernel(e) => kernel(e),
        Error::Memory { .. } => PyMemoryError::new_err(message),
        Error::User(e) => match e.downcast::<PyErr>() {
            Ok(e) => *e,
            Err(e) => internal(&format!("hrla internal error: {e}")),
        },
        Error::Internal(m) => internal(&m),
        _ => PyValueError::new_err(message),
    }
}

/// `BusyError` with `message`.
pub fn busy(message: &str) -> PyErr {
    of(&BUSY, message)
}

/// `InternalError` with `message`.
pub fn internal(message: &str) -> PyErr {
    of(&INTERNAL, message)
}

fn of(cell: &PyOnceLock<Py<PyType>>, message: &str) -> PyErr {
    Python::attach(|py| match cell.get(py) {
        Some(t) => PyErr::from_type(t.bind(py).clone(), message.to_owned()),
        // Only before the module's init has run, which no call can precede.
        None => PyRuntimeError::new_err(message.to_owned()),
    })
}

/// Runs `body`, turning a panic into `InternalError` (pyo3 would raise
/// `PanicException`, a `BaseException` that `except Exception` misses).
/// State that the panic interrupted is the caller's to fence off: the
/// optimiser's lock is poisoned by it.
pub fn guard<T>(body: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".to_owned());
        Err(internal(&format!(
            "hrla internal error: {what} (please report it)"
        )))
    })
}

/// A subclass of both `HrlaError` and `RuntimeError`, whose module is `hrla`.
fn both<'py>(py: Python<'py>, name: &str, doc: &str) -> PyResult<Py<PyType>> {
    let dict = PyDict::new(py);
    dict.set_item("__doc__", doc)?;
    dict.set_item("__module__", "hrla")?;
    let bases = (py.get_type::<HrlaError>(), py.get_type::<PyRuntimeError>());
    let t = py
        .get_type::<PyType>()
        .call1((name, bases, dict))?
        .cast_into::<PyType>()?;
    Ok(t.unbind())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("HrlaError", py.get_type::<HrlaError>())?;
    m.add("DivergedError", py.get_type::<DivergedError>())?;
    m.add("UnboundedBelowError", py.get_type::<UnboundedBelowError>())?;
    let busy = BUSY.get_or_try_init(py, || both(py, "BusyError", BUSY_DOC))?;
    m.add("BusyError", busy.bind(py))?;
    let internal = INTERNAL.get_or_try_init(py, || both(py, "InternalError", INTERNAL_DOC))?;
    m.add("InternalError", internal.bind(py))?;
    Ok(())
}

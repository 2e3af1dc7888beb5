//! Kernel errors as Python exceptions, carrying the kernel's messages.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    _hrla,
    HrlaError,
    PyValueError,
    "The kernel refused its input or the run failed; the message is the kernel's."
);
create_exception!(
    _hrla,
    DivergedError,
    HrlaError,
    "Every chain diverged (non-finite position, potential or gradient)."
);
create_exception!(
    _hrla,
    UnboundedBelowError,
    HrlaError,
    "The potential fell below -sqrt(MAX): it looks unbounded below."
);
create_exception!(
    _hrla,
    DimensionError,
    HrlaError,
    "A dimension D that the module was not compiled for."
);

/// The Python exception for a kernel error: its `Display` text, in the
/// subclass that says what kind of failure it is.
pub fn kernel(e: hrla::Error) -> PyErr {
    let message = e.to_string();
    match e {
        hrla::Error::AllDiverged { .. } => DivergedError::new_err(message),
        hrla::Error::UnboundedBelow { .. } => UnboundedBelowError::new_err(message),
        _ => HrlaError::new_err(message),
    }
}

/// The error for a `D` outside [`crate::dims::SUPPORTED`].
pub fn unsupported_dimension(d: usize) -> PyErr {
    DimensionError::new_err(format!(
        "dimension {d} is not compiled in; supported: {:?} (the kernel's D is a const generic)",
        crate::dims::SUPPORTED
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("HrlaError", py.get_type::<HrlaError>())?;
    m.add("DivergedError", py.get_type::<DivergedError>())?;
    m.add("UnboundedBelowError", py.get_type::<UnboundedBelowError>())?;
    m.add("DimensionError", py.get_type::<DimensionError>())?;
    Ok(())
}

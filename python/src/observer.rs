//! A Python caller's observer of a run and how often a run looks for
//! Ctrl-C: what the optimiser (`engine.rs`) and the default solver
//! (`auto.rs`) share.

use std::ops::ControlFlow;

use hrla_dyn::Progress;
use numpy::PyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

/// Coordinate-steps (chains x `D` per step) of a built-in potential's
/// run between two checks for a signal (Ctrl-C): a few milliseconds at
/// the kernel's 5 to 20 ns per coordinate-step. Counted in work, not
/// time, so that where a run checks never depends on the machine.
pub const SIGNAL_WORK: u64 = 1 << 18;

/// Steps between two checks for a signal, for `n` chains of dimension `d`.
pub fn signal_steps(n: usize, d: usize) -> u64 {
    (SIGNAL_WORK / (n as u64).saturating_mul(d as u64).max(1)).max(1)
}

/// A run's observer as given: `None` (or Python's `None`) for none, a
/// callable kept, anything else a `TypeError`.
pub fn observer_of(observer: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Py<PyAny>>> {
    match observer.filter(|o| !o.is_none()) {
        Some(o) if !o.is_callable() => Err(PyTypeError::new_err(format!(
            "observer must be callable, got {}",
            o.get_type().name()?
        ))),
        o => Ok(o.map(|o| o.clone().unbind())),
    }
}

/// A user's observer called on `p`: `observer(iteration, evaluations,
/// best_value)`, and the best point (copied) after them when `with_x`;
/// whether it answered true.
pub fn observe(py: Python<'_>, o: &Py<PyAny>, p: &Progress<'_>, with_x: bool) -> PyResult<bool> {
    let o = o.bind(py);
    let answer = if with_x {
        o.call1((
            p.iteration,
            p.evaluations,
            p.value,
            PyArray1::from_slice(py, p.x),
        ))?
    } else {
        o.call1((p.iteration, p.evaluations, p.value))?
    };
    answer.is_truthy()
}

/// A look at a run of the layer: Ctrl-C first, then the caller's
/// observer, if any (see [`observe`]). `Break` when either asks the run to
/// end; an exception (Ctrl-C's `KeyboardInterrupt` included) is kept in
/// `stopped` for the caller to raise once the run has returned.
pub fn look(
    py: Python<'_>,
    observer: Option<&Py<PyAny>>,
    p: &Progress<'_>,
    with_x: bool,
    stopped: &mut Option<PyErr>,
) -> ControlFlow<()> {
    let answer = py.check_signals().and_then(|()| match observer {
        Some(o) => observe(py, o, p, with_x),
        None => Ok(false),
    });
    match answer {
        Ok(false) => ControlFlow::Continue(()),
        Ok(true) => ControlFlow::Break(()),
        Err(e) => {
            *stopped = Some(e);
            ControlFlow::Break(())
        }
    }
}

//! The chains as numpy arrays that look into the optimiser's own storage.
//!
//! The optimiser keeps each field of the chains (positions, velocities,
//! gradients, best points, values, best values) as one contiguous block of
//! an array it owns and never resizes: an `(N, D)` row-major block for the
//! points, an `(N,)` block for the values. A view is that block. The views
//! are read-only and keep the optimiser alive (it is their numpy `base`);
//! every step updates them in place.
#![allow(unsafe_code)]

use hrla_dyn::Layout;
use numpy::ndarray::{ArrayView1, ArrayView2};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

/// The address of the field at `offset`.
fn at(l: &Layout, offset: usize) -> *const f64 {
    // The layer took `base` from the storage's own address (a cast that
    // exposes it), so this pointer carries the storage's provenance.
    std::ptr::with_exposed_provenance::<f64>(l.base).wrapping_add(offset)
}

/// The `(N, D)` field at `offset`, as a read-only view whose base is
/// `owner`.
pub fn rows<'py>(owner: Bound<'py, PyAny>, l: &Layout, offset: usize) -> Bound<'py, PyArray2<f64>> {
    // SAFETY: `base + offset + c * d + j` for `c < n`, `j < d` is the
    // field's coordinate `j` of chain `c`, inside the storage's
    // allocation. That allocation lives as long as `owner` (the optimiser
    // owns it and never resizes or replaces it), and `owner` is the
    // array's base, so it outlives the array.
    let array = unsafe {
        let view = ArrayView2::from_shape_ptr((l.n, l.d), at(l, offset));
        PyArray2::borrow_from_array(&view, owner)
    };
    read_only(array)
}

/// The scalar field at `offset`, `(N,)`, as [`rows`] does.
pub fn column<'py>(
    owner: Bound<'py, PyAny>,
    l: &Layout,
    offset: usize,
) -> Bound<'py, PyArray1<f64>> {
    // SAFETY: as in `rows`, with one element per chain.
    let array = unsafe {
        let view = ArrayView1::from_shape_ptr(l.n, at(l, offset));
        PyArray1::borrow_from_array(&view, owner)
    };
    read_only(array)
}

/// Writing through a view would bypass the kernel's checks: refuse it.
fn read_only<T>(array: Bound<'_, T>) -> Bound<'_, T> {
    // `setflags(write=False)` cannot fail: clearing the flag always may.
    let _ = array.as_any().call_method1("setflags", (false,));
    array
}

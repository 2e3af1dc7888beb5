//! The chains as numpy arrays that look into the optimiser's own storage.
//!
//! The kernel keeps each chain as one struct (position, velocity, gradient,
//! best point, ...) in a `Vec` that the optimiser owns and never resizes.
//! A field across all chains is then a strided array: its offset in a
//! chain, and the size of a chain as the stride between rows. The views
//! are read-only and keep the optimiser alive (it is their numpy `base`);
//! every step updates them in place.
#![allow(unsafe_code)]

use hrla_dyn::Layout;
use numpy::ndarray::{ArrayView1, ArrayView2, ShapeBuilder};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

/// The address of field `offset` of the first chain.
fn at(l: &Layout, offset: usize) -> *const f64 {
    // The layer measured `base` from the chains' own address (a cast that
    // exposes it), so this pointer carries the chains' provenance.
    std::ptr::with_exposed_provenance::<f64>(l.base).wrapping_add(offset)
}

/// The `(N, D)` field at `offset` of every chain, as a read-only view
/// whose base is `owner`.
pub fn rows<'py>(owner: Bound<'py, PyAny>, l: &Layout, offset: usize) -> Bound<'py, PyArray2<f64>> {
    // SAFETY: `base + offset + c * stride + j` for `c < n`, `j < d` is
    // field `offset`'s coordinate `j` in chain `c`, inside the chains'
    // allocation. That allocation lives as long as `owner` (the optimiser
    // owns it and never resizes or replaces it), and `owner` is the
    // array's base, so it outlives the array.
    let array = unsafe {
        let view = ArrayView2::from_shape_ptr((l.n, l.d).strides((l.stride, 1)), at(l, offset));
        PyArray2::borrow_from_array(&view, owner)
    };
    read_only(array)
}

/// The scalar field at `offset` of every chain, `(N,)`, as [`rows`] does.
pub fn column<'py>(
    owner: Bound<'py, PyAny>,
    l: &Layout,
    offset: usize,
) -> Bound<'py, PyArray1<f64>> {
    // SAFETY: as in `rows`, with one element per chain.
    let array = unsafe {
        let view = ArrayView1::from_shape_ptr((l.n,).strides((l.stride,)), at(l, offset));
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

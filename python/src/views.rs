//! The chains as numpy arrays that look into the optimiser's own storage.
//!
//! The kernel keeps each chain as one struct (position, velocity, gradient,
//! best point, ...) in a `Vec` that the optimiser owns and never resizes.
//! A field across all chains is then a strided array: its offset in a
//! chain, and the size of a chain as the stride between rows. The views
//! are read-only and keep the optimiser alive (it is their numpy `base`);
//! every step updates them in place.
#![allow(unsafe_code)]

use hrla::Chain;
use numpy::ndarray::{ArrayView1, ArrayView2, ShapeBuilder};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

/// Where the fields of the chains are, in units of `f64` from the first
/// chain's start.
pub struct Layout {
    base: *const f64,
    n: usize,
    d: usize,
    /// The size of a chain.
    stride: usize,
    pub x: usize,
    pub y: usize,
    pub gradient: usize,
    pub best_x: usize,
    pub best_value: usize,
}

// SAFETY: a `Layout` is an address and offsets, never dereferenced except
// by `rows` and `column`, whose safety rests on the owner keeping the
// chains alive, not on the thread that reads them.
unsafe impl Send for Layout {}
// SAFETY: as for `Send`: the layout itself is never written after it is made.
unsafe impl Sync for Layout {}

/// The layout of `chains`, measured from the addresses of their fields
/// (Rust does not fix a struct's field order).
pub fn layout_of<const D: usize, R>(chains: &[Chain<f64, D, R>]) -> Layout {
    let first = &chains[0];
    let start = std::ptr::from_ref(first) as usize;
    let offset = |p: *const f64| (p as usize - start) / size_of::<f64>();
    // A chain holds f64 fields, so it is aligned to (and a multiple of) 8
    // bytes, and every f64 field lies a whole number of f64s from its start.
    const { assert!(size_of::<Chain<f64, 1>>().is_multiple_of(size_of::<f64>())) };
    Layout {
        base: std::ptr::from_ref(first).cast(),
        n: chains.len(),
        d: D,
        stride: size_of::<Chain<f64, D, R>>() / size_of::<f64>(),
        x: offset(first.x().as_ptr()),
        y: offset(first.y().as_ptr()),
        gradient: offset(first.gradient().as_ptr()),
        best_x: offset(first.best().x.as_ptr()),
        best_value: offset(&first.best().value),
    }
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
        let view =
            ArrayView2::from_shape_ptr((l.n, l.d).strides((l.stride, 1)), l.base.add(offset));
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
        let view = ArrayView1::from_shape_ptr((l.n,).strides((l.stride,)), l.base.add(offset));
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

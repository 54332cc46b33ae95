//! Conversions between Python/NumPy values and the Rust types.

use harmonav_rs::Vector2;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A Rust error as a Python `ValueError` carrying its message.
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// `[x, y]` as a vector, rejecting NaN and ±inf with a message naming `what`.
pub fn point(p: [f64; 2], what: &str) -> PyResult<Vector2<f64>> {
    if p.iter().all(|c| c.is_finite()) {
        Ok(Vector2::new(p[0], p[1]))
    } else {
        Err(PyValueError::new_err(format!(
            "{what} must be two finite numbers, got [{}, {}]",
            p[0], p[1]
        )))
    }
}

/// The rows of an `(N, 2)` array (any strides), copied out so that the GIL can be released.
pub fn points(a: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<Vector2<f64>>> {
    let view = a.as_array();
    if view.ncols() != 2 {
        return Err(PyValueError::new_err(format!(
            "points must have shape (N, 2), got ({}, {})",
            view.nrows(),
            view.ncols()
        )));
    }
    Ok(view
        .rows()
        .into_iter()
        .map(|r| Vector2::new(r[0], r[1]))
        .collect())
}

/// A policy name parsed by the Rust type's `FromStr` (whose error lists the choices).
pub fn policy<T: std::str::FromStr>(name: &str) -> PyResult<T>
where
    T::Err: std::fmt::Display,
{
    name.parse().map_err(value_error)
}

/// `f(piece, rows)` over contiguous pieces of `items` and the matching rows of each output
/// (`outs[j]` holds `widths[j]` values per item), on all cores when the batch is large enough
/// to pay for the threads. Outputs shorter than `widths[j]·items.len()` get fewer rows.
pub fn parallel_rows<T: Sync, const K: usize>(
    items: &[T],
    outs: [&mut [f64]; K],
    widths: [usize; K],
    f: impl Fn(&[T], [&mut [f64]; K]) + Sync,
) {
    /// Below this many items one thread is faster than spawning more.
    const PARALLEL_MIN: usize = 4096;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    if items.len() < PARALLEL_MIN || threads == 1 {
        f(items, outs);
        return;
    }
    let per = items.len().div_ceil(threads);
    let mut rest = outs;
    std::thread::scope(|scope| {
        for piece in items.chunks(per) {
            let rows: [&mut [f64]; K] = std::array::from_fn(|j| {
                let out = std::mem::take(&mut rest[j]);
                let (head, tail) = out.split_at_mut((piece.len() * widths[j]).min(out.len()));
                rest[j] = tail;
                head
            });
            let f = &f;
            scope.spawn(move || f(piece, rows));
        }
    });
}

/// An (n, 2) array from `2n` values in row order.
pub fn rows2<'py>(
    py: Python<'py>,
    flat: Vec<f64>,
    n: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    PyArray1::from_vec(py, flat).reshape([n, 2])
}

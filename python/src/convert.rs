//! Conversions between Python/NumPy values and the Rust types, and allocation that fails
//! with `MemoryError` instead of aborting.
//!
//! **Array-likes.** An argument typed `_Points` (an (N, 2) array of points) or `_Point` (one
//! `[x, y]`) accepts whatever `numpy.asarray` turns into real numbers: lists, tuples, and
//! integer, unsigned or floating arrays of any width, cast to float64 (without a copy for a
//! float64 array). Errors name the argument: `TypeError` for values that are not real numbers
//! (strings, booleans, complex numbers, `None`) or an array with the wrong number of
//! dimensions, `ValueError` for the wrong length of a row or a ragged list.
//!
//! **Memory.** Nothing whose size the caller chooses is allocated infallibly: Rust buffers go
//! through `Vec::try_reserve_exact`, and NumPy arrays are made by `numpy.empty` (the numpy
//! crate's constructors panic when NumPy's allocation fails). A request too large raises
//! `MemoryError` naming what was being allocated; the interpreter keeps running.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

use harmonav_rs::Vector2;
use numpy::ndarray::{ArrayView2, Dimension};
use numpy::{
    Element, PyArray, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods,
    PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyMemoryError, PyTypeError, PyValueError};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

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

/// One point `[x, y]` from any array-like of two real numbers (see the module documentation),
/// finite, with errors naming `what`.
pub fn point_like(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vector2<f64>> {
    // The common case (a list or tuple of two numbers) without a trip through NumPy.
    if let Ok(p) = obj.extract::<[f64; 2]>() {
        return point(p, what);
    }
    match float64_array(obj, what)? {
        Floats::One(p) => p,
        Floats::Many(a) => match a.shape() {
            [n] => Err(PyValueError::new_err(format!(
                "{what} must be one point [x, y] (2 numbers), got {n}"
            ))),
            shape => Err(PyTypeError::new_err(format!(
                "{what} must be one point [x, y], got an array of shape {}",
                shape_text(shape)
            ))),
        },
    }
}

/// One point or an (N, 2) array of points: what `Shape.signed_distance` takes.
pub enum OneOrMany {
    /// A single finite `[x, y]`.
    One(Vector2<f64>),
    /// The rows of an (N, 2) array (rows may be non-finite).
    Many(Vec<Vector2<f64>>),
}

/// A point `[x, y]` (a sequence or a (2,) array) or an (N, 2) array-like of points; errors
/// name `what`.
pub fn point_or_points(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<OneOrMany> {
    if let Ok(p) = obj.extract::<[f64; 2]>() {
        return point(p, what).map(OneOrMany::One);
    }
    match float64_array(obj, what)? {
        Floats::One(p) => p.map(OneOrMany::One),
        Floats::Many(a) => rows_of(&a, what).map(OneOrMany::Many),
    }
}

/// The rows of an (N, 2) array-like of points (see the module documentation), copied out so
/// that the GIL can be released. Non-finite rows are kept (the callers give them NaN results).
/// An empty sequence is zero points.
pub fn points_like(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vector2<f64>>> {
    match float64_array(obj, what)? {
        Floats::One(_) => Err(PyTypeError::new_err(format!(
            "{what} must be an (N, 2) array of points, got one point of shape (2,) (use [[x, y]])"
        ))),
        Floats::Many(a) => rows_of(&a, what),
    }
}

/// What `float64_array` found: a 1-D array of length 2 read as a point (an error if it has a
/// non-finite coordinate), or any other float64 array, not yet checked.
enum Floats<'py> {
    One(PyResult<Vector2<f64>>),
    Many(Bound<'py, PyUntypedArray>),
}

/// `obj` through `numpy.asarray`, refused unless it holds real numbers, cast to float64.
fn float64_array<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Floats<'py>> {
    let py = obj.py();
    let array = match obj.cast::<PyArrayDyn<f64>>() {
        Ok(a) => a.as_untyped().clone(),
        Err(_) => {
            let numpy = py.import(intern!(py, "numpy"))?;
            let a = numpy
                .call_method1(intern!(py, "asarray"), (obj,))
                .map_err(|e| reword(py, e, what))?
                .cast_into::<PyUntypedArray>()?;
            let dtype = a.dtype();
            // Integers, unsigned integers and floats of any width; objects (Decimal,
            // Fraction, …) if each converts to a float. Not booleans, complex, text, dates.
            if !matches!(dtype.kind(), b'i' | b'u' | b'f' | b'O') {
                return Err(PyTypeError::new_err(format!(
                    "{what} must hold real numbers, got an array of dtype {dtype}"
                )));
            }
            if dtype.is_equiv_to(&numpy::dtype::<f64>(py)) {
                a
            } else {
                a.call_method1(intern!(py, "astype"), (numpy::dtype::<f64>(py),))
                    .map_err(|e| reword(py, e, what))?
                    .cast_into::<PyUntypedArray>()?
            }
        }
    };
    if array.shape() == [2] {
        let a = array.cast::<PyArray1<f64>>()?.try_readonly()?;
        let v = a.as_array();
        return Ok(Floats::One(point([v[0], v[1]], what)));
    }
    Ok(Floats::Many(array))
}

/// The rows of a float64 array that must have shape (N, 2) (or be empty).
fn rows_of(a: &Bound<'_, PyUntypedArray>, what: &str) -> PyResult<Vec<Vector2<f64>>> {
    match a.shape() {
        [0] => Ok(Vec::new()),
        [_, 2] => rows(a.cast::<PyArray2<f64>>()?.try_readonly()?.as_array(), what),
        [n, m] => Err(PyValueError::new_err(format!(
            "{what} must have shape (N, 2), got ({n}, {m})"
        ))),
        shape => Err(PyTypeError::new_err(format!(
            "{what} must be an (N, 2) array of points, got {} dimension(s), shape {}",
            shape.len(),
            shape_text(shape)
        ))),
    }
}

/// The rows of an (N, 2) view, copied into a buffer allocated fallibly.
fn rows(view: ArrayView2<'_, f64>, what: &str) -> PyResult<Vec<Vector2<f64>>> {
    if view.ncols() != 2 {
        return Err(PyValueError::new_err(format!(
            "{what} must have shape (N, 2), got ({}, {})",
            view.nrows(),
            view.ncols()
        )));
    }
    let mut out = try_vec(view.nrows(), what)?;
    out.extend(view.rows().into_iter().map(|r| Vector2::new(r[0], r[1])));
    Ok(out)
}

/// A shape as Python prints it: `(4,)`, `(3, 2, 2)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => {
            let dims: Vec<String> = shape.iter().map(ToString::to_string).collect();
            format!("({})", dims.join(", "))
        }
    }
}

/// A NumPy conversion error with `what` in front; its type is kept (`TypeError`, `ValueError`,
/// `MemoryError`), and anything else (`KeyboardInterrupt`) passes unchanged.
fn reword(py: Python<'_>, e: PyErr, what: &str) -> PyErr {
    let new = if e.is_instance_of::<PyTypeError>(py) {
        PyTypeError::new_err(format!("{what} must hold real numbers: {e}"))
    } else if e.is_instance_of::<PyValueError>(py) {
        PyValueError::new_err(format!("{what} must be an (N, 2) array or a point: {e}"))
    } else if e.is_instance_of::<PyMemoryError>(py) {
        PyMemoryError::new_err(format!("{what}: {e}"))
    } else {
        return e;
    };
    new.set_cause(py, Some(e));
    new
}

/// An empty `Vec` with room for `n` items, or `MemoryError` naming `what`.
pub fn try_vec<T>(n: usize, what: &str) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        PyMemoryError::new_err(format!(
            "{what}: cannot allocate {n} items of {} bytes ({})",
            size_of::<T>(),
            mebibytes(n.saturating_mul(size_of::<T>()))
        ))
    })?;
    Ok(v)
}

fn mebibytes(bytes: usize) -> String {
    format!("{:.1} MiB", bytes as f64 / (1024.0 * 1024.0))
}

/// A new NumPy array of `shape` (C order, contents unset: the caller writes every element), or
/// `MemoryError` naming `what`. Made by `numpy.empty`, which reports a failed allocation as
/// an exception.
pub fn empty<'py, T: Element, D: Dimension>(
    py: Python<'py>,
    shape: &[usize],
    what: &str,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    let bytes = shape
        .iter()
        .try_fold(size_of::<T>(), |acc, &d| acc.checked_mul(d))
        .filter(|&b| isize::try_from(b).is_ok());
    if bytes.is_none() {
        return Err(PyMemoryError::new_err(format!(
            "{what}: an array of shape {} is larger than the address space",
            shape_text(shape)
        )));
    }
    let numpy = py.import(intern!(py, "numpy"))?;
    let kwargs = PyDict::new(py);
    kwargs.set_item(intern!(py, "dtype"), numpy::dtype::<T>(py))?;
    let array = numpy
        .getattr(intern!(py, "empty"))?
        .call((PyTuple::new(py, shape)?,), Some(&kwargs))
        .map_err(|e| {
            if e.is_instance_of::<PyMemoryError>(py) {
                let new = PyMemoryError::new_err(format!("{what}: {e}"));
                new.set_cause(py, Some(e));
                new
            } else {
                e
            }
        })?;
    Ok(array.cast_into::<PyArray<T, D>>()?)
}

/// `values` as a new (N,) array (fallible: see [`empty`]).
pub fn array1<'py>(
    py: Python<'py>,
    values: &[f64],
    what: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let out = empty(py, &[values.len()], what)?;
    out.try_readwrite()?
        .as_slice_mut()
        .map_err(value_error)?
        .copy_from_slice(values);
    Ok(out)
}

/// A policy name parsed by the Rust type's `FromStr` (whose error lists the choices).
pub fn policy<T: std::str::FromStr>(name: &str) -> PyResult<T>
where
    T::Err: std::fmt::Display,
{
    name.parse().map_err(value_error)
}

/// A piece of `parallel_rows`'s work: items and their output rows, taken by one thread.
type Job<'a, T, O, const K: usize> = Mutex<Option<(&'a [T], [&'a mut [O]; K])>>;

/// `f(piece, rows)` over contiguous pieces of `items` and the matching rows of each output
/// (`outs[j]` holds `widths[j]` values per item), on all cores when the batch is large enough
/// to pay for the threads. Outputs shorter than `widths[j]·items.len()` get fewer rows.
///
/// A thread that cannot be spawned (out of memory, or of threads) leaves its piece to the
/// threads that run, this one included: it costs speed, never a panic.
pub fn parallel_rows<T: Sync, O: Send, const K: usize>(
    items: &[T],
    outs: [&mut [O]; K],
    widths: [usize; K],
    f: impl Fn(&[T], [&mut [O]; K]) + Sync,
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
    // One job per piece. Each job is claimed once through `next`; the mutex only moves it out.
    let jobs: Vec<Job<'_, T, O, K>> = items
        .chunks(per)
        .map(|piece| {
            let rows: [&mut [O]; K] = std::array::from_fn(|j| {
                let out = std::mem::take(&mut rest[j]);
                let (head, tail) = out.split_at_mut((piece.len() * widths[j]).min(out.len()));
                rest[j] = tail;
                head
            });
            Mutex::new(Some((piece, rows)))
        })
        .collect();
    let next = AtomicUsize::new(0);
    let work = || {
        while let Some(job) = jobs.get(next.fetch_add(1, Ordering::Relaxed)) {
            let taken = job.lock().unwrap_or_else(PoisonError::into_inner).take();
            if let Some((piece, rows)) = taken {
                f(piece, rows);
            }
        }
    };
    std::thread::scope(|scope| {
        for _ in 1..jobs.len() {
            // Ignoring a failed spawn is the point: the remaining workers take its job.
            let _ = std::thread::Builder::new().spawn_scoped(scope, work);
        }
        work();
    });
}

/// An (n, 2) array from `2n` values in row order (fallible: see [`empty`]).
pub fn rows2<'py>(
    py: Python<'py>,
    flat: Vec<f64>,
    n: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    if flat.len() != 2 * n {
        return Err(value_error(format!(
            "internal: {} values for an ({n}, 2) array",
            flat.len()
        )));
    }
    let out = empty(py, &[n, 2], "an (n, 2) array")?;
    out.try_readwrite()?
        .as_slice_mut()
        .map_err(value_error)?
        .copy_from_slice(&flat);
    Ok(out)
}

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
//!
//! **Messages.** Errors built from Rust messages have their control characters escaped
//! ([`escape`]); integer arguments of any size are refused by name ([`integer`]).
//!
//! **Threads and signals.** A navigator's state sits behind a mutex taken without blocking
//! while attached to Python ([`lock`]); a long run polls Python's signal handlers and stops
//! at Ctrl-C ([`detach_interruptible`]).

use std::borrow::Cow;
use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use harmonav_rs::Vector2;
use numpy::ndarray::{ArrayView2, Dimension};
use numpy::{
    Element, PyArray, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods,
    PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyMemoryError, PyOverflowError, PyTypeError, PyValueError};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::sync::MutexExt;
use pyo3::types::{PyDict, PyInt, PyTuple};

/// A Rust error as a Python `ValueError` carrying its message, control characters escaped
/// ([`escape`]: the message may quote a path or a file's content).
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(escape(&e.to_string()).into_owned())
}

/// Bidirectional-formatting characters (embeddings, overrides, isolates): text after them can
/// be shown in another order than it is (CVE-2021-42574, "Trojan Source").
fn reorders(c: char) -> bool {
    matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// `text` with every control character (C0, DEL, C1: `char::is_control`) and bidirectional
/// formatting character escaped, so that an error message printed to a terminal shows them as
/// text and cannot act on it (an ESC sequence retitling or clearing it). The characters are
/// those the CLI escapes (`harmonav-cli`'s `text::escape`), written as Python's `repr` writes
/// them: `\x1b`, `\x07`, `\n`, `\r`, `\t`, `\x9b`, `\u202e`. Other text (`Θ`, accents,
/// backslashes) is unchanged.
pub fn escape(text: &str) -> Cow<'_, str> {
    let special = |c: char| c.is_control() || reorders(c);
    if !text.chars().any(special) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if special(c) => {
                let n = u32::from(c);
                // Writing to a String cannot fail.
                let _ = if n < 0x100 {
                    write!(out, "\\x{n:02x}")
                } else {
                    write!(out, "\\u{n:04x}")
                };
            }
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// The Python integer `obj` (the argument `name`) as a `T`, with every refusal naming it:
/// `TypeError` for a value that is not an integer (a float, a string, a bool is an integer
/// to Python and accepted as 0 or 1), `ValueError` for one outside `T`'s range, with `expected`
/// (what the argument must be) and the value. (pyo3's own conversion gives an
/// `OverflowError` that names nothing.)
pub fn integer<'py, T>(obj: &Bound<'py, PyAny>, name: &str, expected: &str) -> PyResult<T>
where
    T: for<'a> FromPyObject<'a, 'py>,
    for<'a> <T as FromPyObject<'a, 'py>>::Error: Into<PyErr>,
{
    let py = obj.py();
    if !obj.is_instance_of::<PyInt>() {
        // `operator.index` accepts NumPy integers and whatever defines `__index__`.
        let index = py
            .import(intern!(py, "operator"))?
            .call_method1(intern!(py, "index"), (obj,))
            .map_err(|e| {
                let new = PyTypeError::new_err(format!(
                    "`{name}` must be an integer, got {}",
                    type_name(obj)
                ));
                new.set_cause(py, Some(e));
                new
            })?;
        return integer(&index, name, expected);
    }
    match obj.extract::<T>() {
        Ok(v) => Ok(v),
        Err(e) => {
            let e: PyErr = e.into();
            if !e.is_instance_of::<PyOverflowError>(py) {
                return Err(e);
            }
            Err(PyValueError::new_err(format!(
                "`{name}` must be {expected}, got {}",
                int_text(obj)
            )))
        }
    }
}

/// The type name of `obj`, for a message.
fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type().name().map_or_else(
        |_| "an object".to_owned(),
        |n| escape(&n.to_string()).into_owned(),
    )
}

/// A Python integer for a message: its digits up to 96 bits, else in floating point (`1e30`),
/// or its sign and size as a power of two beyond the floats (`2^1328`).
fn int_text(obj: &Bound<'_, PyAny>) -> String {
    let bits: u64 = obj
        .call_method0("bit_length")
        .and_then(|b| b.extract())
        .unwrap_or(u64::MAX);
    if bits <= 96
        && let Ok(s) = obj.str()
    {
        return s.to_string();
    }
    match obj.extract::<f64>() {
        Ok(v) => format!("{v:e}"),
        Err(_) => {
            let sign = if obj.lt(0).unwrap_or(false) { "-" } else { "" };
            format!("{sign}2^{}", bits.saturating_sub(1))
        }
    }
}

/// The state behind `m`, locked without ever blocking while attached to Python: if another
/// thread holds it (a scan running without the GIL), this one detaches while it waits, so the
/// holder can take the GIL back to finish. A lock poisoned by a panic is taken as it is (every
/// navigator call builds its new state before it stores it).
///
/// The callers lock only around Rust work: they convert their arguments before and build
/// their Python results after, so that no Python code (which could call back into the same
/// object) runs while the lock is held.
pub fn lock<'a, T>(py: Python<'_>, m: &'a Mutex<T>) -> MutexGuard<'a, T> {
    m.lock_py_attached(py)
        .unwrap_or_else(PoisonError::into_inner)
}

/// What unwinds a computation stopped by a signal: the exception its handler raised.
struct Interrupted(PyErr);

/// The signal check of a computation running without the GIL ([`detach_interruptible`]).
pub struct SignalPoll {
    last: Instant,
}

impl SignalPoll {
    /// How often the signal handlers are run: a Ctrl-C stops the computation this soon.
    const EVERY: Duration = Duration::from_millis(50);

    /// Runs Python's signal handlers (with the GIL, on the main thread), at most every
    /// [`SignalPoll::EVERY`]; if one raises (`KeyboardInterrupt` for Ctrl-C), the computation
    /// is unwound to [`detach_interruptible`], dropping what it holds on the way (an output
    /// set's staging folder is then removed).
    pub fn check(&mut self) {
        if self.last.elapsed() < Self::EVERY {
            return;
        }
        self.last = Instant::now();
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            // Not a panic: `resume_unwind` runs no panic hook (nothing is printed).
            resume_unwind(Box::new(Interrupted(e)));
        }
    }
}

/// `f` run without the GIL, interruptible: `f` calls [`SignalPoll::check`] as it goes (a
/// simulation's observer does, at every event), and a signal handler that raises stops it by
/// unwinding, whose exception is returned. Any other panic goes on unwinding (pyo3 turns it into
/// `PanicException`).
pub fn detach_interruptible<T: Send>(
    py: Python<'_>,
    f: impl FnOnce(&mut SignalPoll) -> T + Send,
) -> PyResult<T> {
    let run = py.detach(|| {
        let mut poll = SignalPoll {
            last: Instant::now(),
        };
        catch_unwind(AssertUnwindSafe(|| f(&mut poll)))
    });
    match run {
        Ok(value) => Ok(value),
        Err(payload) => match payload.downcast::<Interrupted>() {
            Ok(interrupted) => Err(interrupted.0),
            Err(other) => resume_unwind(other),
        },
    }
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

/// `obj` through [`real_array`], a (2,) array read as a point.
fn float64_array<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Floats<'py>> {
    let array = real_array(obj, what, "an (N, 2) array or a point")?;
    if array.shape() == [2] {
        let a = array.cast::<PyArray1<f64>>()?.try_readonly()?;
        let v = a.as_array();
        return Ok(Floats::One(point([v[0], v[1]], what)));
    }
    Ok(Floats::Many(array))
}

/// `obj` through `numpy.asarray`, refused unless it holds real numbers, cast to float64 (not
/// copied if it is a float64 array). Errors name `what`; a ragged list is "not `expected`".
fn real_array<'py>(
    obj: &Bound<'py, PyAny>,
    what: &str,
    expected: &str,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = obj.py();
    if let Ok(a) = obj.cast::<PyArrayDyn<f64>>() {
        return Ok(a.as_untyped().clone());
    }
    let numpy = py.import(intern!(py, "numpy"))?;
    let a = numpy
        .call_method1(intern!(py, "asarray"), (obj,))
        .map_err(|e| reword(py, e, what, expected))?
        .cast_into::<PyUntypedArray>()?;
    let dtype = a.dtype();
    // Integers, unsigned integers and floats of any width; objects (Decimal, Fraction, …) if
    // each converts to a float. Not booleans, complex, text, dates.
    if !matches!(dtype.kind(), b'i' | b'u' | b'f' | b'O') {
        return Err(PyTypeError::new_err(format!(
            "{what} must hold real numbers, got an array of dtype {dtype}"
        )));
    }
    if dtype.is_equiv_to(&numpy::dtype::<f64>(py)) {
        Ok(a)
    } else {
        Ok(
            a.call_method1(intern!(py, "astype"), (numpy::dtype::<f64>(py),))
                .map_err(|e| reword(py, e, what, expected))?
                .cast_into::<PyUntypedArray>()?,
        )
    }
}

/// The values of a 1-D array-like of real numbers (a scan's `ranges`: a list, a tuple, a
/// NumPy array of integers or floats of any width), copied out so that the GIL can be
/// released; NaN and ±inf are kept. Booleans, complex numbers and text are refused by dtype
/// (`TypeError` naming `what`), as for points.
pub fn reals_like(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let array = real_array(obj, what, "a 1-D array of numbers")?;
    match array.shape() {
        [n] => {
            let a = array.cast::<PyArray1<f64>>()?.try_readonly()?;
            let mut out = try_vec(*n, what)?;
            out.extend(a.as_array().iter().copied());
            Ok(out)
        }
        shape => Err(PyTypeError::new_err(format!(
            "{what} must be a 1-D array of numbers, got {} dimension(s), shape {}",
            shape.len(),
            shape_text(shape)
        ))),
    }
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
fn reword(py: Python<'_>, e: PyErr, what: &str, expected: &str) -> PyErr {
    let new = if e.is_instance_of::<PyTypeError>(py) {
        PyTypeError::new_err(format!("{what} must hold real numbers: {e}"))
    } else if e.is_instance_of::<PyValueError>(py) {
        PyValueError::new_err(format!("{what} must be {expected}: {e}"))
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

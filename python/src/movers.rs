//! Movers (issue 54): `harmonav.Mover`, a disc reported with a position error and a speed
//! bound, what `Navigator.set_movers` takes; and `harmonav.MoverFilter`, the standalone
//! certified filter behind any planner's velocity. The maths is the Rust `harmonav::movers`.

use std::sync::Mutex;

use harmonav_rs::{Mover as RsMover, MoverFilter as RsMoverFilter, MoverKind, NavError, Vector2};
use numpy::PyArray1;
use pyo3::exceptions::{PyKeyError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{array1, lock, point_like, value_error};

/// The names of `Mover`'s arguments, in order (a dict given to `set_movers` has these keys).
const FIELDS: [&str; 7] = [
    "centre",
    "radius",
    "speed_bound",
    "error",
    "kind",
    "share",
    "velocity",
];

/// A moving disc as perception reports it: `centre` (m, array-like `[x, y]`), the body's
/// `radius` (m, not grown), `speed_bound` (m/s: its speed never exceeds it), `error` (m: the
/// report is within it of the true centre) and `kind`: `"noncooperative"` (a person, a robot of
/// another stack: the robot keeps out of all it can reach) or `"reciprocal"` (another harmonav
/// robot with the same filter and control period, taking `1 − share` of the avoidance; this
/// robot takes `share`, ½ by default; each robot's `error` for the other is allowed, the row
/// is robust to it, docs/movers.md eq. robust). `velocity` (m/s, array-like `[vx, vy]`, optional) is a
/// tracked velocity: the certificate never uses it; KeepRight's anticipation does (docs/movers.md
/// §7; without it a mover is anticipated as if at rest). Immutable, picklable; equal when every
/// field is.
///
/// Raises `ValueError` naming the field for a non-finite centre or velocity, a radius, speed
/// bound or error outside `[0, 1e6]`, a share outside `[0, 1]`, or an unknown kind.
#[pyclass(module = "harmonav", frozen, eq)]
#[derive(Clone, Debug, PartialEq)]
pub struct Mover {
    pub(crate) inner: RsMover,
    /// The share as given (kept for a non-cooperative mover too, which does not use it).
    share: f64,
}

impl Mover {
    /// A mover from its fields, checked (errors name `what.field`).
    fn checked(
        (centre, velocity): (Vector2<f64>, Option<Vector2<f64>>),
        (radius, speed_bound, error): (f64, f64, f64),
        kind: &str,
        share: f64,
        what: &str,
    ) -> PyResult<Self> {
        let inner = RsMover {
            velocity,
            ..RsMover::new(centre, radius, speed_bound).with_error(error)
        };
        let inner = match kind {
            "noncooperative" => inner,
            "reciprocal" => inner.reciprocal(share),
            other => {
                return Err(value_error(format!(
                    "{what}.kind: unknown kind \"{other}\": expected \"noncooperative\" or \
                     \"reciprocal\""
                )));
            }
        };
        // The share is checked for either kind: a NaN left in it is a mistake.
        inner
            .reciprocal(share)
            .validate(0)
            .map_err(|e| renamed(e, what))?;
        Ok(Self { inner, share })
    }

    /// From the Rust mover (`movers`): a non-cooperative one's share is the default.
    pub(crate) fn from_rs(inner: RsMover) -> Self {
        let share = match inner.kind {
            MoverKind::Reciprocal { share } => share,
            _ => 0.5,
        };
        Self { inner, share }
    }

    fn kind_str(&self) -> &'static str {
        match self.inner.kind {
            MoverKind::Reciprocal { .. } => "reciprocal",
            _ => "noncooperative",
        }
    }
}

/// A `NavError::InvalidMover` (index 0) reworded to name `what` instead of `movers[0]`.
fn renamed(e: NavError, what: &str) -> PyErr {
    let text = e.to_string();
    value_error(match text.strip_prefix("movers[0]") {
        Some(rest) => format!("{what}{rest}"),
        None => text,
    })
}

/// Mover `i` of a list given to `set_movers` or `MoverFilter.filter`: a `Mover`, or a dict
/// with `Mover`'s argument names as keys (`centre`, `radius`, `speed_bound` required). A dict's
/// values are checked as the constructor checks them, its errors naming `movers[i].field`.
pub(crate) fn mover_from(obj: &Bound<'_, PyAny>, i: usize) -> PyResult<RsMover> {
    if let Ok(m) = obj.cast::<Mover>() {
        return Ok(m.get().inner);
    }
    let what = format!("movers[{i}]");
    let Ok(d) = obj.cast::<PyDict>() else {
        return Err(PyTypeError::new_err(format!(
            "{what} must be a harmonav.Mover or a dict with its arguments as keys, got {}",
            obj.get_type().name()?
        )));
    };
    for key in d.keys() {
        let key: String = key.extract()?;
        if !FIELDS.contains(&key.as_str()) {
            return Err(PyTypeError::new_err(format!(
                "{what}: unexpected key '{key}' (expected {})",
                FIELDS.join(", ")
            )));
        }
    }
    let required = |name: &str| -> PyResult<Bound<'_, PyAny>> {
        d.get_item(name)?
            .ok_or_else(|| PyKeyError::new_err(format!("{what}.{name} is required")))
    };
    let real = |name: &str, default: Option<f64>| -> PyResult<f64> {
        match (d.get_item(name)?, default) {
            (Some(v), _) => v.extract::<f64>().map_err(|e| {
                PyTypeError::new_err(format!("{what}.{name} must be a real number: {e}"))
            }),
            (None, Some(v)) => Ok(v),
            (None, None) => Err(PyKeyError::new_err(format!("{what}.{name} is required"))),
        }
    };
    let centre = point_like(&required("centre")?, &format!("{what}.centre"))?;
    let kind = match d.get_item("kind")? {
        Some(k) => k
            .extract::<String>()
            .map_err(|e| PyTypeError::new_err(format!("{what}.kind must be a string: {e}")))?,
        None => "noncooperative".to_owned(),
    };
    let velocity = match d.get_item("velocity")? {
        Some(v) if !v.is_none() => Some(point_like(&v, &format!("{what}.velocity"))?),
        _ => None,
    };
    let m = Mover::checked(
        (centre, velocity),
        (
            real("radius", None)?,
            real("speed_bound", None)?,
            real("error", Some(0.0))?,
        ),
        &kind,
        real("share", Some(0.5))?,
        &what,
    )?;
    Ok(m.inner)
}

/// The movers of an iterable of `Mover`s or dicts (see [`mover_from`]).
pub(crate) fn movers_from(movers: &Bound<'_, PyAny>) -> PyResult<Vec<RsMover>> {
    if movers.is_instance_of::<PyDict>() || movers.cast::<Mover>().is_ok() {
        return Err(PyTypeError::new_err(
            "movers must be a list of harmonav.Mover (or of dicts), not one mover",
        ));
    }
    let items = movers
        .try_iter()
        .map_err(|e| PyTypeError::new_err(format!("movers must be a list: {e}")))?;
    items.enumerate().map(|(i, m)| mover_from(&m?, i)).collect()
}

#[pymethods]
impl Mover {
    #[new]
    #[pyo3(signature = (centre, radius, speed_bound, error=0.0, kind="noncooperative", share=0.5,
                        velocity=None))]
    fn new(
        centre: &Bound<'_, PyAny>,
        radius: f64,
        speed_bound: f64,
        error: f64,
        kind: &str,
        share: f64,
        velocity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let centre = point_like(centre, "Mover.centre")?;
        let velocity = match velocity {
            Some(v) if !v.is_none() => Some(point_like(v, "Mover.velocity")?),
            _ => None,
        };
        Self::checked(
            (centre, velocity),
            (radius, speed_bound, error),
            kind,
            share,
            "Mover",
        )
    }

    /// The reported centre, m, a (2,) array.
    #[getter]
    fn centre<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let c = self.inner.centre;
        array1(py, &[c.x, c.y], "centre")
    }

    /// The tracked velocity, m/s, a (2,) array, or `None`.
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        self.inner
            .velocity
            .map(|v| array1(py, &[v.x, v.y], "velocity"))
            .transpose()
    }

    /// The body's radius (not grown), m.
    #[getter]
    fn radius(&self) -> f64 {
        self.inner.radius
    }

    /// The bound on its speed, m/s.
    #[getter]
    fn speed_bound(&self) -> f64 {
        self.inner.speed_bound
    }

    /// The bound on the report's position error, m.
    #[getter]
    fn error(&self) -> f64 {
        self.inner.position_error
    }

    /// `"noncooperative"` or `"reciprocal"`.
    #[getter]
    fn kind(&self) -> &'static str {
        self.kind_str()
    }

    /// This robot's share of the avoidance of a reciprocal mover (unused for a
    /// non-cooperative one).
    #[getter]
    fn share(&self) -> f64 {
        self.share
    }

    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let m = slf.get();
        let c = m.inner.centre;
        let args = (
            [c.x, c.y],
            m.inner.radius,
            m.inner.speed_bound,
            m.inner.position_error,
            m.kind_str(),
            m.share,
            m.inner.velocity.map(|v| [v.x, v.y]),
        )
            .into_pyobject(py)?;
        Ok((slf.get_type().into_any(), args))
    }

    fn __repr__(&self) -> String {
        let c = self.inner.centre;
        let share = match self.inner.kind {
            MoverKind::Reciprocal { share } => format!(", share={share:?}"),
            _ => String::new(),
        };
        let velocity = self.inner.velocity.map_or(String::new(), |v| {
            format!(", velocity=[{:?}, {:?}]", v.x, v.y)
        });
        format!(
            "Mover(centre=[{:?}, {:?}], radius={:?}, speed_bound={:?}, error={:?}, kind='{}'{share}{velocity})",
            c.x,
            c.y,
            self.inner.radius,
            self.inner.speed_bound,
            self.inner.position_error,
            self.kind_str()
        )
    }

    /// Movers are immutable: the copy is the same object.
    fn __copy__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    fn __deepcopy__(slf: Py<Self>, _memo: &Bound<'_, PyAny>) -> Py<Self> {
        slf
    }
}

/// The standalone certified mover filter (issue 54): certifies any planner's velocity (ORCA's,
/// DWB's, your own) against movers, for a disc robot of `radius` and `margin` (m) that holds
/// the velocity for `control_period` (s) and moves at most `v_max` (m/s). Raises `ValueError`
/// naming an argument that is not finite or out of range.
///
/// `filter(x, nominal, movers, clearance=inf)` returns `(velocity, mode)`: the nominal
/// velocity (clipped to `|u| ≤ min(v_max, clearance/(2h))`, mode `"capped"` if it was, else
/// `"law"`) when it keeps out of every place a mover can reach within the period; else the
/// closest certified velocity (`"yielding"`); else the least violation, not certified
/// (`"overwhelmed"`). `clearance` is the caller's certified distance from the robot's centre
/// to the static world grown by `radius + margin`.
#[pyclass(module = "harmonav", frozen)]
pub struct MoverFilter {
    filter: Mutex<RsMoverFilter>,
    args: (f64, f64, f64, f64),
}

#[pymethods]
impl MoverFilter {
    #[new]
    fn new(radius: f64, margin: f64, v_max: f64, control_period: f64) -> PyResult<Self> {
        let filter =
            RsMoverFilter::new(radius, margin, v_max, control_period).map_err(value_error)?;
        Ok(Self {
            filter: Mutex::new(filter),
            args: (radius, margin, v_max, control_period),
        })
    }

    /// The velocity to hold at `x` instead of `nominal` (each array-like `[x, y]`) against
    /// `movers` (a list of `Mover` or dicts), and its mode. Raises `ValueError` for non-finite
    /// input, an invalid mover (naming `movers[i].field`) or a mover whose reported body
    /// overlaps the robot's.
    #[pyo3(signature = (x, nominal, movers, clearance=f64::INFINITY))]
    fn filter<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        nominal: &Bound<'py, PyAny>,
        movers: &Bound<'py, PyAny>,
        clearance: f64,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, &'static str)> {
        let x = point_like(x, "x")?;
        let nominal = point_like(nominal, "nominal")?;
        let movers = movers_from(movers)?;
        let f = lock(py, &self.filter)
            .filter(x, nominal, &movers, clearance)
            .map_err(value_error)?;
        Ok((
            array1(py, &[f.velocity.x, f.velocity.y], "velocity")?,
            f.mode.as_str(),
        ))
    }

    #[getter]
    fn radius(&self) -> f64 {
        self.args.0
    }

    #[getter]
    fn margin(&self) -> f64 {
        self.args.1
    }

    #[getter]
    fn v_max(&self) -> f64 {
        self.args.2
    }

    #[getter]
    fn control_period(&self) -> f64 {
        self.args.3
    }

    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let args = slf.get().args.into_pyobject(slf.py())?;
        Ok((slf.get_type().into_any(), args))
    }

    fn __repr__(&self) -> String {
        let (r, m, v, h) = self.args;
        format!("MoverFilter(radius={r:?}, margin={m:?}, v_max={v:?}, control_period={h:?})")
    }
}

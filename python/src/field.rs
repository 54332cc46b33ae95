//! `Θ = σ∘φ_k∘Φ` with every given obstacle known, evaluated in batches.

use std::sync::Arc;

use harmonav_rs::KPolicy;
use harmonav_rs::field::{Field as RsField, FieldError};
use harmonav_rs::transform::Workspace;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{empty, parallel_rows, point_like, points_like, policy, value_error};
use crate::shapes::Shape;

/// Points per `Field::eval_many` call (its results live on the stack).
const BATCH: usize = 256;

/// `(Θ (N,), ∇Θ (N, 2))` of a batch evaluation.
type ThetaAndGradient<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>);

/// The navigation function `Θ(x) = σ(φ_k(Φ(x)))` (eq. `phiseq`) of a workspace whose every
/// obstacle is known: `boundary` and `obstacles` are `Shape`s, `goal` the destination `x_d`.
/// `k` is the policy `"auto"` (the default, `k = max(6(M + 1), 2·layer_ratio)`, docs/maths.md §8) or `"paper"` (`k = M + 1`).
/// `margin` (m) grows the obstacles and shrinks the boundary, as a robot radius does.
///
/// Immutable: `copy.copy` and `copy.deepcopy` return the same object; pickle rebuilds it from
/// the constructor's arguments (or, for `Scenario.field()`, from the pickled scenario).
#[pyclass(module = "harmonav", frozen)]
pub struct Field {
    inner: RsField,
    /// How it was made (what pickle rebuilds it from).
    origin: Origin,
}

/// How a `Field` was made.
enum Origin {
    /// `Field(boundary, obstacles, goal, k, margin)`.
    Args {
        boundary: Box<Shape>,
        obstacles: Vec<Shape>,
        goal: [f64; 2],
        k: String,
        margin: f64,
    },
    /// `scenario.field()` (the `Scenario` object, held untyped: this module does not name the
    /// scenario's, which names it).
    Scenario(Py<PyAny>),
}

impl Field {
    /// The field of `scenario.field()`.
    pub fn of_scenario(inner: RsField, scenario: Py<PyAny>) -> Self {
        Self {
            inner,
            origin: Origin::Scenario(scenario),
        }
    }
}

#[pymethods]
impl Field {
    #[new]
    #[pyo3(signature = (boundary, obstacles, goal, k="auto", margin=0.0))]
    fn new(
        boundary: &Shape,
        obstacles: Vec<PyRef<'_, Shape>>,
        goal: &Bound<'_, PyAny>,
        k: &str,
        margin: f64,
    ) -> PyResult<Self> {
        let (boundary_shape, k_name) = (boundary, k);
        let k: KPolicy = policy(k)?;
        if !(margin.is_finite() && margin >= 0.0) {
            return Err(value_error(format!(
                "margin must be finite and ≥ 0, got {margin}"
            )));
        }
        let goal = point_like(goal, "goal")?;
        let boundary = boundary.inner.offset(-margin).map_err(value_error)?;
        let grown = obstacles
            .iter()
            .enumerate()
            .map(|(i, o)| {
                o.inner
                    .offset(margin)
                    .map_err(|e| value_error(format!("obstacles[{i}]: {e}")))
            })
            .collect::<PyResult<Vec<_>>>()?;
        let ws = Workspace::new(boundary, grown, goal).map_err(value_error)?;
        let inner = RsField::all_known_with(Arc::new(ws), k).map_err(value_error)?;
        let origin = Origin::Args {
            boundary: Box::new(boundary_shape.clone()),
            obstacles: obstacles.iter().map(|o| (**o).clone()).collect(),
            goal: [goal.x, goal.y],
            k: k_name.to_owned(),
            margin,
        };
        Ok(Self { inner, origin })
    }

    /// Pickle support: the call that made it, `Field(boundary, obstacles, goal, k, margin)` or
    /// `Scenario.field(scenario)`.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        match &self.origin {
            Origin::Args {
                boundary,
                obstacles,
                goal,
                k,
                margin,
            } => {
                let obstacles = obstacles
                    .iter()
                    .map(|o| Bound::new(py, o.clone()))
                    .collect::<PyResult<Vec<_>>>()?;
                let args = (
                    Bound::new(py, Shape::clone(boundary))?,
                    obstacles,
                    *goal,
                    k.clone(),
                    *margin,
                )
                    .into_pyobject(py)?;
                Ok((py.get_type::<Self>().into_any(), args))
            }
            Origin::Scenario(scenario) => {
                let field = scenario.bind(py).get_type().getattr("field")?;
                Ok((field, (scenario.clone_ref(py),).into_pyobject(py)?))
            }
        }
    }

    /// The same object: a field is immutable.
    fn __copy__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    /// The same object: a field is immutable (`memo` is unused).
    fn __deepcopy__(slf: Py<Self>, _memo: &Bound<'_, PyAny>) -> Py<Self> {
        slf
    }

    /// `k` of `φ_k`.
    #[getter]
    fn k(&self) -> f64 {
        self.inner.k()
    }

    /// `(theta, grad)` at each row of `points_xy`, an (N, 2) array-like: `Θ` as an (N,) array
    /// and `∇Θ` as an (N, 2) array. Rows outside the free space (inside an obstacle grown by
    /// `margin`, on or outside the boundary) and non-finite rows are NaN; `free(points_xy)` is
    /// the mask. Runs without the GIL through the batched `Field::eval_many`, on all cores for
    /// large N. Raises `MemoryError` if the copy of the points or the results cannot be
    /// allocated.
    fn eval<'py>(
        &self,
        py: Python<'py>,
        points_xy: &Bound<'py, PyAny>,
    ) -> PyResult<ThetaAndGradient<'py>> {
        // The copy first, then the results (tests/test_memory.py reaches both).
        let pts = points_like(points_xy, "points_xy")?;
        let n = pts.len();
        let theta = empty::<f64, _>(py, &[n], "theta")?;
        let grad = empty::<f64, _>(py, &[n, 2], "grad")?;
        {
            let (mut tw, mut gw) = (theta.try_readwrite()?, grad.try_readwrite()?);
            let (t, g) = (tw.as_slice_mut()?, gw.as_slice_mut()?);
            py.detach(|| {
                parallel_rows(&pts, [t, g], [1, 2], |xs, [t, g]| {
                    let mut evals = [const { Err(FieldError::Outside) }; BATCH];
                    let pieces = xs.chunks(BATCH).zip(t.chunks_mut(BATCH));
                    for ((xs, t), g) in pieces.zip(g.chunks_mut(2 * BATCH)) {
                        let evals = &mut evals[..xs.len()];
                        // The lengths are equal by construction.
                        let batch = self.inner.eval_many(xs, evals);
                        for ((e, t), g) in evals.iter().zip(t).zip(g.chunks_exact_mut(2)) {
                            (*t, g[0], g[1]) = match (&batch, e) {
                                (Ok(()), Ok(e)) => (e.value, e.gradient.x, e.gradient.y),
                                _ => (f64::NAN, f64::NAN, f64::NAN),
                            };
                        }
                    }
                })
            });
        }
        Ok((theta, grad))
    }

    /// Whether each row of `points_xy`, an (N, 2) array-like, lies in the free space (a
    /// boolean (N,) array). Raises `MemoryError` as `eval` does.
    fn free<'py>(
        &self,
        py: Python<'py>,
        points_xy: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let pts = points_like(points_xy, "points_xy")?;
        let out = empty::<bool, _>(py, &[pts.len()], "free")?;
        {
            let mut w = out.try_readwrite()?;
            let rows = w.as_slice_mut().map_err(value_error)?;
            py.detach(|| {
                parallel_rows(&pts, [rows], [1], |xs, [rows]| {
                    for (x, row) in xs.iter().zip(rows) {
                        *row = self.inner.eval(*x).is_ok();
                    }
                })
            });
        }
        Ok(out)
    }

    /// The critical points of `Θ` (theorem `isNF`): a list of dicts with `x` (a (2,) list),
    /// `kind` (`"minimum"`, `"saddle"` or `"degenerate-saddle"`) and `eigenvalues` of the
    /// Hessian (ascending, or `None` where it cannot be resolved).
    fn census<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.inner
            .census()
            .points
            .iter()
            .map(|p| {
                let d = PyDict::new(py);
                d.set_item("x", [p.x.x, p.x.y])?;
                d.set_item("kind", p.kind.as_str())?;
                d.set_item("eigenvalues", p.eigenvalues)?;
                Ok(d)
            })
            .collect()
    }

    fn __repr__(&self) -> String {
        format!(
            "Field({} obstacles, k={}, policy=\"{}\")",
            self.inner.known().len(),
            self.inner.k(),
            self.inner.k_policy()
        )
    }
}

//! Shapes: discs, ellipses, rounded polygons and Fourier stars (`harmonav::StarShape`).

use harmonav_rs::StarShape;
use numpy::{Ix1, Ix2, PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyMemoryError, PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::convert::{
    OneOrMany, array1, empty, parallel_rows, point_like, point_or_points, points_like, try_vec,
    value_error,
};

/// The highest harmonic order `n` of a Fourier star: the cap of scenario files, which the Rust
/// library is to enforce too. Past it the radius costs `n` multiplications per evaluation
/// (issue 23: `n = 4·10⁹` never returned), and no obstacle a robot meets needs it.
pub const MAX_HARMONIC: i64 = 1000;

/// The most points `Shape.outline` returns: 2²⁴ (256 MiB of float64), far beyond any plot.
/// Above it `outline` raises `MemoryError` before allocating anything (issue 23:
/// `outline(2**40)` aborted the interpreter).
pub const MAX_OUTLINE: usize = 1 << 24;

/// A star-shaped region `{c + r u : r ≤ R(θ)}`: an obstacle, or a workspace boundary.
/// Made by `circle`, `ellipse`, `polygon` or `star`. Immutable; `copy`, `deepcopy` and pickle
/// rebuild it from the arguments it was made with.
#[pyclass(module = "harmonav", frozen)]
#[derive(Clone)]
pub struct Shape {
    pub inner: StarShape,
    recipe: Recipe,
}

/// The call that made a shape: its `repr`, and what pickle stores.
#[derive(Clone, Debug)]
enum Recipe {
    Circle {
        center: [f64; 2],
        radius: f64,
    },
    Ellipse {
        center: [f64; 2],
        semi_axes: [f64; 2],
        angle_deg: f64,
    },
    Polygon {
        vertices: Vec<[f64; 2]>,
        corner_radius: f64,
    },
    Star {
        center: [f64; 2],
        radius: f64,
        harmonics: Vec<(u32, f64, f64)>,
    },
    Tabulated {
        center: [f64; 2],
        radii: Vec<f64>,
    },
}

impl Recipe {
    /// The name of the module-level function that makes the shape.
    fn function(&self) -> &'static str {
        match self {
            Self::Circle { .. } => "circle",
            Self::Ellipse { .. } => "ellipse",
            Self::Polygon { .. } => "polygon",
            Self::Star { .. } => "star",
            Self::Tabulated { .. } => "tabulated",
        }
    }

    /// The function's positional arguments.
    fn args<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        match self {
            Self::Circle { center, radius } => (*center, *radius).into_pyobject(py),
            Self::Ellipse {
                center,
                semi_axes,
                angle_deg,
            } => (*center, *semi_axes, *angle_deg).into_pyobject(py),
            Self::Polygon {
                vertices,
                corner_radius,
            } => (vertices.clone(), *corner_radius).into_pyobject(py),
            Self::Star {
                center,
                radius,
                harmonics,
            } => (*center, *radius, harmonics.clone()).into_pyobject(py),
            Self::Tabulated { center, radii } => (*center, radii.clone()).into_pyobject(py),
        }
    }
}

impl std::fmt::Display for Recipe {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Circle { center: c, radius } => {
                write!(f, "circle(center=[{}, {}], radius={radius})", c[0], c[1])
            }
            Self::Ellipse {
                center: c,
                semi_axes: s,
                angle_deg,
            } => write!(
                f,
                "ellipse(center=[{}, {}], semi_axes=[{}, {}], angle_deg={angle_deg})",
                c[0], c[1], s[0], s[1]
            ),
            Self::Polygon {
                vertices,
                corner_radius,
            } => write!(
                f,
                "polygon({} vertices, corner_radius={corner_radius})",
                vertices.len()
            ),
            Self::Star {
                center: c,
                radius,
                harmonics,
            } => write!(
                f,
                "star(center=[{}, {}], radius={radius}, {} harmonics)",
                c[0],
                c[1],
                harmonics.len()
            ),
            Self::Tabulated { center: c, radii } => write!(
                f,
                "tabulated(center=[{}, {}], {} radii)",
                c[0],
                c[1],
                radii.len()
            ),
        }
    }
}

#[pymethods]
impl Shape {
    /// The centre `c` about which the shape is star-shaped, as a (2,) array.
    #[getter]
    fn center<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let c = self.inner.centre();
        array1(py, &[c.x, c.y], "center")
    }

    /// Whether the point (any array-like `[x, y]`) lies in the closed region.
    fn contains(&self, point_xy: &Bound<'_, PyAny>) -> PyResult<bool> {
        Ok(self.inner.contains(point_like(point_xy, "point_xy")?))
    }

    /// Signed distance to the outline, negative inside: a float for one point `[x, y]`, an
    /// (N,) array for an (N, 2) array-like (NaN for a non-finite row). Raises `MemoryError`
    /// if the batch's copy or result cannot be allocated.
    fn signed_distance<'py>(
        &self,
        py: Python<'py>,
        points_xy: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let pts = match point_or_points(points_xy, "points_xy")? {
            OneOrMany::One(p) => {
                return Ok(self.inner.signed_distance(p).into_pyobject(py)?.into_any());
            }
            OneOrMany::Many(pts) => pts,
        };
        let out = empty::<f64, Ix1>(py, &[pts.len()], "signed_distance")?;
        {
            let mut w = out.try_readwrite()?;
            let rows = w.as_slice_mut().map_err(value_error)?;
            py.detach(|| {
                parallel_rows(&pts, [rows], [1], |xs, [rows]| {
                    for (p, row) in xs.iter().zip(rows) {
                        *row = if p.iter().all(|c| c.is_finite()) {
                            self.inner.signed_distance(*p)
                        } else {
                            f64::NAN
                        };
                    }
                })
            });
        }
        Ok(out.into_any())
    }

    /// `n` points evenly spaced in angle on the outline, as an (n, 2) array (for plotting).
    /// `n` is at most 2²⁴ (16 777 216); above that, or when the array cannot be allocated, it
    /// raises `MemoryError`.
    #[pyo3(signature = (n=None), text_signature = "($self, n=256)")]
    fn outline<'py>(
        &self,
        py: Python<'py>,
        n: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let default = 256_i64.into_pyobject(py)?.into_any();
        let n = n.unwrap_or(&default);
        let count = match n.extract::<i64>() {
            Ok(c) => c,
            // Beyond i64: only the sign matters for the messages below.
            Err(e) if e.is_instance_of::<PyOverflowError>(py) => {
                if n.gt(0)? {
                    i64::MAX
                } else {
                    i64::MIN
                }
            }
            Err(e) => return Err(PyTypeError::new_err(format!("n must be an integer: {e}"))),
        };
        let Ok(count) = usize::try_from(count) else {
            return Err(PyValueError::new_err(format!(
                "n must be a number of points ≥ 0, got {n}"
            )));
        };
        if count > MAX_OUTLINE {
            return Err(PyMemoryError::new_err(format!(
                "outline: n = {n} points is above the cap of {MAX_OUTLINE} (256 MiB)"
            )));
        }
        let out = empty::<f64, Ix2>(py, &[count, 2], "outline")?;
        {
            let mut w = out.try_readwrite()?;
            let flat = w.as_slice_mut().map_err(value_error)?;
            py.detach(|| {
                for (i, xy) in flat.chunks_exact_mut(2).enumerate() {
                    let p = self
                        .inner
                        .boundary_point(std::f64::consts::TAU * i as f64 / count as f64);
                    (xy[0], xy[1]) = (p.x, p.y);
                }
            });
        }
        Ok(out)
    }

    /// Pickle support: the call of `circle`, `ellipse`, `polygon` or `star` that made the
    /// shape, with its arguments (so `copy` and `deepcopy` work too).
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let module = py.import("harmonav")?;
        Ok((
            module.getattr(self.recipe.function())?,
            self.recipe.args(py)?,
        ))
    }

    /// A copy (shapes are immutable: it is equal to the original in every query).
    fn __copy__(&self) -> Self {
        self.clone()
    }

    /// A copy; `memo` is unused (a shape holds no Python objects).
    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    fn __repr__(&self) -> String {
        self.recipe.to_string()
    }
}

fn shape(inner: Result<StarShape, harmonav_rs::ShapeError>, recipe: Recipe) -> PyResult<Shape> {
    Ok(Shape {
        inner: inner.map_err(value_error)?,
        recipe,
    })
}

/// A disc of `radius` about `center`: `R(θ) = r`.
#[pyfunction]
pub fn circle(center: &Bound<'_, PyAny>, radius: f64) -> PyResult<Shape> {
    let c = point_like(center, "center")?;
    shape(
        StarShape::circle(c, radius),
        Recipe::Circle {
            center: [c.x, c.y],
            radius,
        },
    )
}

/// An ellipse with `semi_axes` `(a, b)`, the first along `angle_deg`:
/// `R(ψ) = ab/√(b² cos²ψ + a² sin²ψ)`, `ψ = θ − angle`.
#[pyfunction]
#[pyo3(signature = (center, semi_axes, angle_deg=0.0))]
pub fn ellipse(
    center: &Bound<'_, PyAny>,
    semi_axes: &Bound<'_, PyAny>,
    angle_deg: f64,
) -> PyResult<Shape> {
    let c = point_like(center, "center")?;
    let s = point_like(semi_axes, "semi_axes")?;
    shape(
        StarShape::ellipse(c, [s.x, s.y], angle_deg.to_radians()),
        Recipe::Ellipse {
            center: [c.x, c.y],
            semi_axes: [s.x, s.y],
            angle_deg,
        },
    )
}

/// A polygon (vertices as an (N, 2) array-like, N ≥ 3, star-shaped about their centroid) with
/// every corner rounded to `corner_radius`.
#[pyfunction]
pub fn polygon(vertices: &Bound<'_, PyAny>, corner_radius: f64) -> PyResult<Shape> {
    let vs = points_like(vertices, "vertices")?;
    if let Some(i) = vs.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
        return Err(PyValueError::new_err(format!(
            "vertices must be finite, got [{}, {}] at row {i}",
            vs[i].x, vs[i].y
        )));
    }
    let mut recipe = try_vec(vs.len(), "vertices")?;
    recipe.extend(vs.iter().map(|v| [v.x, v.y]));
    shape(
        StarShape::rounded_polygon(&vs, corner_radius),
        Recipe::Polygon {
            vertices: recipe,
            corner_radius,
        },
    )
}

/// A Fourier star `R(θ) = r0 + Σ (a_n cos nθ + b_n sin nθ)` with `harmonics` as `(n, a_n, b_n)`
/// triples; each order `n` is a whole number from 1 to 1000 (the cap of scenario files), and
/// `R` must stay positive.
#[pyfunction]
pub fn star(
    center: &Bound<'_, PyAny>,
    radius: f64,
    harmonics: &Bound<'_, PyAny>,
) -> PyResult<Shape> {
    let c = point_like(center, "center")?;
    let h = harmonic_triples(harmonics)?;
    shape(
        StarShape::fourier_star(c, radius, &h),
        Recipe::Star {
            center: [c.x, c.y],
            radius,
            harmonics: h,
        },
    )
}

/// A tabulated star: `radii` `R_i` (at least 8, finite, positive) at the directions
/// `θ_i = 2πi/G` about `center`, with monotone cubic cells in between (PCHIP): the form of a
/// perceived radial hull (`Navigator.perceived`).
#[pyfunction]
pub fn tabulated(center: &Bound<'_, PyAny>, radii: Vec<f64>) -> PyResult<Shape> {
    let c = point_like(center, "center")?;
    shape(
        StarShape::tabulated(c, &radii),
        Recipe::Tabulated {
            center: [c.x, c.y],
            radii,
        },
    )
}

/// A perceived shape (`Navigator.perceived`) as the `tabulated(center, radii)` or
/// `star(center, r0, harmonics)` it is.
pub(crate) fn from_perceived(p: &harmonav_rs::Perceived) -> Shape {
    let c = p.centre();
    let recipe = match (p.radii(), p.fourier()) {
        (Some(radii), _) => Recipe::Tabulated {
            center: [c.x, c.y],
            radii: radii.to_vec(),
        },
        (None, Some((radius, harmonics))) => Recipe::Star {
            center: [c.x, c.y],
            radius,
            harmonics: harmonics.to_vec(),
        },
        (None, None) => unreachable!("a perceived shape is a hull or a Fourier star"),
    };
    Shape {
        inner: p.shape().clone(),
        recipe,
    }
}

/// `harmonics` as `(n, a_n, b_n)` with `1 ≤ n ≤ MAX_HARMONIC`, each error naming its entry.
fn harmonic_triples(harmonics: &Bound<'_, PyAny>) -> PyResult<Vec<(u32, f64, f64)>> {
    let py = harmonics.py();
    let not_triples = |e: PyErr| {
        PyTypeError::new_err(format!(
            "harmonics must be a sequence of (n, a_n, b_n) triples: {e}"
        ))
    };
    let mut out = Vec::new();
    for (i, item) in harmonics.try_iter().map_err(not_triples)?.enumerate() {
        let item = item?;
        let parts: Vec<Bound<'_, PyAny>> = item
            .try_iter()
            .and_then(|it| it.take(4).collect::<PyResult<_>>())
            .map_err(|e| {
                PyTypeError::new_err(format!(
                    "harmonics[{i}] must be a triple (n, a_n, b_n): {e}"
                ))
            })?;
        let [n, a, b] = parts.as_slice() else {
            return Err(PyValueError::new_err(format!(
                "harmonics[{i}] must be a triple (n, a_n, b_n), got {} values",
                parts.len()
            )));
        };
        let order = match n.extract::<i64>() {
            Ok(order) => order,
            Err(e) if e.is_instance_of::<PyOverflowError>(py) => i64::MAX,
            Err(e) => {
                return Err(PyTypeError::new_err(format!(
                    "harmonics[{i}]: the order n must be an integer: {e}"
                )));
            }
        };
        let order = match u32::try_from(order) {
            Ok(order @ 1..) if i64::from(order) <= MAX_HARMONIC => order,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "harmonics[{i}]: the order n must be a whole number from 1 to \
                     {MAX_HARMONIC}, got {n}"
                )));
            }
        };
        let coefficient = |x: &Bound<'_, PyAny>, name: &str| {
            x.extract::<f64>().map_err(|e| {
                PyTypeError::new_err(format!("harmonics[{i}]: {name} must be a number: {e}"))
            })
        };
        out.push((order, coefficient(a, "a_n")?, coefficient(b, "b_n")?));
    }
    Ok(out)
}

//! Shapes: discs, ellipses, rounded polygons and Fourier stars (`harmonav::StarShape`).

use harmonav_rs::{StarShape, Vector2};
use numpy::{PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{parallel_rows, point, points, rows2, value_error};

/// A star-shaped region `{c + r u : r ≤ R(θ)}`: an obstacle, or a workspace boundary.
/// Made by `circle`, `ellipse`, `polygon` or `star`.
#[pyclass(module = "harmonav", frozen)]
#[derive(Clone)]
pub struct Shape {
    pub inner: StarShape,
    description: String,
}

#[pymethods]
impl Shape {
    /// The centre `c` about which the shape is star-shaped, as a (2,) array.
    #[getter]
    fn center<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let c = self.inner.centre();
        PyArray1::from_vec(py, vec![c.x, c.y])
    }

    /// Whether the point lies in the closed region.
    fn contains(&self, point_xy: [f64; 2]) -> PyResult<bool> {
        Ok(self.inner.contains(point(point_xy, "point")?))
    }

    /// Signed distance to the outline, negative inside: a float for one point `[x, y]`, an
    /// (N,) array for an (N, 2) array (NaN for a non-finite row).
    fn signed_distance<'py>(
        &self,
        py: Python<'py>,
        points_xy: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        if let Ok(p) = points_xy.extract::<[f64; 2]>() {
            let d = self.inner.signed_distance(point(p, "point")?);
            return Ok(d.into_pyobject(py)?.into_any());
        }
        let array: PyReadonlyArray2<'py, f64> = points_xy.extract()?;
        let pts = points(&array)?;
        let mut out = vec![0.0; pts.len()];
        py.detach(|| {
            parallel_rows(&pts, [&mut out], [1], |xs, [rows]| {
                for (p, row) in xs.iter().zip(rows) {
                    *row = if p.iter().all(|c| c.is_finite()) {
                        self.inner.signed_distance(*p)
                    } else {
                        f64::NAN
                    };
                }
            })
        });
        Ok(PyArray1::from_vec(py, out).into_any())
    }

    /// `n` points evenly spaced in angle on the outline, as an (n, 2) array (for plotting).
    #[pyo3(signature = (n=256))]
    fn outline<'py>(&self, py: Python<'py>, n: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = (0..n)
            .flat_map(|i| {
                let p = self
                    .inner
                    .boundary_point(std::f64::consts::TAU * i as f64 / n as f64);
                [p.x, p.y]
            })
            .collect();
        rows2(py, flat, n)
    }

    fn __repr__(&self) -> String {
        self.description.clone()
    }
}

fn shape(
    inner: Result<StarShape, harmonav_rs::ShapeError>,
    description: String,
) -> PyResult<Shape> {
    Ok(Shape {
        inner: inner.map_err(value_error)?,
        description,
    })
}

/// A disc of `radius` about `center`: `R(θ) = r`.
#[pyfunction]
pub fn circle(center: [f64; 2], radius: f64) -> PyResult<Shape> {
    let c = point(center, "center")?;
    shape(
        StarShape::circle(c, radius),
        format!("circle(center=[{}, {}], radius={radius})", c.x, c.y),
    )
}

/// An ellipse with `semi_axes` `(a, b)`, the first along `angle_deg`:
/// `R(ψ) = ab/√(b² cos²ψ + a² sin²ψ)`, `ψ = θ − angle`.
#[pyfunction]
#[pyo3(signature = (center, semi_axes, angle_deg=0.0))]
pub fn ellipse(center: [f64; 2], semi_axes: [f64; 2], angle_deg: f64) -> PyResult<Shape> {
    let c = point(center, "center")?;
    shape(
        StarShape::ellipse(c, semi_axes, angle_deg.to_radians()),
        format!(
            "ellipse(center=[{}, {}], semi_axes=[{}, {}], angle_deg={angle_deg})",
            c.x, c.y, semi_axes[0], semi_axes[1]
        ),
    )
}

/// A polygon (vertices as an (N, 2) sequence, N ≥ 3, star-shaped about their centroid) with
/// every corner rounded to `corner_radius`.
#[pyfunction]
pub fn polygon(vertices: Vec<[f64; 2]>, corner_radius: f64) -> PyResult<Shape> {
    let vs = vertices
        .iter()
        .map(|&v| point(v, "vertices"))
        .collect::<PyResult<Vec<Vector2<f64>>>>()?;
    shape(
        StarShape::rounded_polygon(&vs, corner_radius),
        format!(
            "polygon({} vertices, corner_radius={corner_radius})",
            vs.len()
        ),
    )
}

/// A Fourier star `R(θ) = r0 + Σ (a_n cos nθ + b_n sin nθ)` with `harmonics` as `(n, a_n, b_n)`
/// triples (`n ≥ 1`); `R` must stay positive.
#[pyfunction]
pub fn star(center: [f64; 2], radius: f64, harmonics: Vec<(u32, f64, f64)>) -> PyResult<Shape> {
    let c = point(center, "center")?;
    shape(
        StarShape::fourier_star(c, radius, &harmonics),
        format!(
            "star(center=[{}, {}], radius={radius}, {} harmonics)",
            c.x,
            c.y,
            harmonics.len()
        ),
    )
}

//! The online API: `harmonav::Navigator`.

use harmonav_rs::{DampingPolicy, KPolicy, Law, NavError, Navigator as RsNavigator, Options};
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::convert::{point, policy, value_error};
use crate::shapes::Shape;

/// The navigator of a robot that does not know its map: obstacles are added as its perception
/// finds them, and `command(x, v)` returns the law's command.
///
/// - `law="kinematic"`: the velocity `u = −K√(2Θ)∇Θ/|∇Θ|` (eq. `kinctrl`), `K = gain`.
/// - `law="dynamic"`: the force `f = −μ∇Ψ − λẋ` (eq. `dynctrllocal`; `Ψ = Θ` and `λ` of
///   eq. `dissipationfun` under `damping="paper"`), for a robot of mass `mass`; its speed stays
///   below `√(2μ/m)`.
///
/// `sensor=(range_m, aperture_deg)` sets `d_min` (eq. `dmin`); `radius` and `margin` (m) grow
/// every obstacle and shrink the boundary; `k` is `"auto"` or `"paper"`.
#[pyclass(module = "harmonav")]
pub struct Navigator {
    inner: RsNavigator,
}

fn nav_error(e: NavError) -> PyErr {
    value_error(e)
}

#[pymethods]
impl Navigator {
    #[new]
    #[pyo3(signature = (boundary, goal, law="kinematic", gain=1.0, mass=1.0, mu=10.0,
                        sensor=(1.0, 60.0), radius=0.0, margin=0.0, k="auto", damping="auto",
                        rho_min=0.05))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        boundary: &Shape,
        goal: [f64; 2],
        law: &str,
        gain: f64,
        mass: f64,
        mu: f64,
        sensor: (f64, f64),
        radius: f64,
        margin: f64,
        k: &str,
        damping: &str,
        rho_min: f64,
    ) -> PyResult<Self> {
        let law = match law {
            "kinematic" => Law::kinematic(gain),
            "dynamic" => Law::dynamic(mass, mu),
            other => {
                return Err(value_error(format!(
                    "unknown law \"{other}\": expected \"kinematic\" or \"dynamic\""
                )));
            }
        };
        let options = Options::default()
            .with_sensor(sensor.0, sensor.1)
            .with_robot(radius, margin)
            .with_rho_min(rho_min)
            .with_k(policy::<KPolicy>(k)?)
            .with_damping(policy::<DampingPolicy>(damping)?);
        let goal = point(goal, "goal")?;
        let inner =
            RsNavigator::new(boundary.inner.clone(), goal, law, options).map_err(nav_error)?;
        Ok(Self { inner })
    }

    /// Adds a newly sensed obstacle (its true shape; grown by `radius + margin` here) and
    /// returns its index. `k`, `Φ` and the damping state update. Raises `ValueError` (and
    /// changes nothing) if it overlaps a known obstacle, crosses the boundary, or contains the
    /// goal or the robot.
    fn add_obstacle(&mut self, shape: &Shape) -> PyResult<usize> {
        self.inner
            .add_obstacle(shape.inner.clone())
            .map_err(nav_error)
    }

    /// The command at position `x` with velocity `v` (default 0): a velocity (kinematic law)
    /// or a force (dynamic law), as a (2,) array. Raises `ValueError` (and changes nothing)
    /// for a point outside the free space or non-finite input.
    #[pyo3(signature = (x, v=None))]
    fn command<'py>(
        &mut self,
        py: Python<'py>,
        x: [f64; 2],
        v: Option<[f64; 2]>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = point(x, "x")?;
        let v = point(v.unwrap_or([0.0; 2]), "v")?;
        let c = self.inner.command(x, v).map_err(nav_error)?;
        Ok(PyArray1::from_vec(py, vec![c.x, c.y]))
    }

    /// `Θ(x)` over the known obstacles.
    fn theta(&self, x: [f64; 2]) -> PyResult<f64> {
        self.inner.theta(point(x, "x")?).map_err(nav_error)
    }

    /// `k` of `φ_k` for the obstacles known so far.
    #[getter]
    fn k(&self) -> f64 {
        self.inner.k()
    }

    /// How many obstacles are known.
    #[getter]
    fn obstacle_count(&self) -> usize {
        self.inner.obstacles().len()
    }

    /// The goal, as a (2,) array.
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let g = self.inner.goal();
        PyArray1::from_vec(py, vec![g.x, g.y])
    }

    /// `√(2μ/m)` for the dynamic law, `None` for the kinematic one.
    #[getter]
    fn speed_bound(&self) -> Option<f64> {
        self.inner.speed_bound()
    }

    fn __repr__(&self) -> String {
        format!(
            "Navigator({} obstacles known, k={})",
            self.inner.obstacles().len(),
            self.inner.k()
        )
    }
}

//! The online API on a floor plan: `harmonav::FloorNavigator`.

use std::sync::Arc;

use harmonav_rs::floorplan::MapOptions;
use harmonav_rs::{
    CentrePolicy, DampingPolicy, FloorMap, FloorNavigator as RsFloorNavigator, FloorOptions,
    HeadingPolicy, HoldPolicy, KPolicy, Law, Mode, NavError, Options, SpeedPolicy, Vector2,
};
use numpy::PyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::convert::{array1, point_like, points_like, policy, value_error};
use crate::navigator::{
    ScanUpdate, finite_theta, free_memory_count, law_named, scan_from, scan_options,
};
use crate::shapes::{Shape, from_perceived};

/// The constructor's keyword arguments shared by `FloorNavigator(...)` and
/// `FloorNavigator.from_map(...)`: the law, the robot, the policies and the scan's priors.
struct Setup {
    law: Law,
    options: Options,
    floor: FloorOptions,
}

impl Setup {
    #[allow(clippy::too_many_arguments)]
    fn new(
        law: &str,
        gain: f64,
        mass: f64,
        mu: f64,
        radius: f64,
        margin: f64,
        max_element: f64,
        centre: &str,
        k: &str,
        damping: &str,
        heading: &str,
        hold: &str,
        speed: &str,
        v_max: Option<f64>,
        control_period: Option<f64>,
        scan: (f64, f64, f64, Option<f64>, i64),
    ) -> PyResult<Self> {
        let law = law_named(law, gain, mass, mu)?;
        // The robot's size first: the floor plan is shrunk by it before the navigator checks it.
        for (field, value) in [("radius", radius), ("margin", margin)] {
            if !(value.is_finite() && (0.0..=harmonav_rs::transform::MAX_LENGTH).contains(&value)) {
                return Err(nav_error(NavError::InvalidOption { field, value }));
            }
        }
        let (range_noise, depth, growth, fit_range, free_memory) = scan;
        let free_memory = free_memory_count(free_memory)?;
        let mut options = Options::default()
            .with_robot(radius, margin)
            .with_k(policy::<KPolicy>(k)?)
            .with_damping(policy::<DampingPolicy>(damping)?)
            .with_heading(policy::<HeadingPolicy>(heading)?)
            .with_hold(policy::<HoldPolicy>(hold)?)
            .with_speed(policy::<SpeedPolicy>(speed)?)
            .with_scan(scan_options(
                range_noise,
                depth,
                growth,
                fit_range,
                free_memory,
            ));
        if let Some(h) = control_period {
            options = options.with_control_period(h);
        }
        if let Some(v) = v_max {
            options = options.with_v_max(v);
        }
        let floor = FloorOptions::new(max_element, radius + margin)
            .with_centre(policy::<CentrePolicy>(centre)?);
        Ok(Self {
            law,
            options,
            floor,
        })
    }

    /// The navigator on `floor` towards `goal`.
    fn navigator(self, floor: FloorMap, goal: Vector2<f64>) -> PyResult<FloorNavigator> {
        let inner = RsFloorNavigator::new(Arc::new(floor), goal, self.law, self.options)
            .map_err(value_error)?;
        Ok(FloorNavigator {
            inner,
            mode: Mode::Law,
        })
    }
}

/// The navigator of a robot on a floor plan (issue 25): the walls are known, a polygon with
/// holes or a ROS map_server map, and its harmonic map is solved once at construction; star
/// obstacles met on the way are added as shapes (`add_obstacle`) or perceived from range scans
/// (`observe_scan`), each without a new solve. `command(x, v)` returns the law's command, as
/// `Navigator`'s does: the velocity (`law="kinematic"`, `gain`) or the force (`law="dynamic"`,
/// `mass`, `mu`), safe to hold for `control_period`.
///
/// `FloorNavigator(outer, goal, holes=None)` takes the walls as rings of points (either
/// orientation; the outer ring need not be star-shaped); `FloorNavigator.from_map(yaml, start,
/// goal)` reads a ROS map (`speck_pixels`, `simplify` as in a floor-plan file). The robot keeps
/// `radius + margin` (m) from the walls; `max_element` (m) is the boundary elements' length and
/// the width `δ` of the boundary layer, where the discrete map is not used (`docs/maths.md`
/// §13): the robot navigates in the certified region `W_δ`, at least `max(radius + margin, δ)`
/// from the walls. `centre` (`"solve"` or `"goal"`), `heading` (`"auto"`: within 60° of `−∇Θ`
/// along the shortest path; `"paper"`: `−∇Θ`), `k`, `damping`, `hold`, `speed` and the scan's
/// priors are `Navigator`'s.
///
/// Invalid arguments raise `ValueError` naming the field (a map's error names the file); walls
/// that the robot's clearance would erase, a goal outside `W_δ`, or a map whose start and goal
/// are not connected are refused. Built from rings, the navigator has no start: a point cut off
/// from the goal by a passage narrower than the robot is not found here (a floor-plan file
/// refuses such a start). A call that raises leaves the navigator as it was.
#[pyclass(module = "harmonav")]
#[derive(Clone)]
pub struct FloorNavigator {
    inner: RsFloorNavigator,
    /// How the last command was formed.
    mode: Mode,
}

/// The rings `holes` (each an array-like of points), or a `TypeError` naming the hole.
fn rings(holes: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<Vec<Vector2<f64>>>> {
    let Some(holes) = holes else {
        return Ok(Vec::new());
    };
    let items = holes
        .try_iter()
        .map_err(|e| PyTypeError::new_err(format!("holes must be a sequence of rings: {e}")))?;
    items
        .enumerate()
        .map(|(i, ring)| points_like(&ring?, &format!("holes[{i}]")))
        .collect()
}

fn nav_error(e: NavError) -> PyErr {
    value_error(e)
}

#[pymethods]
impl FloorNavigator {
    #[new]
    #[pyo3(signature = (outer, goal, holes=None, *, law="kinematic", gain=1.0, mass=1.0,
                        mu=10.0, radius=0.0, margin=0.0, max_element=0.2, centre="solve",
                        k="auto", damping="governed", heading="auto", hold="auto",
                        speed="auto", v_max=None, control_period=None, range_noise=0.02,
                        max_obstacle_depth=1.0, growth_threshold=0.02, fit_range=None,
                        free_memory=16))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        outer: &Bound<'_, PyAny>,
        goal: &Bound<'_, PyAny>,
        holes: Option<&Bound<'_, PyAny>>,
        law: &str,
        gain: f64,
        mass: f64,
        mu: f64,
        radius: f64,
        margin: f64,
        max_element: f64,
        centre: &str,
        k: &str,
        damping: &str,
        heading: &str,
        hold: &str,
        speed: &str,
        v_max: Option<f64>,
        control_period: Option<f64>,
        range_noise: f64,
        max_obstacle_depth: f64,
        growth_threshold: f64,
        fit_range: Option<f64>,
        free_memory: i64,
    ) -> PyResult<Self> {
        let outer = points_like(outer, "outer")?;
        let holes = rings(holes)?;
        let goal = point_like(goal, "goal")?;
        let setup = Setup::new(
            law,
            gain,
            mass,
            mu,
            radius,
            margin,
            max_element,
            centre,
            k,
            damping,
            heading,
            hold,
            speed,
            v_max,
            control_period,
            (
                range_noise,
                max_obstacle_depth,
                growth_threshold,
                fit_range,
                free_memory,
            ),
        )?;
        let options = setup.floor;
        let floor = py
            .detach(|| FloorMap::new(outer, holes, &options))
            .map_err(value_error)?;
        py.detach(|| setup.navigator(floor, goal))
    }

    /// The navigator on the ROS map_server map at `yaml` (its image relative to it) for a robot
    /// going from `start` to `goal` (world coordinates): the free component holding the goal,
    /// specks of at most `speck_pixels` dropped, the outline simplified by `simplify` square
    /// pixels (`docs/maths.md` §13.1), shrunk by `radius + margin`. The other arguments are the
    /// constructor's. Raises `ValueError` naming the file and the problem: a missing or
    /// truncated image, a start or goal in a wall or unknown space or outside the image, a goal
    /// not reachable from the start, a passage narrower than the robot.
    #[staticmethod]
    #[pyo3(signature = (yaml, start, goal, *, speck_pixels=2, simplify=0.5, law="kinematic",
                        gain=1.0, mass=1.0, mu=10.0, radius=0.0, margin=0.0, max_element=0.2,
                        centre="solve", k="auto", damping="governed", heading="auto",
                        hold="auto", speed="auto", v_max=None, control_period=None,
                        range_noise=0.02, max_obstacle_depth=1.0, growth_threshold=0.02,
                        fit_range=None, free_memory=16))]
    #[allow(clippy::too_many_arguments)]
    fn from_map(
        py: Python<'_>,
        yaml: std::path::PathBuf,
        start: &Bound<'_, PyAny>,
        goal: &Bound<'_, PyAny>,
        speck_pixels: i64,
        simplify: f64,
        law: &str,
        gain: f64,
        mass: f64,
        mu: f64,
        radius: f64,
        margin: f64,
        max_element: f64,
        centre: &str,
        k: &str,
        damping: &str,
        heading: &str,
        hold: &str,
        speed: &str,
        v_max: Option<f64>,
        control_period: Option<f64>,
        range_noise: f64,
        max_obstacle_depth: f64,
        growth_threshold: f64,
        fit_range: Option<f64>,
        free_memory: i64,
    ) -> PyResult<Self> {
        let start = point_like(start, "start")?;
        let goal = point_like(goal, "goal")?;
        let setup = Setup::new(
            law,
            gain,
            mass,
            mu,
            radius,
            margin,
            max_element,
            centre,
            k,
            damping,
            heading,
            hold,
            speed,
            v_max,
            control_period,
            (
                range_noise,
                max_obstacle_depth,
                growth_threshold,
                fit_range,
                free_memory,
            ),
        )?;
        let speck_pixels = usize::try_from(speck_pixels).map_err(|_| {
            value_error(format!(
                "`speck_pixels` must be an integer ≥ 0, got {speck_pixels}"
            ))
        })?;
        // `simplify` is checked by the map (`MapError` naming it).
        let options = MapOptions {
            floor: setup.floor,
            speck_pixels,
            simplify,
        };
        let floor = py
            .detach(|| FloorMap::from_ros_map(&yaml, start, goal, &options))
            .map_err(value_error)?;
        py.detach(|| setup.navigator(floor, goal))
    }

    /// Adds a newly sensed obstacle (its true shape; grown by `radius + margin` here) and
    /// returns its index; `k` and `Θ` update without a new solve. Raises `ValueError` (and
    /// changes nothing) if it overlaps a known obstacle, contains the goal or the robot, or
    /// reaches the boundary layer.
    fn add_obstacle(&mut self, shape: &Shape) -> PyResult<usize> {
        self.inner
            .add_obstacle(shape.inner.clone())
            .map_err(nav_error)
    }

    /// The command to hold for `control_period` at `x` with velocity `v` (default 0), as a (2,)
    /// array: a velocity (kinematic law) or a force (dynamic law); `mode` then says how it was
    /// formed (`"law"`, `"capped"`, `"recovering"` out of a margin band or the boundary layer,
    /// `"escaping"` along the shortest path from a rest point of the hold). Raises `ValueError`
    /// (and changes nothing) where the robot's disc overlaps a wall or a known obstacle, or for
    /// non-finite input.
    #[pyo3(signature = (x, v=None))]
    fn command<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        v: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = point_like(x, "x")?;
        let v = v.map_or(Ok(Vector2::zeros()), |v| point_like(v, "v"))?;
        // With the GIL held (one evaluation, tens of µs): another thread may read the
        // navigator meanwhile, as with `Navigator.command`.
        let c = self.inner.command(x, v).map_err(nav_error)?;
        self.mode = c.mode;
        array1(py, &[c.value.x, c.value.y], "command")
    }

    /// Observes one range scan taken at `position` with `heading`, as `Navigator.observe_scan`
    /// does; the walls come from the map: hits on them (within the noise bound) are explained,
    /// and fits keep out of them. Returns a `ScanUpdate`. Raises `ValueError` (and changes
    /// nothing) for an invalid scan, a pose outside the walls or inside an obstacle, or when a
    /// new or grown shape would contain the robot or the goal, reach the boundary layer, or
    /// overlap another.
    #[pyo3(signature = (position, heading, ranges, angle_min, angle_increment, range_max,
                        range_min=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn observe_scan(
        &mut self,
        py: Python<'_>,
        position: &Bound<'_, PyAny>,
        heading: f64,
        ranges: &Bound<'_, PyAny>,
        angle_min: f64,
        angle_increment: f64,
        range_max: f64,
        range_min: f64,
    ) -> PyResult<ScanUpdate> {
        let (pose, scan) = scan_from(
            position,
            heading,
            ranges,
            angle_min,
            angle_increment,
            range_max,
            range_min,
        )?;
        let u = py
            .detach(|| self.inner.observe_scan(pose, &scan))
            .map_err(nav_error)?;
        Ok(ScanUpdate::from(u))
    }

    /// The perceived shapes (from scans, not grown) in the navigator's order, each a `star`
    /// with `signed_distance` and `contains`.
    #[getter]
    fn obstacles(&self) -> Vec<Shape> {
        self.inner
            .perceived()
            .map(|(_, p)| from_perceived(p))
            .collect()
    }

    /// `Θ(x)` over the walls and the known obstacles (finite; `ValueError` outside the
    /// certified region or in an obstacle).
    fn theta(&self, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        finite_theta(self.inner.theta(point_like(x, "x")?).map_err(nav_error)?)
    }

    /// The certified clearance at `x`: a lower bound on the distance to the boundary layer
    /// (`sd(x) − δ`) and to every known obstacle grown by `radius + margin`, m.
    fn clearance(&self, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        Ok(self.inner.clearance(point_like(x, "x")?))
    }

    /// The distance from `x` to the true walls (positive inside, negative in a wall), m.
    fn wall_distance(&self, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        Ok(self
            .inner
            .field()
            .floor()
            .walls()
            .signed_distance(point_like(x, "x")?))
    }

    /// `k` of `φ_k`: the holes plus the known obstacles, under the `k` policy.
    #[getter]
    fn k(&self) -> f64 {
        self.inner.k()
    }

    /// `δ`, the width of the boundary layer (m): the robot stays at least
    /// `max(radius + margin, δ)` from the walls.
    #[getter]
    fn delta(&self) -> f64 {
        self.inner.field().floor().delta()
    }

    /// The number of boundary elements of the harmonic map.
    #[getter]
    fn elements(&self) -> usize {
        self.inner.field().floor().map().elements().len()
    }

    /// The goal, as a (2,) array.
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let g = self.inner.goal();
        array1(py, &[g.x, g.y], "goal")
    }

    /// `√(2μ/m)` for the dynamic law, `None` for the kinematic one.
    #[getter]
    fn speed_bound(&self) -> Option<f64> {
        self.inner.speed_bound()
    }

    /// How the last command was formed (`"law"` before the first).
    #[getter]
    fn mode(&self) -> &'static str {
        self.mode.as_str()
    }

    /// The control period in force, s.
    #[getter]
    fn control_period(&self) -> f64 {
        self.inner.control_period()
    }

    /// Escapes begun from rest points of the hold's slide (`docs/maths.md` §13.7).
    #[getter]
    fn escapes(&self) -> usize {
        self.inner.escapes()
    }

    /// An independent navigator with the same walls, obstacles and state.
    fn __copy__(&self) -> Self {
        self.clone()
    }

    /// As `__copy__`; `memo` is unused.
    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "FloorNavigator(δ = {} m, {} perceived obstacles, k={})",
            self.inner.field().floor().delta(),
            self.inner.perceived().count(),
            self.inner.k()
        )
    }
}

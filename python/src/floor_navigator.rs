//! The online API on a floor plan: `harmonav::FloorNavigator`.

use std::sync::{Arc, Mutex};

use harmonav_rs::floorplan::MapOptions;
use harmonav_rs::{
    CentrePolicy, DampingPolicy, FloorMap, FloorNavigator as RsFloorNavigator, FloorOptions,
    HeadingPolicy, HoldPolicy, KPolicy, Law, Mode, NavError, Options, SpeedPolicy, Vector2,
};
use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::convert::{array1, integer, lock, point_like, points_like, policy, value_error};
use crate::navigator::{
    Log, Replayed, ScanUpdate, events, finite_theta, free_memory_count, law_named, scan_from,
    scan_options,
};
use crate::shapes::{Shape, from_perceived};

/// The keyword arguments shared by `FloorNavigator(...)` and `FloorNavigator.from_map(...)`
/// as given (what pickle rebuilds the navigator with): the law, the robot, the policies and
/// the scan's priors.
#[derive(Clone)]
struct Keywords {
    law: String,
    gain: f64,
    mass: f64,
    mu: f64,
    radius: f64,
    margin: f64,
    max_element: f64,
    centre: String,
    k: String,
    damping: String,
    heading: String,
    hold: String,
    speed: String,
    v_max: Option<f64>,
    control_period: Option<f64>,
    range_noise: f64,
    max_obstacle_depth: f64,
    growth_threshold: f64,
    fit_range: Option<f64>,
    free_memory: usize,
}

impl Keywords {
    /// The keywords as a dict of `FloorNavigator(...)`'s.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("law", &self.law)?;
        d.set_item("gain", self.gain)?;
        d.set_item("mass", self.mass)?;
        d.set_item("mu", self.mu)?;
        d.set_item("radius", self.radius)?;
        d.set_item("margin", self.margin)?;
        d.set_item("max_element", self.max_element)?;
        d.set_item("centre", &self.centre)?;
        d.set_item("k", &self.k)?;
        d.set_item("damping", &self.damping)?;
        d.set_item("heading", &self.heading)?;
        d.set_item("hold", &self.hold)?;
        d.set_item("speed", &self.speed)?;
        d.set_item("v_max", self.v_max)?;
        d.set_item("control_period", self.control_period)?;
        d.set_item("range_noise", self.range_noise)?;
        d.set_item("max_obstacle_depth", self.max_obstacle_depth)?;
        d.set_item("growth_threshold", self.growth_threshold)?;
        d.set_item("fit_range", self.fit_range)?;
        d.set_item("free_memory", self.free_memory)?;
        Ok(d)
    }
}

/// The keyword arguments checked: the law, the navigator's options and the floor plan's.
struct Setup {
    keywords: Keywords,
    law: Law,
    options: Options,
    floor: FloorOptions,
}

impl Setup {
    fn new(keywords: Keywords) -> PyResult<Self> {
        let Keywords {
            ref law,
            gain,
            mass,
            mu,
            radius,
            margin,
            max_element,
            ref centre,
            ref k,
            ref damping,
            ref heading,
            ref hold,
            ref speed,
            v_max,
            control_period,
            range_noise,
            max_obstacle_depth: depth,
            growth_threshold: growth,
            fit_range,
            free_memory,
        } = keywords;
        let law = law_named(law, gain, mass, mu)?;
        // The robot's size first: the floor plan is shrunk by it before the navigator checks it.
        for (field, value) in [("radius", radius), ("margin", margin)] {
            if !(value.is_finite() && (0.0..=harmonav_rs::transform::MAX_LENGTH).contains(&value)) {
                return Err(nav_error(NavError::InvalidOption { field, value }));
            }
        }
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
            keywords,
            law,
            options,
            floor,
        })
    }

    /// The navigator on `floor` towards `goal`.
    fn navigator(self, floor: FloorMap, goal: Vector2<f64>) -> PyResult<FloorNavigator> {
        let state =
            FloorState::fresh(Arc::new(floor), goal, self.law, self.options, self.keywords)?;
        Ok(FloorNavigator::holding(state))
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
///
/// Threads: the calls on one navigator are serialised by a lock inside it, as `Navigator`'s
/// are (a call made during another thread's `observe_scan` waits for it).
///
/// `copy.copy` and `copy.deepcopy` give an independent navigator with the same walls (the
/// solved map is shared, it never changes), obstacles and state. Pickle stores the true walls
/// as rings, the goal, the keyword arguments and the calls that made the state (as
/// `Navigator`'s); unpickling solves the harmonic map again (from the same rings: the same
/// map) and replays them. It keeps the obstacles (added and perceived), the last commanded
/// state and the dynamic law's discovery speed, not the memory of the hold's escapes (how long
/// the robot has rested, an escape in progress and where the last one began, `escapes`): that
/// starts again from the replayed commands, so the copy commands as the original except where
/// an escape is under way or due (`docs/maths.md` §13.7).
#[pyclass(module = "harmonav", frozen)]
pub struct FloorNavigator {
    /// Locked with [`lock`], only around Rust work.
    state: Mutex<FloorState>,
}

/// A floor navigator's state, behind its lock.
#[derive(Clone)]
struct FloorState {
    inner: RsFloorNavigator,
    /// How the last command was formed.
    mode: Mode,
    /// The keyword arguments, for pickle.
    keywords: Keywords,
    /// The law and options the navigator was built with (to rebuild it on its map).
    law: Law,
    options: Options,
    /// The calls that made the state since construction (what pickle replays).
    log: Log,
}

impl FloorState {
    /// A navigator as constructed on `floor` (shared: a navigator rebuilt on the same map does
    /// not solve it again).
    fn fresh(
        floor: Arc<FloorMap>,
        goal: Vector2<f64>,
        law: Law,
        options: Options,
        keywords: Keywords,
    ) -> PyResult<Self> {
        let inner = RsFloorNavigator::new(floor, goal, law, options).map_err(value_error)?;
        Ok(Self {
            inner,
            mode: Mode::Law,
            keywords,
            law,
            options,
            log: Log::default(),
        })
    }

    fn add(&mut self, shape: &Shape) -> Result<usize, NavError> {
        let i = self.inner.add_obstacle(shape.inner.clone())?;
        self.log.add(shape.clone());
        Ok(i)
    }

    fn scan(
        &mut self,
        pose: harmonav_rs::Pose,
        scan: harmonav_rs::LaserScan,
    ) -> Result<harmonav_rs::ScanUpdate, NavError> {
        let u = self.inner.observe_scan(pose, &scan);
        self.log
            .observed(pose, scan, &u, harmonav_rs::ScanUpdate::changed);
        u
    }

    fn issue(&mut self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Vector2<f64>, NavError> {
        let before = self.inner.discovery_speed();
        let c = self.inner.command(x, v)?;
        self.mode = c.mode;
        let lifted = self.inner.discovery_speed().to_bits() != before.to_bits();
        self.log.command(x, v, lifted);
        Ok(c.value)
    }
}

impl Replayed for FloorState {
    const CLASS: &'static str = "FloorNavigator";

    fn add(&mut self, shape: &Shape) -> Result<(), NavError> {
        FloorState::add(self, shape).map(drop)
    }

    fn scan(
        &mut self,
        pose: harmonav_rs::Pose,
        scan: harmonav_rs::LaserScan,
    ) -> Result<(), NavError> {
        FloorState::scan(self, pose, scan).map(drop)
    }

    fn issue(&mut self, x: Vector2<f64>, v: Vector2<f64>) -> Result<(), NavError> {
        FloorState::issue(self, x, v).map(drop)
    }
}

impl FloorNavigator {
    fn holding(state: FloorState) -> Self {
        Self {
            state: Mutex::new(state),
        }
    }

    /// The state, locked (see [`lock`]).
    fn state(&self, py: Python<'_>) -> std::sync::MutexGuard<'_, FloorState> {
        lock(py, &self.state)
    }
}

/// `speck_pixels=` as a count, refused by name (negative, or beyond 64 bits).
fn speck_pixels_count(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    let n: i64 = integer(
        obj,
        "speck_pixels",
        "an integer ≥ 0 (at most the map's speck cap)",
    )?;
    usize::try_from(n).map_err(|_| {
        PyValueError::new_err(format!("`speck_pixels` must be an integer ≥ 0, got {n}"))
    })
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
        #[pyo3(from_py_with = free_memory_count)] free_memory: usize,
    ) -> PyResult<Self> {
        let outer = points_like(outer, "outer")?;
        let holes = rings(holes)?;
        let goal = point_like(goal, "goal")?;
        let setup = Setup::new(Keywords {
            law: law.to_owned(),
            gain,
            mass,
            mu,
            radius,
            margin,
            max_element,
            centre: centre.to_owned(),
            k: k.to_owned(),
            damping: damping.to_owned(),
            heading: heading.to_owned(),
            hold: hold.to_owned(),
            speed: speed.to_owned(),
            v_max,
            control_period,
            range_noise,
            max_obstacle_depth,
            growth_threshold,
            fit_range,
            free_memory,
        })?;
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
        #[pyo3(from_py_with = speck_pixels_count)] speck_pixels: usize,
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
        #[pyo3(from_py_with = free_memory_count)] free_memory: usize,
    ) -> PyResult<Self> {
        let start = point_like(start, "start")?;
        let goal = point_like(goal, "goal")?;
        let setup = Setup::new(Keywords {
            law: law.to_owned(),
            gain,
            mass,
            mu,
            radius,
            margin,
            max_element,
            centre: centre.to_owned(),
            k: k.to_owned(),
            damping: damping.to_owned(),
            heading: heading.to_owned(),
            hold: hold.to_owned(),
            speed: speed.to_owned(),
            v_max,
            control_period,
            range_noise,
            max_obstacle_depth,
            growth_threshold,
            fit_range,
            free_memory,
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
    fn add_obstacle(&self, py: Python<'_>, shape: &Shape) -> PyResult<usize> {
        self.state(py).add(shape).map_err(nav_error)
    }

    /// The command to hold for `control_period` at `x` with velocity `v` (default 0), as a (2,)
    /// array: a velocity (kinematic law) or a force (dynamic law); `mode` then says how it was
    /// formed (`"law"`, `"capped"`, `"recovering"` out of a margin band or the boundary layer,
    /// `"escaping"` along the shortest path from a rest point of the hold). Raises `ValueError`
    /// (and changes nothing) where the robot's disc overlaps a wall or a known obstacle, or for
    /// non-finite input.
    #[pyo3(signature = (x, v=None))]
    fn command<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        v: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = point_like(x, "x")?;
        let v = v.map_or(Ok(Vector2::zeros()), |v| point_like(v, "v"))?;
        // With the GIL held (one evaluation, tens of µs), as `Navigator.command`.
        let c = self.state(py).issue(x, v).map_err(nav_error)?;
        array1(py, &[c.x, c.y], "command")
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
        &self,
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
        // The lock is held while the scan runs without the GIL: a call from another thread
        // waits for it (detached too) instead of failing.
        let mut guard = self.state(py);
        let state: &mut FloorState = &mut guard;
        let u = py.detach(|| state.scan(pose, scan));
        drop(guard);
        Ok(ScanUpdate::from(u.map_err(nav_error)?))
    }

    /// The perceived shapes (from scans, not grown), as `(index, Shape)` pairs: `index` among
    /// the navigator's obstacles, the shape a `star` with `signed_distance` and `contains`.
    #[getter]
    fn perceived(&self, py: Python<'_>) -> Vec<(usize, Shape)> {
        self.state(py)
            .inner
            .perceived()
            .map(|(i, p)| (i, from_perceived(p)))
            .collect()
    }

    /// Every known obstacle (not grown) in the navigator's order: the shapes given to
    /// `add_obstacle` as given, and the perceived ones (`perceived`, from scans) as `star`
    /// shapes with `signed_distance` and `contains`.
    #[getter]
    fn obstacles(&self, py: Python<'_>) -> Vec<Shape> {
        let state = self.state(py);
        crate::navigator::known(
            state.inner.added().map(|(i, _)| i),
            &state.log,
            state.inner.perceived(),
        )
    }

    /// `Θ(x)` over the walls and the known obstacles (finite; `ValueError` outside the
    /// certified region or in an obstacle).
    fn theta(&self, py: Python<'_>, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        let x = point_like(x, "x")?;
        let theta = self.state(py).inner.theta(x);
        finite_theta(theta.map_err(nav_error)?)
    }

    /// The certified clearance at `x`: a lower bound on the distance to the boundary layer
    /// (`sd(x) − δ`) and to every known obstacle grown by `radius + margin`, m.
    fn clearance(&self, py: Python<'_>, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        let x = point_like(x, "x")?;
        Ok(self.state(py).inner.clearance(x))
    }

    /// The distance from `x` to the true walls (positive inside, negative in a wall), m.
    fn wall_distance(&self, py: Python<'_>, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        let x = point_like(x, "x")?;
        Ok(self
            .state(py)
            .inner
            .field()
            .floor()
            .walls()
            .signed_distance(x))
    }

    /// `k` of `φ_k`: the holes plus the known obstacles, under the `k` policy.
    #[getter]
    fn k(&self, py: Python<'_>) -> f64 {
        self.state(py).inner.k()
    }

    /// `δ`, the width of the boundary layer (m): the robot stays at least
    /// `max(radius + margin, δ)` from the walls.
    #[getter]
    fn delta(&self, py: Python<'_>) -> f64 {
        self.state(py).inner.field().floor().delta()
    }

    /// The number of boundary elements of the harmonic map.
    #[getter]
    fn elements(&self, py: Python<'_>) -> usize {
        self.state(py).inner.field().floor().map().elements().len()
    }

    /// The goal, as a (2,) array.
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let g = self.state(py).inner.goal();
        array1(py, &[g.x, g.y], "goal")
    }

    /// `√(2μ/m)` for the dynamic law, `None` for the kinematic one.
    #[getter]
    fn speed_bound(&self, py: Python<'_>) -> Option<f64> {
        self.state(py).inner.speed_bound()
    }

    /// How the last command was formed (`"law"` before the first).
    #[getter]
    fn mode(&self, py: Python<'_>) -> &'static str {
        self.state(py).mode.as_str()
    }

    /// The control period in force, s.
    #[getter]
    fn control_period(&self, py: Python<'_>) -> f64 {
        self.state(py).inner.control_period()
    }

    /// Escapes begun from rest points of the hold's slide (`docs/maths.md` §13.7).
    #[getter]
    fn escapes(&self, py: Python<'_>) -> usize {
        self.state(py).inner.escapes()
    }

    /// Pickle support: `(functools.partial(FloorNavigator, **keywords), (outer, goal, holes),
    /// state)`: the true walls as rings (however the navigator was made: from rings or from a
    /// map), and the calls that made the state, replayed by `__setstate__` (as `Navigator`'s).
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>, Bound<'py, PyList>)> {
        // Copied out under the lock, turned into Python objects after it.
        let (outer, holes, goal, keywords, log) = {
            let s = self.state(py);
            let walls = s.inner.field().floor().walls();
            let ring = |r: &[Vector2<f64>]| r.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>();
            let holes: Vec<Vec<[f64; 2]>> = walls.holes().iter().map(|h| ring(h)).collect();
            let g = s.inner.goal();
            (
                ring(walls.outer()),
                holes,
                [g.x, g.y],
                s.keywords.clone(),
                s.log.clone(),
            )
        };
        let partial = py
            .import("functools")?
            .getattr("partial")?
            .call((py.get_type::<Self>(),), Some(&keywords.to_dict(py)?))?;
        let args = (outer, goal, holes).into_pyobject(py)?;
        Ok((partial, args, log.to_python(py)?))
    }

    /// Restores a pickled state: the navigator as constructed (on the same map, not solved
    /// again) with `state` replayed. Raises `ValueError` or `TypeError` (and changes nothing)
    /// for a state that does not replay.
    fn __setstate__(&self, py: Python<'_>, state: &Bound<'_, PyAny>) -> PyResult<()> {
        let events = events(state, "FloorNavigator")?;
        let (floor, goal, law, options, keywords) = {
            let s = self.state(py);
            let floor = Arc::clone(s.inner.field().floor());
            (floor, s.inner.goal(), s.law, s.options, s.keywords.clone())
        };
        let fresh = py.detach(|| {
            let mut fresh = FloorState::fresh(floor, goal, law, options, keywords)?;
            fresh.replay(events)?;
            Ok::<_, PyErr>(fresh)
        })?;
        *self.state(py) = fresh;
        Ok(())
    }

    /// An independent navigator with the same walls, obstacles and state.
    fn __copy__(&self, py: Python<'_>) -> Self {
        Self::holding(self.state(py).clone())
    }

    /// As `__copy__`; `memo` is unused.
    fn __deepcopy__(&self, py: Python<'_>, _memo: &Bound<'_, PyAny>) -> Self {
        self.__copy__(py)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let s = self.state(py);
        format!(
            "FloorNavigator(δ = {} m, {} perceived obstacles, k={})",
            s.inner.field().floor().delta(),
            s.inner.perceived().count(),
            s.inner.k()
        )
    }
}

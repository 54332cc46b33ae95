//! `harmonav.FloorNavigator`: the `Navigator` of a floor plan. Its constructors (from rings,
//! from a ROS map) and its floor-only methods are here; every other method is `Navigator`'s.

use std::sync::Arc;

use harmonav_rs::floorplan::{FunnelOptions, Funnels, MapOptions};
use harmonav_rs::{FloorMap, FloorNavigator as RsFloorNavigator, FloorOptions, Law, Vector2};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{integer, point_like, points_like, value_error};
use crate::navigator::{Built, Navigator, State, Workspace};
use crate::options::{FloorKeywords, Keywords};

/// The navigator of a robot on a floor plan (issue 25), a `Navigator` (its subclass: the same
/// methods and options): the walls are known, a polygon with holes or a ROS map_server map,
/// and its harmonic map is solved once at construction; star obstacles met on the way are
/// added as shapes (`add_obstacle`) or perceived from range scans (`observe_scan`), each
/// without a new solve. `command(x, v)` returns the law's command, as `Navigator`'s does: the
/// velocity (`law="kinematic"`, `gain`) or the force (`law="dynamic"`, `mass`, `mu`), safe to
/// hold for `control_period`.
///
/// `FloorNavigator(outer, goal, holes=None, **options)` takes the walls as rings of points
/// (either orientation; the outer ring need not be star-shaped); `FloorNavigator.from_map(yaml,
/// start, goal)` reads a ROS map (`speck_pixels`, `simplify` as in a floor-plan file). The
/// robot keeps `radius + margin` (m) from the walls; `max_element` (m) is the boundary
/// elements' length and the width `δ` of the boundary layer, where the discrete map is not used
/// (`docs/maths.md` §13): the robot navigates in the certified region `W_δ`, at least
/// `max(radius + margin, δ)` from the walls. `centre` (`"solve"` or `"goal"`) and `heading`
/// (`"auto"`: within 60° of `−∇Θ` along the shortest path; `"paper"`: `−∇Θ`) are the floor
/// plan's own; the other keyword arguments (`law`, `gain`, `mass`, `mu`, `sensor`, `radius`,
/// `margin`, `k`, `damping`, `rho_min`, `control_period`, `hold`, `speed`, `v_max` and the
/// scan's priors) are `Navigator`'s, with its defaults, checked as it checks them.
///
/// `funnels=True` (the kinematic law only; `ValueError` otherwise) builds a chain of certified
/// funnels towards intermediate goals over the walls (`docs/maths.md` §13.10), without the GIL,
/// and the navigator follows it: convergence to the goal is then certified from every point of
/// their union (`funnels`, `funnel_at`). It costs seconds to a minute on a map of a thousand
/// boundary elements; the chain is built over the free space reachable from the goal, so it
/// does not depend on a start and pickle rebuilds the same one.
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
#[pyclass(module = "harmonav", frozen, extends = Navigator)]
pub struct FloorNavigator;

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

/// A floor plan's navigator: its options checked (`Navigator`'s, then the floor's) before
/// `solve` solves the map with the floor's options (without the GIL), and the navigator built
/// on it towards `goal`; with `funnels=True` the chain of certified funnels is built next
/// (without the GIL) and the navigator follows it.
fn on_floor<E: std::fmt::Display + Send>(
    py: Python<'_>,
    keywords: Keywords,
    floor: FloorKeywords,
    goal: Vector2<f64>,
    solve: impl FnOnce(&FloorOptions) -> Result<FloorMap, E> + Send,
) -> PyResult<PyClassInitializer<FloorNavigator>> {
    let (law, options) = keywords.check()?;
    let (floor_options, options) = floor.check(options)?;
    if floor.funnels && !matches!(law, Law::Kinematic { .. }) {
        return Err(PyValueError::new_err(
            "`funnels=True` needs law=\"kinematic\": the funnels are sublevel sets of Θ and \
             certify the kinematic law, not the dynamic law's energy (docs/maths.md §13.10)",
        ));
    }
    let map = Arc::new(py.detach(|| solve(&floor_options)).map_err(value_error)?);
    let funnels = if floor.funnels {
        let nav =
            RsFloorNavigator::new(Arc::clone(&map), goal, law, options).map_err(value_error)?;
        Some(py.detach(|| chain(&nav, options.radius + options.margin)))
    } else {
        None
    };
    let built = Built {
        workspace: Workspace::Floor {
            map,
            keywords: floor,
            funnels,
        },
        goal,
        keywords,
        law,
        options,
    };
    let state = py.detach(|| State::new(built))?;
    Ok(PyClassInitializer::from(Navigator::holding(state)).add_subclass(FloorNavigator))
}

/// The chain of certified funnels towards `nav`'s goal over its walls
/// ([`harmonav_rs::floorplan::FloorField::funnels`], [`FunnelOptions::on_this_machine`]),
/// over the free space of clearance `inflation` reachable from the goal: the same chain
/// whichever the start, so a pickled navigator rebuilds it exactly.
fn chain(nav: &RsFloorNavigator, inflation: f64) -> Arc<Funnels> {
    let options = FunnelOptions::on_this_machine();
    let field = nav.field();
    let goal = field.transform().goal();
    Arc::new(field.funnels(None, goal, inflation, &[], &options))
}

impl FloorNavigator {
    /// `f` of the Rust navigator.
    fn floor<R>(slf: &Bound<'_, Self>, f: impl FnOnce(&RsFloorNavigator) -> R) -> PyResult<R> {
        slf.as_super().get().floor(slf.py(), f)
    }

    /// An independent navigator with the same walls, obstacles and state (the map shared).
    fn copied(slf: &Bound<'_, Self>) -> PyResult<Py<Self>> {
        let nav = slf.as_super().get().copied(slf.py());
        Py::new(
            slf.py(),
            PyClassInitializer::from(nav).add_subclass(FloorNavigator),
        )
    }
}

#[pymethods]
impl FloorNavigator {
    /// The navigator on the floor plan walled by the ring `outer` and the rings `holes`,
    /// towards `goal`.
    #[new]
    #[pyo3(signature = (outer, goal, holes=None, *, max_element=0.2, centre="solve",
                        heading="auto", funnels=false, **options))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        outer: &Bound<'_, PyAny>,
        goal: &Bound<'_, PyAny>,
        holes: Option<&Bound<'_, PyAny>>,
        max_element: f64,
        centre: &str,
        heading: &str,
        funnels: bool,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let keywords = Keywords::parse("FloorNavigator", &PyTuple::empty(py), options)?;
        let outer = points_like(outer, "outer")?;
        let holes = rings(holes)?;
        let goal = point_like(goal, "goal")?;
        let floor = FloorKeywords {
            max_element,
            centre: centre.to_owned(),
            heading: heading.to_owned(),
            funnels,
        };
        on_floor(py, keywords, floor, goal, |options| {
            FloorMap::new(outer, holes, options)
        })
    }

    /// The navigator on the ROS map_server map at `yaml` (its image relative to it) for a robot
    /// going from `start` to `goal` (world coordinates): the free component holding the goal,
    /// specks of at most `speck_pixels` dropped (default 0: every occupied island is kept, a
    /// post of one pixel is an obstacle), the outline simplified by at most `simplify` square
    /// pixels (`docs/maths.md` §13.1), shrunk by `radius + margin`. The other arguments are the
    /// constructor's. Raises `ValueError` naming the file and the problem: a missing or
    /// truncated image, a start or goal in a wall or unknown space or outside the image, a goal
    /// not reachable from the start, a passage narrower than the robot.
    #[staticmethod]
    #[pyo3(signature = (yaml, start, goal, *, speck_pixels=0, simplify=0.5, max_element=0.2,
                        centre="solve", heading="auto", funnels=false, **options))]
    #[allow(clippy::too_many_arguments)]
    fn from_map(
        py: Python<'_>,
        yaml: std::path::PathBuf,
        start: &Bound<'_, PyAny>,
        goal: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = speck_pixels_count)] speck_pixels: usize,
        simplify: f64,
        max_element: f64,
        centre: &str,
        heading: &str,
        funnels: bool,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Py<Self>> {
        let keywords = Keywords::parse("FloorNavigator.from_map", &PyTuple::empty(py), options)?;
        let start = point_like(start, "start")?;
        let goal = point_like(goal, "goal")?;
        let floor = FloorKeywords {
            max_element,
            centre: centre.to_owned(),
            heading: heading.to_owned(),
            funnels,
        };
        // `simplify` is checked by the map (`MapError` naming it).
        let init = on_floor(py, keywords, floor, goal, |floor| {
            let options = MapOptions {
                floor: *floor,
                speck_pixels,
                simplify,
            };
            FloorMap::from_ros_map(&yaml, start, goal, &options)
        })?;
        Py::new(py, init)
    }

    /// The distance from `x` to the true walls (positive inside, negative in a wall), m.
    fn wall_distance(slf: &Bound<'_, Self>, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        let x = point_like(x, "x")?;
        Self::floor(slf, |nav| nav.field().floor().walls().signed_distance(x))
    }

    /// `δ`, the width of the boundary layer (m): the robot stays at least
    /// `max(radius + margin, δ)` from the walls.
    #[getter]
    fn delta(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Self::floor(slf, |nav| nav.field().floor().delta())
    }

    /// The number of boundary elements of the harmonic map.
    #[getter]
    fn elements(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Self::floor(slf, |nav| nav.field().floor().map().elements().len())
    }

    /// Escapes begun from rest points of the hold's slide (`docs/maths.md` §13.7).
    #[getter]
    fn escapes(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Self::floor(slf, RsFloorNavigator::escapes)
    }

    /// The chain of certified funnels the navigator follows (`funnels=True`, `docs/maths.md`
    /// §13.10), or `None`: a dict with `count`, `certified_fraction` (the fraction of the free
    /// area reachable from the goal that lies in a funnel: convergence is certified from
    /// there), `deepest` (the most switches to the goal), `goals` (each funnel's goal `(x, y)`
    /// with its parent's index, `None` for the navigator's goal) and `current` (the funnel the
    /// robot was last in, `None` before the first command in one).
    #[getter]
    fn funnels(slf: &Bound<'_, Self>) -> PyResult<Option<Py<PyDict>>> {
        let py = slf.py();
        let Some((chain, current)) =
            Self::floor(slf, |nav| nav.funnels().map(|(c, i)| (Arc::clone(c), i)))?
        else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("count", chain.funnels.len())?;
        d.set_item("certified_fraction", chain.fraction())?;
        d.set_item("deepest", chain.deepest())?;
        let goals: Vec<((f64, f64), Option<usize>)> = chain
            .funnels
            .iter()
            .map(|f| ((f.goal.x, f.goal.y), f.parent))
            .collect();
        d.set_item("goals", goals)?;
        d.set_item("current", current)?;
        Ok(Some(d.unbind()))
    }

    /// The funnel of least index that holds `x` (the one the robot would follow from there), or
    /// `None` when `x` lies in none or the navigator follows no chain: convergence from `x` is
    /// certified by the chain exactly when this is not `None`.
    fn funnel_at(slf: &Bound<'_, Self>, x: &Bound<'_, PyAny>) -> PyResult<Option<usize>> {
        let x = point_like(x, "x")?;
        Self::floor(slf, |nav| {
            nav.funnels().and_then(|(chain, _)| chain.entry(x))
        })
    }

    /// An independent navigator with the same walls, obstacles and state.
    fn __copy__(slf: &Bound<'_, Self>) -> PyResult<Py<Self>> {
        Self::copied(slf)
    }

    /// As `__copy__`; `memo` is unused.
    fn __deepcopy__(slf: &Bound<'_, Self>, _memo: &Bound<'_, PyAny>) -> PyResult<Py<Self>> {
        Self::copied(slf)
    }
}

//! The online API: `harmonav.Navigator`, one class over either world (`harmonav::Navigator<W>`
//! over a star world or a floor plan). A floor plan's navigator is its subclass
//! `FloorNavigator` (`floor_navigator.rs`: its constructors and its floor-only methods); every
//! other method is written once here, over [`Inner`].

use std::sync::{Arc, Mutex};

use harmonav_rs::Vector2;
use harmonav_rs::floorplan::Funnels;
use harmonav_rs::{
    Base, EscapeMemory, FloorMap, FloorNavigator as RsFloorNavigator, GoalTolerance, LaserScan,
    Law, Mode, Mover as RsMover, MoverKind, MoverMemory, NavError, Navigator as RsNavigator,
    Options, Pose, PoseCommand, ScanUpdate as RsScanUpdate, Steer,
};
use numpy::PyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::convert::{array1, lock, point_like, reals_like, value_error};
use crate::movers::{Mover, movers_from};
use crate::options::{FloorKeywords, Keywords};
use crate::shapes::{Shape, from_perceived};

/// The navigator of a robot that does not know its map: obstacles are added as its perception
/// finds them, and `command(x, v)` returns the law's command. `Navigator(boundary, goal, …)`
/// navigates a star world (`boundary` a `Shape`); `FloorNavigator(outer, goal, holes, …)`, its
/// subclass, a floor plan, with the same keyword arguments and methods.
///
/// - `law="kinematic"`: the velocity `u = −s(x)∇Θ/|∇Θ|` along the flow lines of eq. `kinctrl`:
///   under `speed="auto"` (the default) `s = min(v_max, √(2a|x − x_d|))`, full speed until a
///   braking distance, then a constant deceleration and a linear core (35 µm at the default
///   `v_max`): within any tolerance of the goal in finite time, and the hold never steps past
///   it; under `speed="paper"` `s = K√(2Θ)`, `K = gain` (`docs/maths.md` §6). `v_max` (m/s,
///   default `K√2`) caps both.
/// - `law="dynamic"`: the force `f = −μ_p∇Ψ − λẋ` (eq. `dynctrllocal`, `μ_p = μ` but under
///   `"governed"`; `Ψ = Θ` and `λ` of
///   eq. `dissipationfun` under `damping="paper"`; `Ψ = 1 − √(1 − Θ)` and a damping critical at
///   the goal under `damping="shaped"`; the same on `Θ` made free of the world's scale under
///   `damping="auto"`; a goal bowl in metres and a ramp as long as the world under the research
///   policy `damping="fast"`; `"auto"` pulling with `4μ·max(1, ρ/5 m)` (`ρ` the boundary's
///   largest radius), so that the robot uses its whole speed bound, with a governor that keeps it below `0.9·√(2μ/m)` under `damping="governed"`, the
///   default, `docs/maths.md` §9), for a robot of mass `mass`; its speed stays below `√(2μ/m)`.
///
/// `sensor=(range_m, aperture_deg)` sets `d_min` (eq. `dmin`); `radius` and `margin` (m) grow
/// every obstacle and shrink the boundary; `k` is `"auto"` or `"paper"`.
///
/// `observe_scan(...)` feeds it range scans instead of shapes (`docs/maths.md` §12.6), under the
/// priors `range_noise` (m, the noise bound), `max_obstacle_depth` (m, how far an obstacle may
/// extend behind what was seen), `growth_threshold` (m, how far outside a shape a hit must lie
/// to grow it) and `rho_min`; `fit_range` (m, default `None`: every segment) fits a segment only
/// once a hit is that near (`radius + margin + range_noise + 3·v_max·T_scan` is recommended,
/// `docs/maths.md` §12.16; `v_max` the dynamic law's `√(2μ/m)`, which brakes within each scan
/// event's own room, §12.18). Under the dynamic law with `damping="paper"` it cuts the sector
/// of `d_min` to `fit_range − max_obstacle_depth` (`max_obstacle_depth + 0.5` is recommended
/// there, §12.11). `free_memory` (default 16) is how many earlier scans' free space the
/// fits leave out (a static world).
///
/// `control_period` (s; default 0.01 kinematic, 0.001 dynamic) is how long your loop holds
/// each command (`x += h·u`, or `v += h·f/m; x += h·v`): under `hold="auto"` (the default)
/// every command is safe to hold for it (`docs/maths.md` §10), and `mode` says whether the last
/// one was the law's (`"law"`), shortened (`"capped"`), leads out of the margin band
/// (`"recovering"`) or, the kinematic law's held step having come to rest away from the goal
/// (a saddle of `Θ`, a narrow valley), is the steepest certified descent among 16 directions
/// (`"from-rest"`, §10.1). `hold="paper"` gives the continuous law sampled as is.
///
/// `force_bound` (N, dynamic law only; default `None`) bounds every force, `|f| ≤ F`, and
/// certifies each command only if the robot can still brake to rest at `F/m` inside the
/// known free space and out of every mover's reach (docs/movers.md §2): `mode` is
/// `"bounded"` when the bound changed the command, `"braking"` (and `certified` False) when
/// even the full brake's way to rest is not certified (a start at speed, say).
///
/// `comfort` (m, default 0) is a distance the command keeps beyond the margin from every
/// non-cooperative mover where it can (docs/movers.md §7, "Comfort"): it turns the nominal
/// command only, and the mover filter still certifies every command. Negative or not finite:
/// a `ValueError` naming it.
///
/// Invalid parameters raise `ValueError` with the Rust `NavError`'s message, which names the
/// parameter (every range is the scenario files'; `d_min`, the speed bound and `λ_c` are
/// checked finite); a keyword that is not an option is a `TypeError` naming it. Both worlds
/// check their options in one place. `copy.copy`, `copy.deepcopy` and pickle give an
/// independent navigator with the same known obstacles and state, which commands exactly as
/// the original.
///
/// Threads: the calls on one navigator are serialised by a lock inside it. A call made while
/// another thread's call runs (an `observe_scan`, which releases the GIL) waits for it, with
/// the GIL released, instead of failing.
#[pyclass(module = "harmonav", frozen, subclass)]
pub struct Navigator {
    /// Locked with [`lock`], only around Rust work.
    state: Mutex<State>,
}

/// The Rust navigator, over either world.
// One per navigator, in place behind its lock: a box would add an indirection for nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Clone)]
enum Inner {
    Star(RsNavigator),
    Floor(RsFloorNavigator),
}

/// `$body` with `$nav` bound to the Rust navigator of `$inner` (an [`Inner`]), whichever its
/// world: the methods the two worlds share, written once.
macro_rules! each {
    ($inner:expr, $nav:ident => $body:expr) => {
        match $inner {
            Inner::Star($nav) => $body,
            Inner::Floor($nav) => $body,
        }
    };
}

/// What a navigator is built on: a star world's true boundary, or a floor plan's solved map
/// (shared: a navigator rebuilt on it does not solve it again) with the floor's own options.
#[derive(Clone)]
pub(crate) enum Workspace {
    Star(Shape),
    Floor {
        map: Arc<FloorMap>,
        keywords: FloorKeywords,
        /// The chain of certified funnels the navigator follows (`funnels=True`), built once.
        funnels: Option<Arc<Funnels>>,
    },
}

/// How a navigator was built: what `__setstate__` rebuilds it from and pickle stores.
#[derive(Clone)]
pub(crate) struct Built {
    pub(crate) workspace: Workspace,
    pub(crate) goal: Vector2<f64>,
    /// The options as given.
    pub(crate) keywords: Keywords,
    /// The law and the options they gave, checked ([`Keywords::check`]).
    pub(crate) law: Law,
    pub(crate) options: Options,
}

impl Built {
    /// The Rust navigator, as constructed (no obstacle known).
    fn navigator(&self) -> Result<Inner, NavError> {
        let (goal, law, options) = (self.goal, self.law, self.options);
        Ok(match &self.workspace {
            Workspace::Star(boundary) => Inner::Star(RsNavigator::new(
                boundary.inner.clone(),
                goal,
                law,
                options,
            )?),
            Workspace::Floor { map, funnels, .. } => {
                let mut nav = RsFloorNavigator::new(Arc::clone(map), goal, law, options)?;
                if let Some(chain) = funnels {
                    nav.set_funnels(Arc::clone(chain))?;
                }
                Inner::Floor(nav)
            }
        })
    }
}

/// A navigator's state, behind its lock.
#[derive(Clone)]
pub(crate) struct State {
    inner: Inner,
    built: Built,
    /// The calls that made the state since construction (what pickle replays).
    log: Log,
    /// How the last command was formed.
    mode: Mode,
    /// How the last `command_pose` formed `(v, ω)`; `None` after a `command`.
    steer: Option<Steer>,
}

/// A call that changed a navigator's state.
#[derive(Clone)]
enum Event {
    /// `add_obstacle(shape)` (the true shape).
    Add(Shape),
    /// `command(x, v)`.
    Command([f64; 2], [f64; 2]),
    /// `command_pose(position, yaw)` (issue 53).
    Pose([f64; 2], f64),
    /// `set_movers(movers)` (issue 54): in force until the next.
    Movers(Vec<RsMover>),
    /// `set_goal_heading(yaw)` (issue 53): in force until the next.
    GoalHeading(Option<f64>),
    /// `set_goal_tolerance(xy, yaw, stateful)` (issue 53): in force until the next.
    GoalTolerance(f64, f64, bool),
    /// `observe_scan(...)` that changed the obstacles, or that ended a halt (a scan that
    /// changed nothing otherwise leaves no state to replay).
    Scan(Box<(Pose, LaserScan)>),
    /// `observe_scan(...)` that was refused: the navigator halts until a scan is accepted
    /// (`Mode::Halted`), so a copy must too; replayed, it must be refused again.
    Refused(Box<(Pose, LaserScan)>),
    /// A floor navigator's escape memory (`FloorNavigator::escape_memory`), which replaying
    /// the calls does not rebuild: pickle puts it first, and it is taken back after every call.
    Escapes(EscapeMemory),
    /// The mover memory (`Navigator::mover_memory`: KeepRight's and whether the filter changed
    /// the last command), set where it stands: before a kept command made from a memory the
    /// calls kept before it do not rebuild, and last in a pickle (the memory now).
    MoverMemory(MoverMemory),
}

/// The calls that made a navigator's state since construction, which pickle replays: every
/// added obstacle, every scan that changed the obstacles, and of the commands the last one
/// before each of those and at the end, and every one that lifted the dynamic law's discovery
/// speed (a recovery out of a margin band, or the first command after one the mover filter
/// changed), with the movers in force at each. `Navigator`'s state is the known obstacles, the
/// movers, the discovery speed, the last commanded state and the mover memory
/// (`Navigator::mover_memory`: whether the filter changed the last command, and the deadlock
/// rule's memory, KeepRight: how long the robot has been held slow, how long it still turns;
/// docs/movers.md §7): this log determines them all (a scan that changed nothing is not kept,
/// and with it the free space it showed, which later fits leave out). `FloorNavigator` also
/// remembers the hold's escapes, which the log does not determine: pickle stores them apart
/// (`("escapes", …)`, `FloorNavigator::escape_memory`).
///
/// Why the filter's commands are not kept (they were until 2026-12-07, so that a robot held by
/// movers for an hour pickled an hour of commands): the mover memory is read from the Rust
/// navigator before and after each command, and set where the replay would not rebuild it
/// (`("mover-memory", …)`). A command the filter changed leaves only that memory besides what
/// any command leaves (the last state, and a lift of the discovery speed, which keeps the
/// command); so it is superseded by the next command as any other, and the memory it made is
/// set before the next command kept, if that one does not find it already (`replayed`).
/// Pickle puts the memory now last (`Navigator::__reduce__`) when it is not the default or
/// movers were set on a floor plan (whose replay is not exact: D16 in docs/known-limits.md).
/// A state pickled before this has no such entry and keeps every command the filter changed:
/// it replays as it did.
#[derive(Clone, Default)]
struct Log {
    events: Vec<Event>,
    /// Whether the last command must be replayed, not replaced by the next command: it
    /// lifted the discovery speed (or must be replayed for a reason of its own: acceleration
    /// limits, the goal latch; see [`State::pose`]).
    keep_last: bool,
    /// The mover memory a replay of `events` has after the last of them: the original's after
    /// each kept command (replayed from the memory it was made from).
    replayed: MoverMemory,
    /// `replayed` before the last command and the `MoverMemory` entry set for it, if any: what
    /// it is again once the next command supersedes that one.
    before_last: MoverMemory,
    /// Whether the last scan was refused (the navigator halts).
    halted: bool,
}

impl Log {
    /// The shapes of `add_obstacle`, in the order they were added.
    fn added(&self) -> impl Iterator<Item = &Shape> + '_ {
        self.events.iter().filter_map(|e| match e {
            Event::Add(shape) => Some(shape),
            _ => None,
        })
    }

    fn add(&mut self, shape: Shape) {
        self.events.push(Event::Add(shape));
        self.keep_last = false;
    }

    fn scan(&mut self, pose: Pose, scan: LaserScan) {
        self.events.push(Event::Scan(Box::new((pose, scan))));
        self.keep_last = false;
        self.halted = false;
    }

    /// A refused scan; one refusal after another keeps only the last.
    fn refused(&mut self, pose: Pose, scan: LaserScan) {
        let event = Event::Refused(Box::new((pose, scan)));
        match self.events.last_mut() {
            Some(last @ Event::Refused(..)) => *last = event,
            _ => self.events.push(event),
        }
        self.keep_last = false;
        self.halted = true;
    }

    /// Records the outcome of `observe_scan(pose, scan)`: a refusal, a change of the obstacles
    /// or the end of a halt.
    fn observed<T>(
        &mut self,
        pose: Pose,
        scan: LaserScan,
        result: &Result<T, NavError>,
        changed: impl Fn(&T) -> bool,
    ) {
        match result {
            Err(_) => self.refused(pose, scan),
            Ok(u) if changed(u) || self.halted => self.scan(pose, scan),
            Ok(_) => {}
        }
    }

    /// Whether `set_movers` was ever recorded (the list may since have been cleared).
    fn had_movers(&self) -> bool {
        self.events.iter().any(|e| matches!(e, Event::Movers(_)))
    }

    /// A successful `command` or `command_pose` (`event`), made from the mover memory
    /// `memory.0` and leaving `memory.1`; `keep`: it must be replayed, not superseded (it
    /// lifted the discovery speed, or a reason of the caller's). It supersedes the previous
    /// command unless that one must be replayed (`keep_last`), and with it the `set_movers`
    /// between them and the mover memory set for it: only the movers in force at each kept
    /// command are kept, and the memory it was made from is set before it when the replay
    /// would not have it.
    fn command(&mut self, event: Event, keep: bool, memory: (MoverMemory, MoverMemory)) {
        // The movers set since the last event that is not `set_movers`: the latest is in force.
        let mut latest = None;
        while let Some(Event::Movers(_)) = self.events.last() {
            if let Some(Event::Movers(m)) = self.events.pop() {
                latest.get_or_insert(m);
            }
        }
        if !self.keep_last
            && matches!(
                self.events.last(),
                Some(Event::Command(..) | Event::Pose(..))
            )
        {
            self.events.pop();
            if let Some(Event::MoverMemory(_)) = self.events.last() {
                self.events.pop();
            }
            self.replayed = self.before_last;
        }
        if let Some(latest) = latest {
            match self.events.last_mut() {
                // Set before the superseded command, and replaced since.
                Some(Event::Movers(m)) => *m = latest,
                _ => {
                    let in_force = self.events.iter().rev().find_map(|e| match e {
                        Event::Movers(m) => Some(m.as_slice()),
                        _ => None,
                    });
                    if !same_movers(in_force.unwrap_or_default(), &latest) {
                        self.events.push(Event::Movers(latest));
                    }
                }
            }
        }
        let (before, after) = memory;
        self.before_last = self.replayed;
        if !same_memory(&self.replayed, &before) {
            self.events.push(Event::MoverMemory(before));
        }
        self.events.push(event);
        self.replayed = after;
        self.keep_last = keep;
    }

    /// A successful `set_movers`: replaces the list set since the last other event.
    fn movers(&mut self, movers: Vec<RsMover>) {
        match self.events.last_mut() {
            Some(Event::Movers(m)) => *m = movers,
            _ => self.events.push(Event::Movers(movers)),
        }
    }

    /// A successful `set_goal_heading`: replaces the one set since the last other event.
    fn goal_heading(&mut self, yaw: Option<f64>) {
        let same = |g: &Option<f64>| g.map(f64::to_bits) == yaw.map(f64::to_bits);
        if !matches!(self.events.last(), Some(Event::GoalHeading(g)) if same(g)) {
            self.events.push(Event::GoalHeading(yaw));
        }
    }

    /// A successful `set_goal_tolerance`: recorded unless it repeats the entry just before it.
    ///
    /// Why a different value is not merged into the entry before it (as a repeated one is):
    /// a different value releases the goal latch (`Navigator::set_goal_stateful`) and the same
    /// one keeps it, so `xy = 0.3` then `xy = 0.1` after a latching command releases it, where
    /// a merged `xy = 0.1` alone would replay as the same value and keep it (the same for
    /// `set_goal_heading` and `stateful`).
    fn goal_tolerance(&mut self, t: GoalTolerance, stateful: bool) {
        let same = |xy: &f64, yaw: &f64, s: &bool| {
            xy.to_bits() == t.xy.to_bits() && yaw.to_bits() == t.yaw.to_bits() && *s == stateful
        };
        if !matches!(self.events.last(), Some(Event::GoalTolerance(xy, yaw, s)) if same(xy, yaw, s))
        {
            self.events
                .push(Event::GoalTolerance(t.xy, t.yaw, stateful));
        }
    }

    /// The log as pickle stores it: `("add", shape)`, `("command", x, v)`, `("pose", x, yaw)`,
    /// `("movers", [Mover, …])`, `("goal-heading", yaw or None)`, `("goal-tolerance", xy, yaw,
    /// stateful)`, `("mover-memory", slow, turning, yielded)` and `("scan", pose, ranges,
    /// angles)` entries.
    fn to_python<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let entries = self
            .events
            .iter()
            .map(|e| -> PyResult<Bound<'py, PyTuple>> {
                match e {
                    Event::Add(shape) => ("add", Bound::new(py, shape.clone())?).into_pyobject(py),
                    Event::Command(x, v) => ("command", *x, *v).into_pyobject(py),
                    Event::Pose(x, yaw) => ("pose", *x, *yaw).into_pyobject(py),
                    Event::GoalHeading(yaw) => ("goal-heading", *yaw).into_pyobject(py),
                    Event::GoalTolerance(xy, yaw, stateful) => {
                        ("goal-tolerance", *xy, *yaw, *stateful).into_pyobject(py)
                    }
                    Event::Escapes(m) => escapes_entry(py, m),
                    Event::MoverMemory(m) => mover_memory_entry(py, m),
                    Event::Movers(movers) => {
                        let movers = movers
                            .iter()
                            .map(|m| Bound::new(py, Mover::from_rs(*m)))
                            .collect::<PyResult<Vec<_>>>()?;
                        ("movers", movers).into_pyobject(py)
                    }
                    Event::Scan(b) | Event::Refused(b) => {
                        let (p, s) = b.as_ref();
                        (
                            if matches!(e, Event::Scan(_)) {
                                "scan"
                            } else {
                                "refused-scan"
                            },
                            [p.x, p.y, p.yaw],
                            s.ranges.clone(),
                            [s.angle_min, s.angle_increment, s.range_min, s.range_max],
                        )
                            .into_pyobject(py)
                    }
                }
            })
            .collect::<PyResult<Vec<_>>>()?;
        PyList::new(py, entries)
    }
}

/// The entries of a pickled state (`Log::to_python`), parsed before anything is replayed;
/// errors name `class` and the entry.
fn events(state: &Bound<'_, PyAny>, class: &str) -> PyResult<Vec<Event>> {
    state
        .try_iter()?
        .enumerate()
        .map(|(i, entry)| event(&entry?, i, class))
        .collect()
}

/// Every known obstacle in the navigator's order: the shapes of `add_obstacle` (their
/// indices `added`, their shapes as the log holds them, in the same order) and the perceived
/// ones (issue 56, D20: `obstacles` listed only the perceived).
fn known<'a>(
    added: impl Iterator<Item = usize>,
    log: &Log,
    perceived: impl Iterator<Item = (usize, &'a harmonav_rs::Perceived)>,
) -> Vec<Shape> {
    let mut all: Vec<(usize, Shape)> = added.zip(log.added().cloned()).collect();
    all.extend(perceived.map(|(i, p)| (i, from_perceived(p))));
    all.sort_by_key(|(i, _)| *i);
    all.into_iter().map(|(_, s)| s).collect()
}

/// The arguments of `observe_scan` as the Rust navigators take them: the sensor's pose (at
/// `position`, heading `heading` rad) and the scan (`ranges` any sequence of floats).
#[allow(clippy::too_many_arguments)]
fn scan_from(
    position: &Bound<'_, PyAny>,
    heading: f64,
    ranges: &Bound<'_, PyAny>,
    angle_min: f64,
    angle_increment: f64,
    range_max: f64,
    range_min: f64,
) -> PyResult<(Pose, LaserScan)> {
    let p = point_like(position, "position")?;
    // By dtype, as points: booleans and complex numbers are refused, not read as 1 m or
    // without their imaginary part.
    let ranges = reals_like(ranges, "ranges")?;
    let scan = LaserScan {
        angle_min,
        angle_increment,
        range_min,
        range_max,
        ranges,
    };
    Ok((Pose::new(p.x, p.y, heading), scan))
}

/// Whether two lists of movers are the same bit for bit (`==` would take `-0.0` for `0.0`,
/// which a replay must not).
fn same_movers(a: &[RsMover], b: &[RsMover]) -> bool {
    let bits = |m: &RsMover| {
        let share = match m.kind {
            MoverKind::Reciprocal { share } => share.to_bits(),
            _ => u64::MAX,
        };
        let velocity = m.velocity.map(|v| [v.x.to_bits(), v.y.to_bits()]);
        (
            [
                m.centre.x,
                m.centre.y,
                m.radius,
                m.speed_bound,
                m.position_error,
            ]
            .map(f64::to_bits),
            share,
            velocity,
        )
    };
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| bits(p) == bits(q))
}

/// Whether two mover memories are the same bit for bit (a replay must not take `-0.0` for
/// `0.0`).
fn same_memory(a: &MoverMemory, b: &MoverMemory) -> bool {
    a.slow.to_bits() == b.slow.to_bits()
        && a.turning.to_bits() == b.turning.to_bits()
        && a.yielded == b.yielded
}

/// `Θ`, or a `ValueError` when it is not finite.
fn finite_theta(theta: f64) -> PyResult<f64> {
    if theta.is_finite() {
        Ok(theta)
    } else {
        Err(value_error(format!("Θ is not finite here ({theta})")))
    }
}

impl State {
    /// A navigator as constructed from `built`. The Rust navigator checks every option against
    /// its range and every derived quantity (d_min, √(2μ/m), λ_c) for finiteness, naming the
    /// field.
    pub(crate) fn new(built: Built) -> PyResult<Self> {
        Ok(Self {
            inner: built.navigator().map_err(value_error)?,
            built,
            log: Log::default(),
            mode: Mode::Law,
            steer: None,
        })
    }

    /// The Python class of this world's navigator (for errors and `repr`).
    fn class(&self) -> &'static str {
        match self.inner {
            Inner::Star(_) => "Navigator",
            Inner::Floor(_) => "FloorNavigator",
        }
    }

    /// Adds an obstacle and records it.
    fn add(&mut self, shape: &Shape) -> Result<usize, NavError> {
        let i = each!(&mut self.inner, nav => nav.add_obstacle(shape.inner.clone()))?;
        self.log.add(shape.clone());
        Ok(i)
    }

    /// Observes a scan, and records it if it changed the obstacles.
    fn scan(&mut self, pose: Pose, scan: LaserScan) -> Result<RsScanUpdate, NavError> {
        let u = each!(&mut self.inner, nav => nav.observe_scan(pose, &scan));
        self.log.observed(pose, scan, &u, RsScanUpdate::changed);
        u
    }

    /// The command at `(x, v)`, and recorded. The Rust navigator refuses a non-finite command
    /// (`NavError::NonFiniteCommand`) and changes nothing on any error.
    fn issue(&mut self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Vector2<f64>, NavError> {
        let (c, lifted, memory) = each!(&mut self.inner, nav => {
            let (before, was) = (nav.discovery_speed(), nav.mover_memory());
            let c = nav.command(x, v)?;
            let lifted = nav.discovery_speed().to_bits() != before.to_bits();
            (c, lifted, (was, nav.mover_memory()))
        });
        self.mode = c.mode;
        self.steer = None;
        let event = Event::Command([x.x, x.y], [v.x, v.y]);
        self.log.command(event, lifted, memory);
        Ok(c.value)
    }

    /// The differential-drive command at the pose `(x, yaw)`, and recorded; a holonomic base's
    /// navigator refuses it, naming `base` (the Rust message would speak of the law).
    fn pose(&mut self, x: Vector2<f64>, yaw: f64) -> PyResult<PoseCommand> {
        if self.built.options.base == Base::Holonomic {
            return Err(value_error(
                "`base`: command_pose needs a differential-drive navigator (base=\"diff\" with \
                 v_max and omega_max); this one is holonomic: use command",
            ));
        }
        let (c, lifted, latched, memory) = each!(&mut self.inner, nav => {
            let (before, was, memory) =
                (nav.discovery_speed(), nav.goal_latched(), nav.mover_memory());
            let c = nav.command_pose(x, yaw).map_err(value_error)?;
            let lifted = nav.discovery_speed().to_bits() != before.to_bits();
            (c, lifted, nav.goal_latched() && !was, (memory, nav.mover_memory()))
        });
        self.mode = c.mode;
        self.steer = Some(c.steer);
        let event = Event::Pose([x.x, x.y], yaw);
        // Under acceleration limits each command counts from the last: every one is replayed
        // (the log grows with them). The command
        // that latched the goal's position tolerance (`Navigator::goal_latched`) is replayed
        // too, so that a copy is latched: the later ones, wherever their poses, turn in place.
        let limited = matches!(self.built.options.base, Base::Diff { accel: Some(_), .. });
        self.log
            .command(event, lifted || limited || latched, memory);
        Ok(c)
    }

    /// Sets the goal yaw of a differential-drive base, and records it; the Rust navigator
    /// refuses a non-finite one and changes nothing.
    fn set_goal_heading(&mut self, yaw: Option<f64>) -> Result<(), NavError> {
        each!(&mut self.inner, nav => nav.set_goal_heading(yaw))?;
        self.log.goal_heading(yaw);
        Ok(())
    }

    /// Sets where a goal with a yaw has arrived and whether its radius latches, and records
    /// them; the Rust navigator refuses a bound that is not finite and positive and changes
    /// nothing.
    fn set_goal_tolerance(&mut self, t: GoalTolerance, stateful: bool) -> Result<(), NavError> {
        each!(&mut self.inner, nav => {
            nav.set_goal_tolerance(t)?;
            nav.set_goal_stateful(stateful);
        });
        self.log.goal_tolerance(t, stateful);
        Ok(())
    }

    /// Replaces the movers, and records them.
    fn set_movers(&mut self, movers: Vec<RsMover>) -> Result<(), NavError> {
        each!(&mut self.inner, nav => nav.set_movers(&movers))?;
        self.log.movers(movers);
        Ok(())
    }

    /// Replays `events` (a pickled state) on this state, a fresh one: each call must do what
    /// it did (a refused scan must be refused again).
    fn replay(&mut self, events: Vec<Event>) -> PyResult<()> {
        let class = self.class();
        let mut escapes = None;
        for (i, e) in events.into_iter().enumerate() {
            let replayed = match e {
                Event::Add(shape) => self.add(&shape).map(drop),
                Event::Command(x, v) => self.issue(Vector2::from(x), Vector2::from(v)).map(drop),
                Event::Pose(x, yaw) => match self.pose(Vector2::from(x), yaw) {
                    Ok(_) => Ok(()),
                    Err(e) => {
                        return Err(value_error(format!("{class} state, entry {i}: {e}")));
                    }
                },
                Event::Movers(movers) => self.set_movers(movers),
                Event::GoalHeading(yaw) => self.set_goal_heading(yaw),
                Event::GoalTolerance(xy, yaw, stateful) => {
                    self.set_goal_tolerance(GoalTolerance { xy, yaw }, stateful)
                }
                Event::Scan(b) => {
                    let (pose, scan) = *b;
                    self.scan(pose, scan).map(drop)
                }
                Event::Refused(b) => {
                    let (pose, scan) = *b;
                    if self.scan(pose, scan).is_ok() {
                        return Err(value_error(format!(
                            "{class} state, entry {i}: a refused scan was accepted"
                        )));
                    }
                    Ok(())
                }
                // Where it stands: before the kept command made from it, or last (the memory
                // now, after every call).
                Event::MoverMemory(memory) => {
                    each!(&mut self.inner, nav => nav.set_mover_memory(memory))
                }
                Event::Escapes(memory) => {
                    if matches!(self.inner, Inner::Star(_)) {
                        return Err(value_error(format!(
                            "{class} state, entry {i}: a star world's navigator has no escapes"
                        )));
                    }
                    if escapes.is_some() {
                        return Err(value_error(format!(
                            "{class} state, entry {i}: a second escape memory"
                        )));
                    }
                    escapes = Some((i, memory));
                    Ok(())
                }
            };
            replayed.map_err(|e| value_error(format!("{class} state, entry {i}: {e}")))?;
        }
        // The escape memory after every call: the calls' own commands leave one of their own.
        if let (Some((i, memory)), Inner::Floor(nav)) = (escapes, &mut self.inner) {
            nav.set_escape_memory(memory)
                .map_err(|e| value_error(format!("{class} state, entry {i}: {e}")))?;
        }
        Ok(())
    }
}

impl Navigator {
    /// The state, locked (see [`lock`]).
    fn state(&self, py: Python<'_>) -> std::sync::MutexGuard<'_, State> {
        lock(py, &self.state)
    }

    /// A navigator holding `state`.
    pub(crate) fn holding(state: State) -> Self {
        Self {
            state: Mutex::new(state),
        }
    }

    /// An independent navigator with the same obstacles and state (`__copy__`).
    pub(crate) fn copied(&self, py: Python<'_>) -> Self {
        Self::holding(self.state(py).clone())
    }

    /// `f` of the floor plan's Rust navigator; a `TypeError` on a star world's (a guard: a
    /// `FloorNavigator` is always built on a floor plan).
    pub(crate) fn floor<R>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&RsFloorNavigator) -> R,
    ) -> PyResult<R> {
        match &self.state(py).inner {
            Inner::Floor(nav) => Ok(f(nav)),
            Inner::Star(_) => Err(PyTypeError::new_err(
                "a star world's navigator has no floor plan (walls, δ, elements, escapes)",
            )),
        }
    }
}

/// A floor navigator's escape memory as pickle stores it: `("escapes", level or None, early,
/// early_level or None, count, [x, y] or None, periods)`.
fn escapes_entry<'py>(py: Python<'py>, m: &EscapeMemory) -> PyResult<Bound<'py, PyTuple>> {
    let (level, early) = match m.escape {
        Some((level, early)) => (Some(level), early),
        None => (None, false),
    };
    let (anchor, periods) = match m.anchor {
        Some((a, n)) => (Some([a.x, a.y]), n),
        None => (None, 0),
    };
    (
        "escapes",
        level,
        early,
        m.early_level,
        m.escapes,
        anchor,
        periods,
    )
        .into_pyobject(py)
}

/// A navigator's mover memory as pickle stores it: `("mover-memory", slow, turning,
/// yielded)` (`Navigator::mover_memory`; seconds, seconds, bool).
fn mover_memory_entry<'py>(py: Python<'py>, m: &MoverMemory) -> PyResult<Bound<'py, PyTuple>> {
    ("mover-memory", m.slow, m.turning, m.yielded).into_pyobject(py)
}

/// One entry of a pickled state of a `class` navigator, parsed.
fn event(entry: &Bound<'_, PyAny>, i: usize, class: &str) -> PyResult<Event> {
    let bad = |problem: String| {
        PyTypeError::new_err(format!(
            "{class} state, entry {i}: {problem}; expected (\"add\", Shape), \
             (\"command\", [x, y], [vx, vy]), (\"pose\", [x, y], yaw), (\"movers\", \
             [Mover, …]), (\"goal-heading\", yaw or None), (\"goal-tolerance\", xy, yaw[, stateful]), (\"scan\", [x, y, yaw], ranges, [angle_min, angle_increment, \
             range_min, range_max]), (\"mover-memory\", slow, turning, yielded) or \
             (\"escapes\", level or None, early, early_level or None, count, [x, y] or None, \
             periods)"
        ))
    };
    let parts = entry
        .extract::<Vec<Bound<'_, PyAny>>>()
        .map_err(|e| bad(e.to_string()))?;
    let kind: String = match parts.first() {
        Some(k) => k.extract::<String>().map_err(|e| bad(e.to_string()))?,
        None => return Err(bad("an empty entry".into())),
    };
    match (kind.as_str(), parts.as_slice()) {
        ("add", [_, shape]) => Ok(Event::Add(
            shape
                .extract::<PyRef<'_, Shape>>()
                .map_err(|e| bad(e.to_string()))?
                .clone(),
        )),
        ("command", [_, x, v]) => {
            let x = point_like(x, "x")?;
            let v = point_like(v, "v")?;
            Ok(Event::Command([x.x, x.y], [v.x, v.y]))
        }
        ("pose", [_, x, yaw]) => {
            let x = point_like(x, "x")?;
            let yaw = yaw.extract::<f64>().map_err(|e| bad(e.to_string()))?;
            Ok(Event::Pose([x.x, x.y], yaw))
        }
        ("movers", [_, movers]) => Ok(Event::Movers(movers_from(movers)?)),
        // Checked where it is set (`Navigator::set_mover_memory`: a `ValueError` naming the
        // field).
        ("mover-memory", [_, slow, turning, yielded]) => {
            let get = |e: PyErr| bad(e.to_string());
            Ok(Event::MoverMemory(MoverMemory {
                slow: slow.extract::<f64>().map_err(get)?,
                turning: turning.extract::<f64>().map_err(get)?,
                yielded: yielded.extract::<bool>().map_err(get)?,
            }))
        }
        ("escapes", [_, level, early, early_level, count, anchor, periods]) => {
            let get = |e: PyErr| bad(e.to_string());
            // Every slot of its type, whether or not it is read.
            let early = early.extract::<bool>().map_err(get)?;
            let periods = periods.extract::<usize>().map_err(get)?;
            let escape = level
                .extract::<Option<f64>>()
                .map_err(get)?
                .map(|level| (level, early));
            let anchor = anchor
                .extract::<Option<[f64; 2]>>()
                .map_err(get)?
                .map(|[x, y]| (Vector2::new(x, y), periods));
            Ok(Event::Escapes(EscapeMemory {
                escape,
                early_level: early_level.extract::<Option<f64>>().map_err(get)?,
                escapes: count.extract::<usize>().map_err(get)?,
                anchor,
            }))
        }
        ("goal-heading", [_, yaw]) => Ok(Event::GoalHeading(
            yaw.extract::<Option<f64>>()
                .map_err(|e| bad(e.to_string()))?,
        )),
        // Without `stateful` (a state pickled before 2026-12-07, when the radius did not
        // latch): unlatched, so that it replays as it did.
        ("goal-tolerance", [_, xy, yaw]) => {
            let get = |v: &Bound<'_, PyAny>| v.extract::<f64>().map_err(|e| bad(e.to_string()));
            Ok(Event::GoalTolerance(get(xy)?, get(yaw)?, false))
        }
        ("goal-tolerance", [_, xy, yaw, stateful]) => {
            let get = |v: &Bound<'_, PyAny>| v.extract::<f64>().map_err(|e| bad(e.to_string()));
            let stateful = stateful.extract::<bool>().map_err(|e| bad(e.to_string()))?;
            Ok(Event::GoalTolerance(get(xy)?, get(yaw)?, stateful))
        }
        (tag @ ("scan" | "refused-scan"), [_, pose, ranges, angles]) => {
            let [x, y, yaw] = pose.extract::<[f64; 3]>().map_err(|e| bad(e.to_string()))?;
            let ranges = ranges
                .extract::<Vec<f64>>()
                .map_err(|e| bad(e.to_string()))?;
            let [angle_min, angle_increment, range_min, range_max] =
                angles
                    .extract::<[f64; 4]>()
                    .map_err(|e| bad(e.to_string()))?;
            let b = Box::new((
                Pose::new(x, y, yaw),
                LaserScan {
                    angle_min,
                    angle_increment,
                    range_min,
                    range_max,
                    ranges,
                },
            ));
            Ok(if tag == "scan" {
                Event::Scan(b)
            } else {
                Event::Refused(b)
            })
        }
        _ => Err(bad(format!("got \"{kind}\" with {} values", parts.len()))),
    }
}

#[pymethods]
impl Navigator {
    /// A navigator in the star world bounded by `boundary`, towards `goal`; the options after
    /// `goal` may also be given in this order ([`crate::options::NAMES`]).
    #[new]
    #[pyo3(
        signature = (boundary, goal, *options, **keywords),
        text_signature = "(boundary, goal, law='kinematic', gain=1.0, mass=1.0, mu=10.0, \
                          sensor=(1.0, 60.0), radius=0.0, margin=0.0, k='auto', \
                          damping='governed', rho_min=0.05, control_period=None, hold='auto', \
                          speed='auto', v_max=None, range_noise=0.02, max_obstacle_depth=1.0, \
                          growth_threshold=0.02, fit_range=None, free_memory=16, \
                          base='holonomic', omega_max=None, a_max=None, alpha_max=None, \
                          force_bound=None, comfort=0.0)"
    )]
    fn new(
        boundary: &Shape,
        goal: &Bound<'_, PyAny>,
        options: &Bound<'_, PyTuple>,
        keywords: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let keywords = Keywords::parse("Navigator", options, keywords)?;
        let goal = point_like(goal, "goal")?;
        let (law, options) = keywords.check()?;
        let built = Built {
            workspace: Workspace::Star(boundary.clone()),
            goal,
            keywords,
            law,
            options,
        };
        Ok(Self::holding(State::new(built)?))
    }

    /// Adds a newly sensed obstacle (its true shape; grown by `radius + margin` here) and
    /// returns its index. `k`, `Θ` and the damping state update (on a floor plan without a new
    /// solve). In a star world a shape that reaches the boundary joins it (furniture against a
    /// wall, docs/maths/12-range-scans.md §12.21). Raises `ValueError` (and changes nothing)
    /// if it overlaps a known obstacle, reaches the boundary and cannot join it (the goal or the
    /// robot behind it; on a floor plan, its boundary layer), or contains the goal or the
    /// robot.
    fn add_obstacle(&self, py: Python<'_>, shape: &Shape) -> PyResult<usize> {
        self.state(py).add(shape).map_err(value_error)
    }

    /// The command to hold for `control_period` at position `x` with velocity `v` (default 0),
    /// each an array-like `[x, y]`: a velocity (kinematic law) or a force (dynamic law), as a
    /// (2,) array, always finite; `mode` then says how it was formed. Inside the margin band
    /// (or a floor plan's boundary layer) it leads back out (`mode == "recovering"`). Raises
    /// `ValueError` (and changes nothing) where the robot's disc overlaps a known obstacle or
    /// the boundary (a wall), for non-finite input, or for a command that would not be finite.
    #[pyo3(signature = (x, v=None))]
    fn command<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        v: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = point_like(x, "x")?;
        let v = v.map_or(Ok(Vector2::zeros()), |v| point_like(v, "v"))?;
        // With the GIL held: one evaluation, tens of µs.
        let c = self.state(py).issue(x, v).map_err(value_error)?;
        array1(py, &[c.x, c.y], "command")
    }

    /// The `(v, omega)` to hold for `control_period` at the pose `(position, yaw)` of a
    /// differential-drive robot (`base="diff"`; `position` array-like `[x, y]`, `yaw` its heading,
    /// rad): forward speed `0 ≤ v ≤ v_max` (m/s) and turn rate `|omega| ≤ omega_max` (rad/s) by
    /// aligned descent, the arc they sweep over the period certified free (`docs/unicycle.md`).
    /// `mode` then says how the held direction was formed, `steer` how `(v, omega)` was
    /// (`"ahead"`, `"shortened"`, `"turning"`, `"stopped"`, `"braking"`; with a goal heading
    /// `"to-goal-heading"` and `"arrived"`, `set_goal_heading`). Raises `ValueError` (and changes
    /// nothing) on a holonomic navigator (naming `base`), for a non-finite pose, and where
    /// `command` would.
    fn command_pose(
        &self,
        py: Python<'_>,
        position: &Bound<'_, PyAny>,
        yaw: f64,
    ) -> PyResult<(f64, f64)> {
        let x = point_like(position, "position")?;
        let c = self.state(py).pose(x, yaw)?;
        Ok((c.v, c.omega))
    }

    /// Sets the goal yaw (rad, map frame) a differential-drive robot finishes at, or clears it
    /// (`None`, the default: `command_pose` as without, bit for bit). Once the position is
    /// within 1 cm of the goal (`harmonav::tuning::GOAL_ARRIVAL`; `set_goal_tolerance`), `command_pose`
    /// turns in place, `v = 0`, `omega = clamp(k·wrap(yaw − θ), ±omega_max)` within the
    /// acceleration limits (`steer == "to-goal-heading"`), until the heading is within 1e-3 rad
    /// of it (`set_goal_tolerance`), then returns
    /// `(0, 0)` (`steer == "arrived"`); docs/unicycle.md section 3.5. A non-finite yaw is a
    /// `ValueError` naming `goal_yaw`, the navigator unchanged. Pickled with the navigator.
    #[pyo3(signature = (yaw))]
    fn set_goal_heading(&self, py: Python<'_>, yaw: Option<f64>) -> PyResult<()> {
        self.state(py).set_goal_heading(yaw).map_err(value_error)
    }

    /// The goal yaw of `set_goal_heading`, rad; `None` without one.
    #[getter]
    fn goal_heading(&self, py: Python<'_>) -> Option<f64> {
        each!(&self.state(py).inner, nav => nav.goal_heading())
    }

    /// Sets where a goal with a yaw (`set_goal_heading`) has arrived: the turn in place begins
    /// within `xy` m of the goal and ends within `yaw` rad of the goal yaw (Nav2's
    /// `xy_goal_tolerance` and `yaw_goal_tolerance`; the defaults 0.01 m and 1e-3 rad,
    /// `harmonav::GoalTolerance`); a bound not given keeps its value. `stateful` (Nav2's goal
    /// checker's, default True, `Navigator::set_goal_stateful`): once a pose within `xy` has
    /// been commanded, the robot only brakes (under acceleration limits) and turns in place
    /// until within `yaw`, wherever it rolls, never driving back (`goal_latched`); False
    /// decides at each command. Turning in place is safe anywhere, so no tolerance weakens a
    /// certificate against the known shapes. A bound that is not finite and positive is a
    /// `ValueError` naming `xy_goal_tolerance` or `yaw_goal_tolerance`, the navigator
    /// unchanged. Pickled with the navigator (the command that latched is replayed).
    #[pyo3(signature = (xy=None, yaw=None, stateful=None))]
    fn set_goal_tolerance(
        &self,
        py: Python<'_>,
        xy: Option<f64>,
        yaw: Option<f64>,
        stateful: Option<bool>,
    ) -> PyResult<()> {
        let mut state = self.state(py);
        let (now, was) = each!(&state.inner, nav => (nav.goal_tolerance(), nav.goal_stateful()));
        let t = GoalTolerance {
            xy: xy.unwrap_or(now.xy),
            yaw: yaw.unwrap_or(now.yaw),
        };
        state
            .set_goal_tolerance(t, stateful.unwrap_or(was))
            .map_err(value_error)
    }

    /// Whether the goal's position tolerance latches (`set_goal_tolerance(stateful=…)`).
    #[getter]
    fn goal_stateful(&self, py: Python<'_>) -> bool {
        each!(&self.state(py).inner, nav => nav.goal_stateful())
    }

    /// Whether the goal's position tolerance is latched: a pose within `xy` of the goal has
    /// been commanded (`command_pose`, with a goal yaw) since the goal yaw or the tolerance
    /// last changed; from then on the robot only brakes and turns in place.
    #[getter]
    fn goal_latched(&self, py: Python<'_>) -> bool {
        each!(&self.state(py).inner, nav => nav.goal_latched())
    }

    /// `(xy, yaw)` of `set_goal_tolerance`: m and rad.
    #[getter]
    fn goal_tolerance(&self, py: Python<'_>) -> (f64, f64) {
        let t = each!(&self.state(py).inner, nav => nav.goal_tolerance());
        (t.xy, t.yaw)
    }

    /// Replaces the movers (issue 54, `docs/movers.md`): a list of `Mover` (or of dicts with
    /// its argument names as keys), reported afresh every period; `[]` clears them. From the
    /// next command on, the held command is filtered last against every place a mover can
    /// reach within the period: unchanged when it keeps out of them all (bit for bit the
    /// command without movers), else the closest certified command (`mode == "yielding"`),
    /// else the least violation, not certified (`mode == "overwhelmed"`, `certified` False).
    /// All or nothing: an invalid mover is a `ValueError` naming `movers[i].field` and the
    /// navigator keeps its movers. A command where the robot's disc overlaps a mover's as
    /// reported is a `ValueError`, as inside an obstacle.
    ///
    /// With `base="diff"`, `command_pose` steers by the filtered direction, but its `(v, omega)`
    /// arc is certified against the static world only, not against the movers.
    fn set_movers(&self, py: Python<'_>, movers: &Bound<'_, PyAny>) -> PyResult<()> {
        let movers = movers_from(movers)?;
        self.state(py).set_movers(movers).map_err(value_error)
    }

    /// The movers of the last `set_movers`, as `Mover`s.
    #[getter]
    fn movers(&self, py: Python<'_>) -> Vec<Mover> {
        each!(&self.state(py).inner, nav => nav.movers().iter().map(|m| Mover::from_rs(*m)).collect())
    }

    /// Whether the last command is certified to keep the robot clear over the period: False
    /// only when it could not be certified against a mover (`mode == "overwhelmed"`), or a
    /// force-bounded robot's way to rest could not be (`mode == "braking"`).
    #[getter]
    fn certified(&self, py: Python<'_>) -> bool {
        self.state(py).mode.certified()
    }

    /// How the last `command_pose` formed `(v, omega)`: `"ahead"` (aligned descent as it is),
    /// `"shortened"` (the arc hold shortened `v`), `"turning"` (`v = 0`, turning in place),
    /// `"stopped"`, `"braking"` (acceleration limits), `"to-goal-heading"` (at the goal,
    /// turning to the goal yaw) or `"arrived"` (at the goal yaw); `None` before the first and
    /// after a `command`.
    #[getter]
    fn steer(&self, py: Python<'_>) -> Option<&'static str> {
        self.state(py).steer.as_ref().map(Steer::as_str)
    }

    /// `"holonomic"` (commanded by `command`) or `"diff"` (by `command_pose`).
    #[getter]
    fn base(&self, py: Python<'_>) -> &'static str {
        self.state(py).built.options.base.as_str()
    }

    /// A differential-drive base's top turn rate, rad/s; `None` for a holonomic one.
    #[getter]
    fn omega_max(&self, py: Python<'_>) -> Option<f64> {
        match self.state(py).built.options.base {
            Base::Diff { omega_max, .. } => Some(omega_max),
            _ => None,
        }
    }

    /// A differential-drive base's acceleration limits `(a_max, alpha_max)`, m/s² and rad/s²;
    /// `None` without them (or for a holonomic base).
    #[getter]
    fn accel(&self, py: Python<'_>) -> Option<(f64, f64)> {
        match self.state(py).built.options.base {
            Base::Diff { accel: Some(a), .. } => Some((a.a_max, a.alpha_max)),
            _ => None,
        }
    }

    /// The dynamic law's force bound `F`, N (`force_bound=`, docs/movers.md §2); `None`
    /// without one.
    #[getter]
    fn force_bound(&self, py: Python<'_>) -> Option<f64> {
        self.state(py).built.options.force_bound
    }

    /// The comfort distance from non-cooperative movers, m (`comfort=`, docs/movers.md §7); 0
    /// for none.
    #[getter]
    fn comfort(&self, py: Python<'_>) -> f64 {
        self.state(py).built.options.comfort
    }

    /// Observes one range scan (the fields of `sensor_msgs/LaserScan`) taken at `position`
    /// (array-like `[x, y]`, the robot's centre) with `heading` (rad, the scan's angle 0):
    /// `ranges` (m, a 1-D array-like of real numbers: booleans and complex numbers are a
    /// `TypeError`, as for points; NaN, ±inf and out-of-range readings are classified as ROS
    /// does), `angle_min` and `angle_increment` (rad, increment > 0),
    /// `range_max` and `range_min` (m). Hits explained by known shapes (or a floor plan's
    /// walls, within the noise bound) are dropped, the rest fitted to conservative stars that
    /// grow known ones or are added (`docs/maths.md` §12.6). Returns a `ScanUpdate`. Raises
    /// `ValueError` (and changes nothing) for an invalid scan or pose, or when a new or grown
    /// shape would contain the robot or the goal, cross the boundary (reach the boundary
    /// layer), or overlap another ("the world as perceived is not a star world").
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
        let state: &mut State = &mut guard;
        let u = py.detach(|| state.scan(pose, scan));
        drop(guard);
        Ok(ScanUpdate::from(u.map_err(value_error)?))
    }

    /// The perceived shapes (from scans, not grown), as `(index, Shape)` pairs: `index` among
    /// the navigator's obstacles, the shape a `star` with `signed_distance` and `contains`.
    #[getter]
    fn perceived(&self, py: Python<'_>) -> Vec<(usize, Shape)> {
        each!(&self.state(py).inner, nav => {
            nav.perceived().map(|(i, p)| (i, from_perceived(p))).collect()
        })
    }

    /// Every known obstacle (not grown) in the navigator's order: the shapes given to
    /// `add_obstacle` as given, and the perceived ones (`perceived`, from scans) as `star`
    /// shapes with `signed_distance` and `contains`.
    #[getter]
    fn obstacles(&self, py: Python<'_>) -> Vec<Shape> {
        let state = self.state(py);
        each!(&state.inner, nav => {
            known(nav.added().map(|(i, _)| i), &state.log, nav.perceived())
        })
    }

    /// `Θ(x)` over the known obstacles (and a floor plan's walls): finite, or `ValueError` as
    /// `command` (on a floor plan also outside the certified region).
    fn theta(&self, py: Python<'_>, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        let x = point_like(x, "x")?;
        let theta = each!(&self.state(py).inner, nav => nav.theta(x));
        finite_theta(theta.map_err(value_error)?)
    }

    /// `k` of `φ_k` for the obstacles known so far (on a floor plan: the holes and the known
    /// obstacles, under the `k` policy).
    #[getter]
    fn k(&self, py: Python<'_>) -> f64 {
        each!(&self.state(py).inner, nav => nav.k())
    }

    /// The indices (among `obstacles`) of the obstacles that joined the workspace's boundary
    /// or a floor plan's walls: furniture against a wall, whose gap to the wall is closed (on
    /// a floor plan the harmonic map is solved again). Sorted; empty while none did.
    #[getter]
    fn joined(&self, py: Python<'_>) -> Vec<usize> {
        each!(&self.state(py).inner, nav => nav.joined().to_vec())
    }

    /// How many obstacles are known.
    #[getter]
    fn obstacle_count(&self, py: Python<'_>) -> usize {
        match &self.state(py).inner {
            Inner::Star(nav) => nav.obstacles().len(),
            Inner::Floor(nav) => nav.added().count() + nav.perceived().count(),
        }
    }

    /// The goal, as a (2,) array.
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let g = each!(&self.state(py).inner, nav => nav.goal());
        array1(py, &[g.x, g.y], "goal")
    }

    /// `√(2μ/m)` for the dynamic law (finite), `None` for the kinematic one.
    #[getter]
    fn speed_bound(&self, py: Python<'_>) -> Option<f64> {
        each!(&self.state(py).inner, nav => nav.speed_bound())
    }

    /// How the last command was formed: `"law"`, `"capped"` (shortened to be safe to hold),
    /// `"recovering"` (out of the margin band or a floor plan's boundary layer), `"from-rest"`
    /// (the kinematic law's step had come to rest away from the goal, at a saddle of `Θ` or in
    /// a narrow valley: the steepest certified descent among 16 directions instead),
    /// `"escaping"` (on a floor plan, along the shortest path from a rest point of the hold),
    /// `"halted"` (the last `observe_scan` was refused: the robot stops until a scan is
    /// accepted), `"yielding"` (the mover filter changed it, certified) or `"overwhelmed"` (no
    /// command keeps out of every mover's reach: the least violation, not certified); `"law"`
    /// before the first.
    #[getter]
    fn mode(&self, py: Python<'_>) -> &'static str {
        self.state(py).mode.as_str()
    }

    /// The control period in force, s.
    #[getter]
    fn control_period(&self, py: Python<'_>) -> f64 {
        each!(&self.state(py).inner, nav => nav.control_period())
    }

    /// The certified clearance at `x`: a lower bound on the distance to the nearest known
    /// grown obstacle and to the shrunk boundary (on a floor plan: to the boundary layer,
    /// `sd(x) − δ`), m (what the hold keeps each step within).
    fn clearance(&self, py: Python<'_>, x: &Bound<'_, PyAny>) -> PyResult<f64> {
        let x = point_like(x, "x")?;
        Ok(each!(&self.state(py).inner, nav => nav.clearance(x)))
    }

    /// Pickle support. A star world's navigator: `(Navigator, constructor arguments, state)`;
    /// a floor plan's: `(functools.partial(FloorNavigator, **keywords), (outer, goal, holes),
    /// state)`, the true walls as rings however it was made (from rings or from a map), the
    /// map solved again on unpickling (from the same rings: the same map). The state is the
    /// list of calls that made it (`("add", shape)`, `("command", x, v)`, `("pose", x, yaw)`,
    /// `("movers", [Mover, …])`, `("scan", …)`), replayed by `__setstate__`, on a floor plan
    /// its escape memory first (`("escapes", …)`, taken back after every call), which the
    /// calls do not determine, and the mover memory (`("mover-memory", slow, turning,
    /// yielded)`, `Navigator::mover_memory`) where the kept calls do not rebuild it: last (the
    /// memory now, set after every call) and before a kept command made from another (`Log`
    /// in python/src/navigator.rs). A state without it (pickled before 2026-12-07, with every command the filter
    /// changed) replays as it did.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>, Bound<'py, PyList>)> {
        let py = slf.py();
        // Copied out under the lock, turned into Python objects after it.
        let (built, log, escapes, memory) = {
            let s = slf.get().state(py);
            let escapes = match &s.inner {
                Inner::Floor(nav) => Some(nav.escape_memory()),
                Inner::Star(_) => None,
            };
            let memory = each!(&s.inner, nav => nav.mover_memory());
            (s.built.clone(), s.log.clone(), escapes, memory)
        };
        let goal = [built.goal.x, built.goal.y];
        let class = slf.get_type().into_any();
        let (call, args) = match &built.workspace {
            Workspace::Star(boundary) => {
                let mut args = vec![
                    Bound::new(py, boundary.clone())?.into_any(),
                    goal.into_pyobject(py)?.into_any(),
                ];
                args.extend(built.keywords.values(py)?);
                (class, PyTuple::new(py, args)?)
            }
            Workspace::Floor { map, keywords, .. } => {
                let walls = map.walls();
                let ring = |r: &[Vector2<f64>]| r.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>();
                let holes: Vec<Vec<[f64; 2]>> = walls.holes().iter().map(|h| ring(h)).collect();
                let named = built.keywords.to_dict(py)?;
                keywords.add_to(&named)?;
                let partial = py
                    .import("functools")?
                    .getattr("partial")?
                    .call((class,), Some(&named))?;
                (
                    partial,
                    (ring(walls.outer()), goal, holes).into_pyobject(py)?,
                )
            }
        };
        let state = log.to_python(py)?;
        if let Some(m) = escapes {
            state.insert(0, escapes_entry(py, &m)?)?;
        }
        // The memory now, set after every call: a star world's replay rebuilds the default
        // exactly; a floor plan's, among movers, may not (its escape memory is set last).
        let floor_among_movers = escapes.is_some() && log.had_movers();
        if !same_memory(&memory, &MoverMemory::default()) || floor_among_movers {
            state.append(mover_memory_entry(py, &memory)?)?;
        }
        Ok((call, args, state))
    }

    /// Restores a pickled state: the navigator as constructed (a floor plan's on the same map,
    /// not solved again) with `state` replayed. Raises `ValueError` or `TypeError` (and changes
    /// nothing) for a state that does not replay.
    fn __setstate__(&self, py: Python<'_>, state: &Bound<'_, PyAny>) -> PyResult<()> {
        let (built, class) = {
            let s = self.state(py);
            (s.built.clone(), s.class())
        };
        let events = events(state, class)?;
        let fresh = py.detach(|| {
            let mut fresh = State::new(built)?;
            fresh.replay(events)?;
            Ok::<_, PyErr>(fresh)
        })?;
        *self.state(py) = fresh;
        Ok(())
    }

    /// An independent navigator with the same obstacles and state (not shared: changing
    /// either leaves the other as it was; a floor plan's solved map is shared, it never
    /// changes).
    fn __copy__(&self, py: Python<'_>) -> Self {
        self.copied(py)
    }

    /// As `__copy__`; `memo` is unused (a navigator holds no Python objects).
    fn __deepcopy__(&self, py: Python<'_>, _memo: &Bound<'_, PyAny>) -> Self {
        self.copied(py)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        match &self.state(py).inner {
            Inner::Star(nav) => format!(
                "Navigator({} obstacles known, k={})",
                nav.obstacles().len(),
                nav.k()
            ),
            Inner::Floor(nav) => format!(
                "FloorNavigator(δ = {} m, {} perceived obstacles, k={})",
                nav.field().floor().delta(),
                nav.perceived().count(),
                nav.k()
            ),
        }
    }
}

/// What one `Navigator.observe_scan` did (indices among the navigator's obstacles).
#[pyclass(module = "harmonav", frozen, get_all)]
#[derive(Clone, Debug)]
pub struct ScanUpdate {
    /// New obstacles (indices after the scan).
    added: Vec<usize>,
    /// Obstacles that grew (indices after the scan).
    grown: Vec<usize>,
    /// Obstacles merged into a grown one and removed (indices before the scan).
    absorbed: Vec<usize>,
    /// Returns in `[range_min, range_max)`.
    hits: usize,
    /// Hits explained by a known shape or the boundary.
    explained: usize,
    /// Segments no fit covers (wider than the depth prior).
    unfitted: usize,
    /// At an event: the distance from the robot's centre to the changed grown shapes, m.
    event_clearance: Option<f64>,
    /// Whether the obstacles changed (an event).
    changed: bool,
}

impl From<RsScanUpdate> for ScanUpdate {
    fn from(u: RsScanUpdate) -> Self {
        Self {
            changed: u.changed(),
            added: u.added,
            grown: u.grown,
            absorbed: u.absorbed,
            hits: u.hits,
            explained: u.explained,
            unfitted: u.unfitted,
            event_clearance: u.event_clearance,
        }
    }
}

#[pymethods]
impl ScanUpdate {
    fn __repr__(&self) -> String {
        format!(
            "ScanUpdate(added={:?}, grown={:?}, absorbed={:?}, hits={}, explained={})",
            self.added, self.grown, self.absorbed, self.hits, self.explained
        )
    }
}

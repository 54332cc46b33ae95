//! The judgement of a run: its [`Summary`] (`summary.json`), the [`Run`] with the kept
//! states, and why a run could not start ([`RunError`]).

use harmonav::NavError;
use harmonav_control::DampingPolicy;
use harmonav_field::FieldError;
use harmonav_field::KPolicy;
use harmonav_scenario::Model;
use serde::{Deserialize, Serialize, Serializer};

use crate::guarantee::{Guarantee, Kind};
use crate::outcome::Outcome;
use crate::trace::{Discovery, MoverFrame, Sample, ScanRecord};
use crate::warning::Warning;

/// Which integrator moves the robot.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Physics {
    /// The built-in adaptive integrator ([`crate::run::run`]).
    #[default]
    Builtin,
    /// rapier2d, cross-checked against a built-in run of the same model (`rapier::run_rapier`;
    /// needs the crate's feature `rapier`, else [`RunError::NoRapier`]).
    Rapier,
}

impl Physics {
    /// The name in the CLI, Python and `summary.json`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Builtin => "builtin",
            Self::Rapier => "rapier",
        }
    }
}

impl std::fmt::Display for Physics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::str::FromStr for Physics {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        [Self::Builtin, Self::Rapier]
            .into_iter()
            .find(|p| p.as_str() == s)
            .ok_or_else(|| format!("unknown physics \"{s}\": expected \"builtin\" or \"rapier\""))
    }
}

/// The summary of a run (`summary.json`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Scenario name.
    pub name: String,
    /// `kinematic` or `dynamic`.
    pub model: Model,
    /// The integrator that moved the robot (`"builtin"` or `"rapier"` in the file).
    pub physics: Physics,
    /// The `k` policy (by its name in the file: `"paper"` or `"auto"`).
    #[serde(serialize_with = "by_name")]
    pub k_policy: KPolicy,
    /// The damping policy of the dynamic law that ran (by its name; `None` for the
    /// kinematic model).
    #[serde(serialize_with = "by_name_if_any")]
    pub damping: Option<DampingPolicy>,
    /// Goal reached within tolerance and time.
    pub reached: bool,
    /// Time at the end of the run, s.
    pub time_s: f64,
    /// Distance to the goal at the end, m.
    pub final_distance: f64,
    /// Smallest clearance to the true obstacles and boundary (minus the robot radius), m.
    pub min_clearance: f64,
    /// The length of the recorded path (every state on the `sim.dt` grid and at the events),
    /// m.
    pub path_length: f64,
    /// Largest speed, m/s.
    pub max_speed: f64,
    /// `√(2μ/m)` for the dynamic model.
    pub speed_bound: Option<f64>,
    /// Recorded states in collision (clearance ≤ 0).
    pub collisions: usize,
    /// Contact events reported by the physics engine (rapier runs only).
    pub physics_contacts: Option<usize>,
    /// Discoveries in order.
    pub discoveries: Vec<Discovery>,
    /// The guarantee monitors.
    pub guarantees: Vec<Guarantee>,
    /// How the run ended.
    pub outcome: Outcome,
    /// What the verdict alone would not explain (a start on a symmetry axis, …): filled by
    /// [`crate::physics::simulate`], empty from [`crate::run::run`] alone (a sweep's many runs skip them).
    pub warnings: Vec<Warning>,
    /// States recorded (on the `sim.dt` grid and at the events), all of them judged and handed
    /// to the observer; [`Run::samples`] keeps at most [`crate::trajectory::MAX_KEPT_STATES`] of the grid ones.
    pub recorded_states: usize,
    /// Accepted integration steps.
    pub steps: usize,
    /// Rejected integration steps.
    pub rejected_steps: usize,
    /// What a lidar's perception did (`[sensor] type = "lidar"`; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub perception: Option<PerceptionReport>,
    /// What the file's movers did: the commands by mode, the contacts and the least mover
    /// clearance (`[[movers]]`; absent otherwise, so that a summary without movers is as
    /// before).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub movers: Option<crate::movers::MoverReport>,
    /// The other robots of a file with `[[robots]]` and the clearances between all of them
    /// (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fleet: Option<crate::movers::FleetReport>,
    /// What a differential drive did (`[robot] base = "diff"`): its commands by how they were
    /// formed, their extremes and the clearance along its arcs (absent for a holonomic robot).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diff: Option<crate::unicycle::DiffReport>,
}

impl Summary {
    /// Whether every guarantee held.
    pub fn all_passed(&self) -> bool {
        self.guarantees.iter().all(|g| g.passed)
    }

    /// Whether the run was safe: every guarantee but arrival held (no collision, inside the
    /// workspace, the speed bound, `V` non-increasing, no overshoot, …, and the file's own
    /// `[expect]` entries). The quality benchmark and verify's adversarial suite ask it here;
    /// the experiment records' `guarantees_held` leaves the `[expect]` entries out as well.
    pub fn safe(&self) -> bool {
        self.first_unsafe().is_none()
    }

    /// The first guarantee other than arrival (and a lidar's `scans-accepted`: a refused scan
    /// stops the robot, it does not endanger it) that failed (`None` when [`Self::safe`]).
    pub fn first_unsafe(&self) -> Option<&Guarantee> {
        self.guarantees
            .iter()
            .find(|g| !g.passed && !matches!(g.kind(), Kind::ReachedGoal | Kind::ScansAccepted))
    }
}

/// A policy by its name in the scenario file (`KPolicy`, `DampingPolicy` print their names).
pub(crate) fn by_name<S: Serializer, T: std::fmt::Display>(
    policy: &T,
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_str(policy)
}

/// [`by_name`] for an optional policy: `null` when there is none.
pub(crate) fn by_name_if_any<S: Serializer, T: std::fmt::Display>(
    policy: &Option<T>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match policy {
        Some(p) => s.collect_str(p),
        None => s.serialize_none(),
    }
}

/// What the lidar perception did over a run and how it compares with the truth
/// (`summary.json`'s `perception`).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PerceptionReport {
    /// Scans the navigator observed.
    pub scans: usize,
    /// Scans that changed the obstacles.
    pub events: usize,
    /// Perceived shapes at the end.
    pub perceived: usize,
    /// True boundary points the coverage check's rays saw, over all scans.
    pub seen_points: usize,
    /// Of those, points outside every perceived shape (`0`: the perceived shapes covered the
    /// seen truth).
    pub uncovered_points: usize,
    /// Segments of unexplained hits wider than `D + 2ε` that no fit covers, over all scans
    /// (`ScanUpdate::unfitted`): the world broke the depth prior A3 there (an obstacle wider
    /// than `D`, or two obstacles in one segment), and the truth they saw is not perceived.
    pub unfitted_segments: usize,
    /// The smallest depth of a covered seen truth point inside the perceived shape that holds
    /// it deepest, m: how tight the fits are on the seen faces (a fit shrunk by more than this
    /// would leave seen truth uncovered). `None`: no point covered.
    pub min_cover_depth: Option<f64>,
    /// Boundary points of a perceived shape outside every later one, over all events (`0`:
    /// the shapes only grew).
    pub shrunk_points: usize,
    /// The smallest clearance from the robot's centre to a changed obstacle (grown by radius
    /// and margin) at an event, m.
    pub min_event_clearance: Option<f64>,
    /// Perceived area over the true area of the obstacles a perceived shape holds the centre
    /// of, at the end (`None`: none).
    pub conservatism: Option<f64>,
}

/// A run: the summary and the recorded trajectory.
#[derive(Clone, Debug)]
pub struct Run {
    /// The summary.
    pub summary: Summary,
    /// Recorded states (every `sim.dt`, and at discoveries and the end), kept in bounded
    /// memory: a run longer than [`crate::trajectory::MAX_KEPT_STATES`] grid states keeps one in a power of two
    /// of them ([`crate::trajectory`]). The monitors judged every state, and
    /// [`crate::run::run_observed`] hands every one to its observer.
    pub samples: Vec<Sample>,
    /// A lidar's scans that changed the obstacles (events), with the perceived shapes after
    /// each; every scan went to the observer.
    pub scan_events: Vec<ScanRecord>,
    /// The movers every [`crate::trace::MOVER_FRAME_PERIOD`] (a file with `[[movers]]`;
    /// empty otherwise), as the observer got them.
    pub mover_frames: Vec<MoverFrame>,
}

/// Why a run could not start or go on (the run's guarantees are judged only on a run that
/// started; this is the error before that, or of a controller other than the law).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum RunError {
    /// The navigator refused the scenario's world, goal or law, or a command.
    Navigator(NavError),
    /// `Θ` with every obstacle known could not be built (the first sector axis).
    Field(FieldError),
    /// An obstacle known at the start could not be added: the start is inside it.
    Start(Box<Guarantee>),
    /// The start is not in the free space of the obstacles known at the start.
    StartNotFree,
    /// A rapier run was asked of a build without the feature `rapier`.
    NoRapier,
    /// Never returned since 2026-12-07, when rapier began to fly files with movers; a file
    /// with robots gets [`RunError::RobotsInRapier`]. Kept for one release so that code naming
    /// it compiles.
    #[deprecated(note = "rapier flies files with movers since 2026-12-07; see RobotsInRapier")]
    MoversInRapier,
    /// A rapier run was asked of a file with `[[robots]]`: several robots fly in the built-in
    /// held-command loop only (docs/movers.md §8).
    RobotsInRapier,
    /// Never returned since 2026-12-07, when a floor plan's differential drive began to fly in
    /// rapier; kept for one release so that code naming it compiles.
    #[deprecated(note = "rapier flies a floor plan's differential drive since 2026-12-07")]
    DiffFloorInRapier,
    /// Robot `robot` of a file with `[[robots]]` (0: `[robot]`) could not be prepared with its
    /// own start and goal.
    Robot {
        /// Which robot.
        robot: usize,
        /// Why.
        problem: String,
    },
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Navigator(e) => write!(f, "{e}"),
            Self::Field(e) => write!(f, "{e}"),
            Self::Start(lost) => f.write_str(&lost.detail()),
            Self::StartNotFree => f.write_str("the start is not in the free space"),
            Self::NoRapier => f.write_str(
                "this build has no rapier integrator: enable harmonav-sim's feature `rapier`",
            ),
            Self::Robot { robot, problem } => write!(f, "robot {robot}: {problem}"),
            #[allow(deprecated)]
            Self::DiffFloorInRapier => f.write_str(
                "a floor plan with a differential drive (robot.base = \"diff\") ran in the \
                 built-in loop only before 2026-12-07",
            ),
            #[allow(deprecated)]
            Self::MoversInRapier => f.write_str(
                "a file with [[movers]] ran in the built-in held-command loop only before \
                 2026-12-07",
            ),
            Self::RobotsInRapier => f.write_str(
                "a file with [[robots]] runs in the built-in held-command loop only (not rapier): \
                 several robots are not one rapier world",
            ),
        }
    }
}

impl std::error::Error for RunError {}

impl From<NavError> for RunError {
    fn from(e: NavError) -> Self {
        Self::Navigator(e)
    }
}

impl From<FieldError> for RunError {
    fn from(e: FieldError) -> Self {
        Self::Field(e)
    }
}

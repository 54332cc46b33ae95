//! The MCAP recording of a run, written by the `foxglove` crate with its official Protobuf
//! schemas (every message is decodable from the schemas the file carries), chunks compressed
//! with zstd.
//!
//! | topic | schema | content |
//! |---|---|---|
//! | `/scene` | `foxglove.SceneUpdate` | boundary (white), obstacles (grey: unknown, red: known; ids `obstacle/<name>`), goal; at t = 0 and each discovery |
//! | `/theta` | `foxglove.Grid` | `Θ` of the known world on a [`GRID_CELLS`]² grid over the workspace (field `theta`, float32, NaN outside the free space); at t = 0 and each discovery |
//! | `/robot/pose` | `foxglove.PoseInFrame` | the robot pose (heading: the velocity; a differential drive's body heading `θ`) at every recorded state |
//! | `/tf` | `foxglove.FrameTransform` | `world → robot` at every recorded state |
//! | `/sensor/sector` | `foxglove.SceneUpdate` | the sensing sector, once, in the `robot` frame (it follows `/tf`); sector sensing only |
//! | `/robot/path` | `foxglove.SceneUpdate` | the path, one new line entity per [`PATH_PERIOD`] of simulated time (entities accumulate: the size is linear in the run's length) |
//! | `/log` | `foxglove.Log` | the scenario's warnings, discoveries and damping switches |
//! | `/harmonav/state` | `harmonavstate.HarmonavState` ([`HarmonavState`], Protobuf derived from the struct) | t, x, ẋ, speed, Θ, V, λ, k, the policies |
//!
//! A run with a simulated lidar (`[sensor] type = "lidar"`) adds [`LIDAR_TOPICS`], and its
//! `/theta` grids are those of the obstacles as perceived (grown by the robot's radius and
//! margin), at `t = 0` and each event:
//!
//! | topic | schema | content |
//! |---|---|---|
//! | `/scan` | `foxglove.LaserScan` | every scan as the navigator got it, in the `world` frame at the sensor's pose (`+∞`: no return, NaN: a dropout) |
//! | `/perceived` | `foxglove.SceneUpdate` | the perceived shapes (cyan, not grown), replaced at each event (the true ones stay on `/scene`) |
//!
//! A run with movers (`[[movers]]`, or other robots in `[[robots]]`) adds [`MOVER_TOPICS`]:
//!
//! | topic | schema | content |
//! |---|---|---|
//! | `/movers` | `foxglove.SceneUpdate` | every mover's disc (orange: non-cooperative, blue: reciprocal, ids `mover/<i>`) and, thinner, the disc it may reach within one control period as the filter sees it, replaced every [`harmonav_sim::trace::MOVER_FRAME_PERIOD`]; each change of the robot's mode (`yielding`, `overwhelmed`, …) is a line on `/log` |
//!
//! A run with `[[robots]]` adds, for each robot after the first (`i` = 1, 2, … in the file's
//! order of `[[robots]]`), its own trajectory ([`Stream::robots`], logged when the run ends:
//! its messages are stamped with their simulated times, as the first robot's):
//!
//! | topic | schema | content |
//! |---|---|---|
//! | `/robots/<i>/pose` | `foxglove.PoseInFrame` | its pose at every recorded state (heading as the first robot's) |
//! | `/tf` | `foxglove.FrameTransform` | `world → robot_<i>` at every recorded state |
//! | `/robots/<i>/path` | `foxglove.SceneUpdate` | its path, blue, one new line entity per [`PATH_PERIOD`] |
//! | `/robots/<i>/state` | `harmonavstate.HarmonavState` | its state, as `/harmonav/state` |
//!
//! A floor plan's recording ([`Stream::create_floor`], issue 25) has the same topics but the
//! sector: `/scene` holds the true walls (every ring, white) and the shrunk walls `∂W_s`
//! (grey; the certified region `W_δ` lies `δ` inside them) in place of the boundary, with a
//! chain of funnels (`floor_plan.funnels`) their goals and the links to their parents (teal,
//! the entity `funnels`), `/theta` the floor plan's `Θ` as
//! the robot knew it over the walls' bounding square (NaN outside the certified region), and
//! `/harmonav/state` the floor navigator's own evaluation at every state (`V` of the floor's
//! `Θ` under the dynamic law).

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;
use std::sync::Arc;

use foxglove::messages::{
    FrameTransform, Grid, LaserScan as FoxScan, Log, PoseInFrame, SceneEntityDeletion, SceneUpdate,
    Vector3, log, scene_entity_deletion,
};
use foxglove::{Channel, Context, Encode, McapCompression, McapWriteOptions};
use nalgebra::Vector2;

use harmonav_scenario::Prepared;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_sim::movers::FleetRobot;
use harmonav_sim::summary::Run;
use harmonav_sim::trace::{Discovery, Event, MoverFrame, Sample, ScanRecord};

use crate::atomic::AtomicFile;
use crate::drawing::closed_outline;
use crate::messages::{PERCEIVED, entity, line, log_message, nanos, pose, stamp, yaw_quaternion};
use crate::world::World;

/// The topics, in the order of the table above.
pub const TOPICS: [&str; 8] = [
    "/scene",
    "/theta",
    "/robot/pose",
    "/tf",
    "/sensor/sector",
    "/robot/path",
    "/log",
    "/harmonav/state",
];

/// The topics a run with a simulated lidar adds, in the order of the table above.
pub const LIDAR_TOPICS: [&str; 2] = ["/scan", "/perceived"];

/// The topics a run with movers adds, in the order of the table above.
pub const MOVER_TOPICS: [&str; 1] = ["/movers"];

/// A non-cooperative mover's colour on `/movers` (orange).
const MOVER: [f64; 4] = [0.95, 0.55, 0.1, 1.0];

/// A reciprocal mover's colour on `/movers` (another harmonav robot: blue).
const PEER: [f64; 4] = [0.2, 0.45, 0.9, 1.0];

/// The other robots' paths on `/robots/<i>/path` (blue, as they are on `/movers`).
const ROBOT_PATH_COLOUR: [f64; 4] = PEER;

/// Vertices of a mover's circle on `/movers`.
const CIRCLE_VERTICES: usize = 32;

pub use crate::world::GRID_CELLS;

/// Simulated seconds between two `/robot/path` updates.
pub const PATH_PERIOD: f64 = 0.5;

/// Vertices of the path are at least this far apart, m (every state is on `/robot/pose`).
pub const PATH_SPACING: f64 = 0.01;

/// The first robot's path on `/robot/path` (yellow).
const PATH_COLOUR: [f64; 4] = [1.0, 0.8, 0.1, 1.0];

/// A path logged as it grows: one new line entity every [`PATH_PERIOD`] of simulated time
/// (`/robot/path`, and each other robot's `/robots/<i>/path`), vertices at least
/// [`PATH_SPACING`] apart.
struct PathLog {
    points: Vec<Vector2<f64>>,
    n: usize,
    next: f64,
    colour: [f64; 4],
}

impl PathLog {
    fn new(colour: [f64; 4]) -> Self {
        Self {
            points: Vec::new(),
            n: 0,
            next: PATH_PERIOD,
            colour,
        }
    }

    /// A state at `x` at `t`: the update to log, when one is due.
    fn push(&mut self, x: Vector2<f64>, t: f64) -> Option<SceneUpdate> {
        if self
            .points
            .last()
            .is_none_or(|p: &Vector2<f64>| (x - p).norm() >= PATH_SPACING)
        {
            self.points.push(x);
        }
        if t >= self.next { self.flush(t) } else { None }
    }

    /// The path since the last update as one line entity at `t` (`None` with fewer than two
    /// vertices); the next one starts where it ends.
    fn flush(&mut self, t: f64) -> Option<SceneUpdate> {
        let mut update = None;
        if self.points.len() >= 2 {
            let id = format!("path-{:05}", self.n);
            update = Some(SceneUpdate {
                deletions: Vec::new(),
                entities: vec![entity(
                    t,
                    "world",
                    &id,
                    vec![line(self.points.iter().copied(), self.colour, 0.02)],
                )],
            });
            self.n += 1;
            let keep = self.points.len() - 1;
            self.points.drain(..keep);
        }
        self.next = ((t / PATH_PERIOD).floor() + 1.0) * PATH_PERIOD;
        update
    }

    /// The last segment, ending at the last state `x` at `t`.
    fn end(&mut self, x: Vector2<f64>, t: f64) -> Option<SceneUpdate> {
        if self.points.last() != Some(&x) {
            self.points.push(x);
        }
        self.flush(t)
    }
}

/// The transform `world → child` at `x`, heading `yaw`, at `t`.
fn transform(t: f64, child: &str, x: Vector2<f64>, yaw: f64) -> FrameTransform {
    FrameTransform {
        timestamp: stamp(t),
        parent_frame_id: "world".into(),
        child_frame_id: child.into(),
        translation: Some(Vector3 {
            x: x.x,
            y: x.y,
            z: 0.0,
        }),
        rotation: Some(yaw_quaternion(yaw)),
    }
}

/// harmonav's state at a recorded instant: the message of `/harmonav/state` (its Protobuf
/// schema, `harmonavstate.HarmonavState`, is derived from this struct by `foxglove`).
#[derive(Clone, Debug, Default, PartialEq, Encode, serde::Serialize)]
pub struct HarmonavState {
    /// Time, s.
    pub t: f64,
    /// Position `x`, m.
    pub x: f64,
    /// Position `y`, m.
    pub y: f64,
    /// Velocity `ẋ`, m/s.
    pub vx: f64,
    /// Velocity `ẏ`, m/s.
    pub vy: f64,
    /// `|ẋ|`, m/s.
    pub speed: f64,
    /// `Θ(x)` over the known obstacles.
    pub theta: f64,
    /// `V = μ_pΨ + ½m|ẋ|²` (dynamic law, `μ_p` its pull; `Ψ` its potential under the damping policy, `Θ`
    /// itself under `"paper"`).
    pub energy: Option<f64>,
    /// The damping `λ` in force (dynamic law).
    pub lambda: Option<f64>,
    /// `k` of `phi_k`.
    pub k: f64,
    /// The `k` policy.
    pub k_policy: String,
    /// The damping policy (dynamic law; empty for the kinematic one).
    pub damping: String,
    /// The damping is in its `V < μ_p` branch (dynamic law; `μ_p` the pull).
    pub damping_critical: bool,
}

/// Why a recording could not be written.
#[derive(Debug)]
pub struct RecordError(pub String);

impl std::fmt::Display for RecordError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for RecordError {}

/// The channels of one recording, on a context of its own (recordings made in parallel do
/// not share channels).
struct Channels {
    scene: Channel<SceneUpdate>,
    theta: Channel<Grid>,
    pose: Channel<PoseInFrame>,
    tf: Channel<FrameTransform>,
    sector: Channel<SceneUpdate>,
    path: Channel<SceneUpdate>,
    log: Channel<Log>,
    state: Channel<HarmonavState>,
    scan: Channel<FoxScan>,
    perceived: Channel<SceneUpdate>,
    movers: Channel<SceneUpdate>,
}

impl Channels {
    fn new(ctx: &Arc<Context>) -> Self {
        let [scene, theta, pose, tf, sector, path, log, state] = TOPICS;
        let [scan, perceived] = LIDAR_TOPICS;
        Self {
            scene: ctx.channel_builder(scene).build(),
            theta: ctx.channel_builder(theta).build(),
            pose: ctx.channel_builder(pose).build(),
            tf: ctx.channel_builder(tf).build(),
            sector: ctx.channel_builder(sector).build(),
            path: ctx.channel_builder(path).build(),
            log: ctx.channel_builder(log).build(),
            state: ctx.channel_builder(state).build(),
            scan: ctx.channel_builder(scan).build(),
            perceived: ctx.channel_builder(perceived).build(),
            movers: ctx.channel_builder(MOVER_TOPICS[0]).build(),
        }
    }
}

/// The heading shown at each state: the velocity's direction, held while at rest.
struct Heading(f64);

impl Heading {
    fn at(&mut self, v: Vector2<f64>) -> f64 {
        if v.norm() > 1e-9 {
            self.0 = v.y.atan2(v.x);
        }
        self.0
    }
}

/// Writes the recording of `run` to `path`, whole or not at all (through a temporary file):
/// [`Stream`] replayed over the run's warnings, discoveries and kept states.
pub fn write_mcap(path: &Path, prepared: &Prepared, run: &Run) -> Result<(), RecordError> {
    let mut stream = Stream::create(path, prepared)?;
    replay(run, &mut |e| stream.observe(e));
    if let Some(fleet) = &run.summary.fleet {
        stream.robots(&fleet.others);
    }
    stream.finish()
}

/// Hands `run`'s warnings, discoveries, scan events and kept states to `observer` in the
/// order `harmonav_sim::run::run_observed` would have (a discovery or a scan event after the
/// states before its time). Of a lidar's scans only the events were kept
/// ([`Run::scan_events`]).
pub fn replay(run: &Run, observer: &mut dyn FnMut(Event<'_>)) {
    for w in &run.summary.warnings {
        observer(Event::Warning(w));
    }
    let mut discoveries = run.summary.discoveries.iter().peekable();
    let mut scans = run.scan_events.iter().peekable();
    let mut frames = run.mover_frames.iter().peekable();
    let mut previous: Option<f64> = None;
    for s in &run.samples {
        // Discoveries at the start come first; a later one, and every scan event, between
        // its two recorded sides.
        let due = |d: &&Discovery| {
            d.time_s < s.t || (d.time_s == s.t && (d.time_s == 0.0 || previous == Some(s.t)))
        };
        while let Some(d) = discoveries.next_if(due) {
            observer(Event::Discovery(d));
        }
        let due = |r: &&ScanRecord| r.time_s < s.t || (r.time_s == s.t && previous == Some(s.t));
        while let Some(r) = scans.next_if(due) {
            observer(Event::Scan(r));
        }
        observer(Event::State(s));
        previous = Some(s.t);
        while let Some(f) = frames.next_if(|f| f.t <= s.t) {
            observer(Event::Movers(f));
        }
    }
    for d in discoveries {
        observer(Event::Discovery(d));
    }
    for r in scans {
        observer(Event::Scan(r));
    }
    for f in frames {
        observer(Event::Movers(f));
    }
}

/// A recording written to disk as the run goes (`harmonav_sim::physics::simulate_observed` feeds
/// it), so that its memory does not grow with the run's length: every message of the run in
/// time order, whole or not at all (through a temporary file, committed by
/// [`Stream::finish`]; dropped before, nothing is left).
pub struct Stream<'p> {
    world: World<'p>,
    path: std::path::PathBuf,
    file: AtomicFile,
    writer: foxglove::McapWriterHandle<BufWriter<File>>,
    /// The recording's own context: the channels log into it only while it lives.
    ctx: Arc<Context>,
    ch: Channels,
    k_policy: String,
    /// The damping policy the dynamic law's states are labelled with (a star world's file's;
    /// a floor plan's navigator's).
    damping: String,
    /// The obstacles known (scenario indices, in discovery order), and how many of them the
    /// last `/scene` showed.
    known: Vec<usize>,
    shown: Option<usize>,
    /// Whether a lidar's perceived `Θ` is on `/theta`: the known set's grid (empty with a
    /// lidar) then no longer replaces it (a floor plan's loop hands a scan at `t = 0` over
    /// before the first state).
    perceived_shown: bool,
    /// Discoveries not yet logged (they are logged with the next state).
    pending: Vec<Discovery>,
    heading: Heading,
    /// `/robot/path`.
    trail: PathLog,
    critical: Option<bool>,
    last: Option<Sample>,
    /// The robot's mode in the last movers' frame (its changes go to `/log`).
    mode: Option<&'static str>,
    /// The first error met while logging (reported by [`Stream::finish`]).
    error: Option<RecordError>,
}

impl<'p> Stream<'p> {
    /// Opens the recording of a run of `prepared` at `path` (the sector, if any, is logged at
    /// `t = 0`).
    pub fn create(path: &Path, prepared: &'p Prepared) -> Result<Self, RecordError> {
        Self::open(path, World::Star(prepared))
    }

    /// Opens the recording of a run of the floor plan `prepared` at `path`
    /// (`harmonav_sim::physics::simulate_floor_observed` feeds it): `/scene` holds the true
    /// walls and the shrunk walls `∂W_s` (the certified region lies `δ` inside them), `/theta` the floor plan's `Θ` over the walls' bounding
    /// square; there is no sector.
    ///
    /// # Errors
    /// The file cannot be created, or the file's navigator (whose `Θ` is recorded) cannot be
    /// built.
    pub fn create_floor(path: &Path, prepared: &'p FloorPrepared) -> Result<Self, RecordError> {
        let world =
            World::floor(prepared).map_err(|e| RecordError(format!("the navigator: {e}")))?;
        Self::open(path, world)
    }

    /// The floor plan's navigator knowing no obstacle (a floor plan's recording only).
    pub(crate) fn floor_base(&self) -> Option<&harmonav::FloorNavigator> {
        match &self.world {
            World::Floor { base, .. } => Some(base),
            World::Star(_) => None,
        }
    }

    fn open(path: &Path, world: World<'p>) -> Result<Self, RecordError> {
        let fail = |e: &dyn std::fmt::Display| RecordError(format!("{}: {e}", path.display()));
        let (file, out) = AtomicFile::create(path).map_err(|e| fail(&e))?;
        let ctx = Context::new();
        let ch = Channels::new(&ctx);
        let options = McapWriteOptions::new().compression(Some(McapCompression::Zstd));
        let writer = ctx
            .mcap_writer_with_options(options)
            .create(out)
            .map_err(|e| fail(&e))?;
        if let Some(s) = world.sector() {
            ch.sector.log_with_time(&s, 0);
        }
        let (k_policy, damping) = world.policies();
        Ok(Self {
            world,
            path: path.to_path_buf(),
            file,
            writer,
            ctx,
            ch,
            k_policy,
            damping,
            known: Vec::new(),
            shown: None,
            perceived_shown: false,
            pending: Vec::new(),
            heading: Heading(0.0),
            trail: PathLog::new(PATH_COLOUR),
            critical: None,
            last: None,
            mode: None,
            error: None,
        })
    }

    /// Logs one event of the run.
    pub fn observe(&mut self, event: Event<'_>) {
        match event {
            Event::Warning(w) => self
                .ch
                .log
                .log_with_time(&log_message(0.0, log::Level::Warning, w.to_string()), 0),
            Event::Discovery(d) => {
                self.known.push(d.index);
                self.pending.push(d.clone());
            }
            Event::State(s) => self.state(s),
            Event::Scan(r) => self.scan(r),
            Event::Movers(f) => self.movers(f),
        }
    }

    /// The movers' frame: their discs and reach on `/movers`, a change of mode on `/log`.
    fn movers(&mut self, f: &MoverFrame) {
        let (t, ch) = (f.t, &self.ch);
        let circle = |c: [f64; 2], r: f64| {
            (0..=CIRCLE_VERTICES).map(move |j| {
                let a = std::f64::consts::TAU * j as f64 / CIRCLE_VERTICES as f64;
                Vector2::new(c[0] + r * a.cos(), c[1] + r * a.sin())
            })
        };
        let entities = f
            .movers
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let rgba = if m.reciprocal { PEER } else { MOVER };
                let faint = [rgba[0], rgba[1], rgba[2], 0.4];
                entity(
                    t,
                    "world",
                    &format!("mover/{i}"),
                    vec![
                        line(circle(m.position, m.radius), rgba, 0.03),
                        line(circle(m.position, m.reach), faint, 0.01),
                    ],
                )
            })
            .collect();
        ch.movers.log_with_time(
            &SceneUpdate {
                deletions: Vec::new(),
                entities,
            },
            nanos(t),
        );
        if f.mode.is_some() && f.mode != self.mode {
            self.mode = f.mode;
            let text = format!("mode {} at t = {t:.3} s", f.mode.unwrap_or_default());
            ch.log
                .log_with_time(&log_message(t, log::Level::Info, text), nanos(t));
        }
    }

    /// A lidar scan: `/scan`, and at an event the perceived shapes on `/perceived` and their
    /// `Θ` on `/theta`.
    fn scan(&mut self, r: &ScanRecord) {
        let (t, ch) = (r.time_s, &self.ch);
        let n = r.scan.ranges.len();
        ch.scan.log_with_time(
            &FoxScan {
                timestamp: stamp(t),
                frame_id: "world".into(),
                pose: Some(pose(r.pose.position(), r.pose.yaw)),
                start_angle: r.scan.angle_min,
                end_angle: r.scan.angle_min + n.saturating_sub(1) as f64 * r.scan.angle_increment,
                ranges: r.scan.ranges.clone(),
                intensities: Vec::new(),
            },
            nanos(t),
        );
        let Some(perceived) = &r.perceived else {
            return;
        };
        let entities = perceived
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let id = format!("P{}", i + 1);
                entity(
                    t,
                    "world",
                    &id,
                    vec![line(closed_outline(p), PERCEIVED, 0.03)],
                )
            })
            .collect();
        ch.perceived.log_with_time(
            &SceneUpdate {
                deletions: vec![SceneEntityDeletion {
                    timestamp: stamp(t),
                    r#type: scene_entity_deletion::Type::All as i32,
                    id: String::new(),
                }],
                entities,
            },
            nanos(t),
        );
        match self.world.perceived_grid(perceived, t) {
            Ok(grid) => {
                ch.theta.log_with_time(&grid, nanos(t));
                self.perceived_shown = true;
            }
            Err(e) => {
                let e = RecordError(format!("the Θ grid at t = {t}: {e}"));
                self.error.get_or_insert(e);
            }
        }
        let text = format!("scan at t = {t:.3} s: {} perceived shapes", perceived.len());
        ch.log
            .log_with_time(&log_message(t, log::Level::Info, text), nanos(t));
    }

    /// A recorded state: the scene and `Θ` grid first if the known set changed (and at the
    /// first state), then the pose, the transform, harmonav's state, a damping switch, and
    /// the path every [`PATH_PERIOD`].
    fn state(&mut self, s: &Sample) {
        if self.shown != Some(self.known.len()) {
            self.shown = Some(self.known.len());
            let t = s.t;
            let ch = &self.ch;
            ch.scene
                .log_with_time(&self.world.scene(&self.known, t), nanos(t));
            let grid = (!self.perceived_shown).then(|| self.world.theta_grid(&self.known, t));
            match grid {
                None => {}
                Some(Ok(grid)) => ch.theta.log_with_time(&grid, nanos(t)),
                Some(Err(e)) => {
                    let e = RecordError(format!("the Θ grid at t = {t}: {e}"));
                    self.error.get_or_insert(e);
                }
            }
            for d in self.pending.drain(..) {
                let text = format!("discovered {} at t = {:.3} s", d.obstacle, d.time_s);
                ch.log
                    .log_with_time(&log_message(t, log::Level::Info, text), nanos(t));
            }
        }
        let (x, v) = (Vector2::from(s.x), Vector2::from(s.v));
        // A differential drive's heading is its body's (`[robot] base = "diff"`).
        let yaw = s.yaw.unwrap_or_else(|| self.heading.at(v));
        let t = nanos(s.t);
        let ch = &self.ch;
        ch.pose.log_with_time(
            &PoseInFrame {
                timestamp: stamp(s.t),
                frame_id: "world".into(),
                pose: Some(pose(x, yaw)),
            },
            t,
        );
        ch.tf.log_with_time(&transform(s.t, "robot", x, yaw), t);
        ch.state
            .log_with_time(&state(s, &self.k_policy, &self.damping), t);
        if s.lambda.is_some() && self.critical.is_some_and(|c| c != s.critical) {
            let text = if s.critical {
                format!(
                    "damping back to its critical branch (V < μ_p) at t = {:.3} s",
                    s.t
                )
            } else {
                format!("damping switched (V ≥ μ_p) at t = {:.3} s", s.t)
            };
            ch.log
                .log_with_time(&log_message(s.t, log::Level::Warning, text), t);
        }
        self.critical = s.lambda.map(|_| s.critical);
        if let Some(update) = self.trail.push(x, s.t) {
            self.ch.path.log_with_time(&update, nanos(s.t));
        }
        self.last = Some(s.clone());
    }

    /// The trajectories of the robots after the first of a run with `[[robots]]` (`others`,
    /// in the file's order; `harmonav_sim::movers::FleetRobot::samples`), each on its own
    /// topics (`/robots/<i>/pose`, `/robots/<i>/path`, `/robots/<i>/state`, and `/tf`'s
    /// `world → robot_<i>`), stamped with their simulated times. Called once, when the run has
    /// ended ([`crate::set::Outputs::finish`], [`crate::floor::FloorOutputs::finish`],
    /// [`write_mcap`]); nothing without other robots.
    pub fn robots(&mut self, others: &[FleetRobot]) {
        for (k, robot) in others.iter().enumerate() {
            let i = k + 1;
            let ctx = &self.ctx;
            let pose_ch = ctx
                .channel_builder(format!("/robots/{i}/pose"))
                .build::<PoseInFrame>();
            let path_ch = ctx
                .channel_builder(format!("/robots/{i}/path"))
                .build::<SceneUpdate>();
            let state_ch = ctx
                .channel_builder(format!("/robots/{i}/state"))
                .build::<HarmonavState>();
            let child = format!("robot_{i}");
            let (mut heading, mut path) = (Heading(0.0), PathLog::new(ROBOT_PATH_COLOUR));
            for s in &robot.samples {
                let (x, v) = (Vector2::from(s.x), Vector2::from(s.v));
                let yaw = s.yaw.unwrap_or_else(|| heading.at(v));
                let t = nanos(s.t);
                pose_ch.log_with_time(
                    &PoseInFrame {
                        timestamp: stamp(s.t),
                        frame_id: "world".into(),
                        pose: Some(pose(x, yaw)),
                    },
                    t,
                );
                self.ch.tf.log_with_time(&transform(s.t, &child, x, yaw), t);
                state_ch.log_with_time(&state(s, &self.k_policy, &self.damping), t);
                if let Some(update) = path.push(x, s.t) {
                    path_ch.log_with_time(&update, t);
                }
            }
            if let Some(last) = robot.samples.last()
                && let Some(update) = path.end(Vector2::from(last.x), last.t)
            {
                path_ch.log_with_time(&update, nanos(last.t));
            }
        }
    }

    /// Ends the recording at the last state (its path's last segment) and moves it into place;
    /// the first error met while logging, if any, instead (and nothing is left).
    pub fn finish(mut self) -> Result<(), RecordError> {
        if let Some(last) = self.last.take()
            && let Some(update) = self.trail.end(Vector2::from(last.x), last.t)
        {
            self.ch.path.log_with_time(&update, nanos(last.t));
        }
        if let Some(e) = self.error {
            return Err(e);
        }
        let fail = |e: &dyn std::fmt::Display| RecordError(format!("{}: {e}", self.path.display()));
        let inner: BufWriter<File> = self.writer.close().map_err(|e| fail(&e))?;
        self.file.commit(inner).map_err(|e| fail(&e))
    }
}

/// harmonav's state at `s`. `damping` is the file's damping policy: it labels the states of
/// the dynamic law (those with an energy), whatever the file's own robot model (a kinematic
/// file run with `--model dynamic` runs the dynamic law), and is empty for the kinematic.
fn state(s: &Sample, k_policy: &str, damping: &str) -> HarmonavState {
    let damping = if s.energy.is_some() { damping } else { "" };
    HarmonavState {
        t: s.t,
        x: s.x[0],
        y: s.x[1],
        vx: s.v[0],
        vy: s.v[1],
        speed: s.v[0].hypot(s.v[1]),
        theta: s.theta,
        energy: s.energy,
        lambda: s.lambda,
        k: s.k,
        k_policy: k_policy.into(),
        damping: damping.into(),
        damping_critical: s.critical,
    }
}

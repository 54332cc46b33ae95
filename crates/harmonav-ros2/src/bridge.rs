//! The node's logic without DDS: messages in, a velocity command out, every stop with its
//! reason. [`Bridge`] is driven by `main.rs` (and by the unit tests) with arrival times from
//! the steady clock.
//!
//! Frames (REP 105): the navigation runs in `global_frame` (`map`); the robot's pose there is
//! `map → odom` (`/tf`, from AMCL or SLAM) ∘ `odom → base_link` (`/odom`'s pose, or `/tf`),
//! and the laser's is that ∘ `base_link → laser` (`/tf_static`). An edge never published is
//! taken as the identity, said once: a simulator that publishes only `/odom` works (map =
//! odom, the laser at base_link).

use std::collections::HashSet;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use harmonav::floorplan::ros_map::{MapOptions, RosMap};
use harmonav::{
    FloorMap, FloorNavigator, FloorOptions, Law, Mode, Navigator, Options, StarShape, Steer,
    Vector2, World,
};

use crate::msgs::{
    self, ColorRGBA, Header, Marker, MarkerArray, OccupancyGrid, Odometry, Point, PoseStamped,
    TFMessage, Time, Twist, Vector3,
};
use crate::params::{Base, LawKind, Params};
use crate::tf::{Buffer, Lookup, Se2};

/// m/s: a differential-drive base's top forward speed when `v_max` is not given.
pub const DIFF_V_MAX: f64 = 0.5;

/// A message dropped, with why.
#[derive(Clone, Debug, PartialEq)]
pub struct BadMessage(pub String);

impl std::fmt::Display for BadMessage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// A `sensor_msgs/LaserScan` as harmonav's scan (ranges widened to f64; REP 117's classes,
/// `−Inf` too close, `NaN` error, `+Inf` or `≥ range_max` no return, `< range_min` invalid,
/// are kept as they are and classified by `harmonav::perception`).
///
/// # Errors
/// An empty scan, a non-finite angle or limit, `angle_increment ≤ 0` (a clockwise scanner:
/// dropped, not reversed, as the issue asks), `range_max ≤ range_min`, `range_min < 0`.
pub fn scan_to_harmonav(m: &msgs::LaserScan) -> Result<harmonav::LaserScan, BadMessage> {
    let bad = |s: &str| Err(BadMessage(format!("scan dropped: {s}")));
    if m.ranges.is_empty() {
        return bad("no ranges");
    }
    for (v, name) in [
        (m.angle_min, "angle_min"),
        (m.angle_increment, "angle_increment"),
        (m.range_min, "range_min"),
        (m.range_max, "range_max"),
    ] {
        if !v.is_finite() {
            return bad(&format!("{name} is not finite"));
        }
    }
    if m.angle_increment <= 0.0 {
        return bad(&format!(
            "angle_increment = {} ≤ 0 (a clockwise scan)",
            m.angle_increment
        ));
    }
    if m.range_min < 0.0 || m.range_max <= m.range_min {
        return bad(&format!(
            "range limits [{}, {}] are not 0 ≤ range_min < range_max",
            m.range_min, m.range_max
        ));
    }
    Ok(harmonav::LaserScan {
        angle_min: f64::from(m.angle_min),
        angle_increment: f64::from(m.angle_increment),
        range_min: f64::from(m.range_min),
        range_max: f64::from(m.range_max),
        ranges: m.ranges.iter().map(|&r| f64::from(r)).collect(),
    })
}

/// The class of a grid cell, map_server's reading of `p = occupancy/100`: `p > occupied`
/// occupied, `p < free` free, else (and −1, and above 100) unknown, which counts as occupied.
#[must_use]
pub fn grid_cell(v: i8, occupied: f64, free: f64) -> harmonav::floorplan::ros_map::Cell {
    use harmonav::floorplan::ros_map::Cell;
    if !(0..=100).contains(&v) {
        return Cell::Unknown;
    }
    let p = f64::from(v) / 100.0;
    if p > occupied {
        Cell::Occupied
    } else if p < free {
        Cell::Free
    } else {
        Cell::Unknown
    }
}

static MAP_FILES: AtomicU64 = AtomicU64::new(0);

/// A `nav_msgs/OccupancyGrid` through the same pipeline as a map_server file: it is written as
/// one (a trinary PGM, row 0 at the top, and its YAML with the grid's resolution and origin)
/// into a private temporary folder, read back by [`RosMap::load`], and the folder removed.
/// (harmonav-floorplan has no in-memory constructor; the files cost milliseconds.)
///
/// # Errors
/// A size that does not match the data, a zero side, a resolution or origin that is not
/// finite and positive, or what [`RosMap::load`] refuses (a side above its cap).
pub fn grid_to_ros_map(g: &OccupancyGrid, occupied: f64, free: f64) -> Result<RosMap, BadMessage> {
    use harmonav::floorplan::ros_map::Cell;
    use std::io::Write;
    let bad = |s: String| Err(BadMessage(format!("map dropped: {s}")));
    let (w, h) = (g.info.width as usize, g.info.height as usize);
    if w == 0 || h == 0 {
        return bad(format!("size {w} × {h}"));
    }
    if w.checked_mul(h) != Some(g.data.len()) {
        return bad(format!(
            "size {w} × {h} does not match its {} cells",
            g.data.len()
        ));
    }
    let res = f64::from(g.info.resolution);
    if !(res.is_finite() && res > 0.0) {
        return bad(format!("resolution {res}"));
    }
    let o = &g.info.origin;
    let Some(yaw) = o.orientation.yaw() else {
        return bad("origin's orientation is not a rotation".into());
    };
    if !(o.position.x.is_finite() && o.position.y.is_finite()) {
        return bad("origin is not finite".into());
    }
    let n = MAP_FILES.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("harmonav-ros2-{}-{n}", std::process::id()));
    let result = (|| -> Result<RosMap, String> {
        std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
        let mut pgm = Vec::with_capacity(w * h + 32);
        write!(pgm, "P5\n{w} {h}\n255\n").map_err(|e| e.to_string())?;
        for row in (0..h).rev() {
            pgm.extend(g.data[row * w..(row + 1) * w].iter().map(|&v| {
                match grid_cell(v, occupied, free) {
                    Cell::Free => 254u8,
                    Cell::Occupied => 0,
                    Cell::Unknown => 128,
                }
            }));
        }
        std::fs::write(dir.join("map.pgm"), &pgm).map_err(|e| e.to_string())?;
        let yaml = format!(
            "image: map.pgm\nresolution: {res:?}\norigin: [{:?}, {:?}, {yaw:?}]\nnegate: 0\n\
             occupied_thresh: 0.65\nfree_thresh: 0.25\nmode: trinary\n",
            o.position.x, o.position.y
        );
        std::fs::write(dir.join("map.yaml"), yaml).map_err(|e| e.to_string())?;
        RosMap::load(dir.join("map.yaml")).map_err(|e| e.to_string())
    })();
    let _ = std::fs::remove_dir_all(&dir);
    result.or_else(bad)
}

/// Why the robot is stopped (each logged once when it begins).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Stop {
    /// No goal yet (or the last one reached).
    NoGoal,
    /// The goal is reached.
    Arrived,
    /// `map_topic` is set and no map has come.
    WaitingForMap,
    /// No odometry yet, or older than `odom_timeout`.
    StaleOdom,
    /// No scan yet, or older than `scan_timeout`.
    StaleScan,
    /// A dynamic transform is older than `transform_timeout`.
    StaleTransform,
    /// The navigator could not be built for this goal (and map).
    NoNavigator(String),
    /// The last scan was refused by the navigator (`Mode::Halted`).
    ScanRefused,
    /// The navigator refused the command (the error).
    Refused(String),
    /// The robot has not moved `required_movement_radius` in `movement_time_allowance`: the
    /// goal is given up (cleared); the text says how long and why it stood.
    NoProgress(String),
    /// Shutting down.
    Shutdown,
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NoGoal => f.write_str("no goal"),
            Self::Arrived => f.write_str("goal reached"),
            Self::WaitingForMap => f.write_str("waiting for the map"),
            Self::StaleOdom => f.write_str("odometry missing or stale"),
            Self::StaleScan => f.write_str("scan missing or stale"),
            Self::StaleTransform => f.write_str("transform stale"),
            Self::NoNavigator(e) => write!(f, "no navigator for this goal: {e}"),
            Self::ScanRefused => f.write_str("the last scan was refused (halted)"),
            Self::Refused(e) => write!(f, "command refused: {e}"),
            Self::NoProgress(e) => write!(f, "no progress, goal given up: {e}"),
            Self::Shutdown => f.write_str("shutting down"),
        }
    }
}

/// Where a goal lies on `/map` ([`Bridge::goal_check`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoalCheck {
    /// In a free cell.
    Free,
    /// In an occupied cell.
    Occupied,
    /// In an unknown cell (counted as occupied, as map_server's trinary reading does).
    Unknown,
    /// Outside the map.
    OutsideMap,
    /// Not checked: no map (yet, or `map_topic` is empty).
    Unchecked,
}

/// The navigator of either world.
enum Nav {
    /// A disc around the robot, from scans alone.
    Star(Box<Navigator>),
    /// The floor plan from `/map`.
    Floor(Box<FloorNavigator>),
}

/// What one control step gives.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// The command in the base frame (zero when stopped).
    pub twist: Twist,
    /// Why it is zero, if it is.
    pub stop: Option<Stop>,
    /// The navigator's mode name when it commanded.
    pub mode: Option<&'static str>,
}

/// The latest scan.
struct LastScan {
    scan: harmonav::LaserScan,
    frame: String,
    arrival: Instant,
    /// s between scans (`scan_time`, else 0.1).
    period: f64,
    /// Whether the navigator has seen it.
    observed: bool,
}

/// The node's state.
pub struct Bridge {
    params: Params,
    tf: Buffer,
    map: Option<Arc<RosMap>>,
    goal: Option<Vector2<f64>>,
    /// The goal's yaw in `global_frame`, when it is used ([`Bridge::uses_goal_orientation`]).
    goal_yaw: Option<f64>,
    nav: Option<Nav>,
    /// The goal (and map version) the navigator was built for needs rebuilding.
    dirty: bool,
    build_error: Option<String>,
    last_scan: Option<LastScan>,
    last_odom: Option<Instant>,
    /// The dynamic law's velocity state (nav frame).
    velocity: Vector2<f64>,
    arrived: bool,
    scan_refused: bool,
    said: HashSet<String>,
    /// Log lines since the last [`Bridge::drain_log`] (level, text).
    log: Vec<(log::Level, String)>,
    last_stop: Option<Stop>,
    /// Where the robot last made progress (unknown before the first odometry of the goal)
    /// and since when.
    progress: Option<(Option<Vector2<f64>>, Instant)>,
    /// The outlines last given as markers (`None`: none given yet).
    markers_sent: Option<Vec<Vec<[f64; 2]>>>,
}

impl Bridge {
    /// A bridge with these parameters (checked by `Params::validate`).
    #[must_use]
    pub fn new(params: Params) -> Self {
        Self {
            params,
            tf: Buffer::new(),
            map: None,
            goal: None,
            goal_yaw: None,
            nav: None,
            dirty: false,
            build_error: None,
            last_scan: None,
            last_odom: None,
            velocity: Vector2::zeros(),
            arrived: false,
            scan_refused: false,
            said: HashSet::new(),
            log: Vec::new(),
            last_stop: None,
            progress: None,
            markers_sent: None,
        }
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The log lines since the last call.
    pub fn drain_log(&mut self) -> Vec<(log::Level, String)> {
        std::mem::take(&mut self.log)
    }

    fn say(&mut self, level: log::Level, text: String) {
        self.log.push((level, text));
    }

    fn say_once(&mut self, key: &str, level: log::Level, text: String) {
        if self.said.insert(key.to_owned()) {
            self.log.push((level, text));
        }
    }

    /// `/tf` or `/tf_static`.
    pub fn on_tf(&mut self, m: &TFMessage, now: Instant, is_static: bool) {
        for t in &m.transforms {
            if let Err(e) = self.tf.insert_msg(t, now, is_static) {
                let key = format!("tf {} {} {e}", t.header.frame_id, t.child_frame_id);
                self.say_once(
                    &key,
                    log::Level::Warn,
                    format!(
                        "transform {} → {} dropped: {e}",
                        t.header.frame_id, t.child_frame_id
                    ),
                );
            }
        }
    }

    /// `/odom`: its pose is the `odom → base_link` edge.
    pub fn on_odom(&mut self, m: &Odometry, now: Instant) {
        let p = &m.pose.pose;
        let (Some(yaw), true) = (
            p.orientation.yaw(),
            p.position.x.is_finite() && p.position.y.is_finite(),
        ) else {
            self.say(log::Level::Warn, "odometry dropped: pose not finite".into());
            return;
        };
        let parent = if m.header.frame_id.is_empty() {
            self.params.odom_frame.clone()
        } else {
            m.header.frame_id.clone()
        };
        let child = if m.child_frame_id.is_empty() {
            self.params.robot_base_frame.clone()
        } else {
            m.child_frame_id.clone()
        };
        let se2 = Se2::new(p.position.x, p.position.y, yaw);
        match self
            .tf
            .insert(&parent, &child, se2, m.header.stamp, now, false)
        {
            Ok(()) => self.last_odom = Some(now),
            Err(e) => self.say(log::Level::Warn, format!("odometry dropped: {e}")),
        }
    }

    /// `/goal_pose`: [`Bridge::set_goal`], a bad goal dropped with a warning.
    pub fn on_goal(&mut self, m: &PoseStamped, now: Instant) {
        if let Err(e) = self.set_goal(m, now) {
            self.say(log::Level::Warn, e.0);
        }
    }

    /// Whether goals' orientations are used: a `diff` base with `use_goal_orientation` (a
    /// holonomic base never turns, so it reads none).
    #[must_use]
    pub fn uses_goal_orientation(&self) -> bool {
        self.params.base == Base::Diff && self.params.use_goal_orientation
    }

    /// Navigates to `m` from now on, in place of any goal before it; returns its position in
    /// `global_frame`. The pose is taken into `global_frame` as a whole, `T ∘ (x, y, θ)` with
    /// `T` the frame's transform, so the goal's yaw is `θ` plus `T`'s rotation. When
    /// [`Bridge::uses_goal_orientation`], that yaw is the navigator's goal heading
    /// (`Navigator::set_goal_heading`): the robot drives to within `xy_goal_tolerance` (default
    /// `GOAL_ARRIVAL`, 1 cm), turns in place to within `yaw_goal_tolerance` of it, and has
    /// arrived only when `command_pose` says so ([`Steer::Arrived`]); otherwise the
    /// orientation is not read and arrival is within [`Params::arrival_radius`].
    ///
    /// # Errors
    /// A position that is not finite; when the orientation is used, a quaternion that is not a
    /// rotation (a component not finite, or all four zero: "no orientation" is the identity,
    /// `w = 1`, as ROS 2's message default and RViz send). The goal before it stays.
    pub fn set_goal(&mut self, m: &PoseStamped, now: Instant) -> Result<Vector2<f64>, BadMessage> {
        let p = &m.pose.position;
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(BadMessage("goal dropped: not finite".into()));
        }
        let yaw = if self.uses_goal_orientation() {
            Some(goal_yaw(&m.pose.orientation)?)
        } else {
            None
        };
        let frame = if m.header.frame_id.is_empty() {
            self.params.global_frame.clone()
        } else {
            m.header.frame_id.clone()
        };
        let (t, _) = self.transform(&self.params.global_frame.clone(), &frame, now);
        let g = t.compose(&Se2::new(p.x, p.y, yaw.unwrap_or(0.0)));
        let goal = Vector2::new(g.x, g.y);
        self.goal = Some(goal);
        self.goal_yaw = yaw.map(|_| g.yaw);
        self.dirty = true;
        self.arrived = false;
        self.progress = Some((None, now));
        let heading = self
            .goal_yaw
            .map_or(String::new(), |y| format!(", yaw {y:.3} rad"));
        self.say(
            log::Level::Info,
            format!(
                "goal ({:.3}, {:.3}){heading} in {}",
                g.x, g.y, self.params.global_frame
            ),
        );
        if self.goal_yaw.is_some() {
            let t = self.params.goal_tolerance();
            self.say_once(
                "goal yaw tolerance",
                log::Level::Info,
                format!(
                    "a goal with a yaw is reached within {} m (xy_goal_tolerance), then a turn \
                     in place to within {} rad (yaw_goal_tolerance); goal_tolerance is not read \
                     for it; the radius latches: {} (stateful)",
                    t.xy, t.yaw, self.params.stateful
                ),
            );
        }
        Ok(goal)
    }

    /// Forgets the goal (a canceled or failed action goal): the robot stops with
    /// [`Stop::NoGoal`] from the next step on.
    pub fn clear_goal(&mut self) {
        if self.goal.take().is_some() {
            self.say(log::Level::Info, "goal cleared".into());
        }
        self.goal_yaw = None;
        self.nav = None;
        self.dirty = false;
        self.build_error = None;
        self.arrived = false;
        self.progress = None;
    }

    /// The goal in `global_frame`, if any.
    #[must_use]
    pub fn goal(&self) -> Option<Vector2<f64>> {
        self.goal
    }

    /// The goal's yaw in `global_frame` (rad, in `(−π, π]`), when the goal's orientation is
    /// used ([`Bridge::uses_goal_orientation`]) and a goal is set.
    #[must_use]
    pub fn goal_yaw(&self) -> Option<f64> {
        self.goal_yaw
    }

    /// Whether the point `g` (in `global_frame`) lies in a free cell of `/map`.
    #[must_use]
    pub fn goal_check(&self, g: Vector2<f64>) -> GoalCheck {
        use harmonav::floorplan::ros_map::Cell;
        if self.params.map_topic.is_empty() {
            return GoalCheck::Unchecked;
        }
        let Some(map) = &self.map else {
            return GoalCheck::Unchecked;
        };
        match map.pixel_at(g).and_then(|[c, r]| map.cell(c, r)) {
            None => GoalCheck::OutsideMap,
            Some(Cell::Free) => GoalCheck::Free,
            Some(Cell::Occupied) => GoalCheck::Occupied,
            Some(Cell::Unknown) => GoalCheck::Unknown,
        }
    }

    /// The robot's pose in `global_frame` (`None` before the first odometry).
    pub fn pose(&mut self, now: Instant) -> Option<Se2> {
        self.last_odom?;
        Some(self.robot_pose(now).0)
    }

    /// The perceived obstacles of the running navigator, grown by `robot_radius + margin`
    /// (what the robot's centre keeps out of), as closed outlines in `global_frame`: the
    /// obstacles the scans found (and, on a floor plan, not the map's walls). Empty without a
    /// navigator.
    #[must_use]
    pub fn obstacle_outlines(&self) -> Vec<Vec<[f64; 2]>> {
        let closed = |s: &StarShape| {
            let mut v: Vec<[f64; 2]> = s.outline().map(|p| [p.x, p.y]).collect();
            if let (Some(&first), Some(&last)) = (v.first(), v.last())
                && first != last
            {
                v.push(first);
            }
            v
        };
        match &self.nav {
            Some(Nav::Star(n)) => n.obstacles().iter().map(closed).collect(),
            // Every known obstacle in the navigator's order, those joined to the walls included.
            Some(Nav::Floor(n)) => n.known_obstacles().iter().map(closed).collect(),
            None => Vec::new(),
        }
    }

    /// The perceived obstacles ([`Bridge::obstacle_outlines`]) as a `MarkerArray` stamped
    /// `stamp`, when they changed since the last call (the first call always gives one):
    /// a `DELETEALL` (so that obstacles no longer perceived vanish), then one `LINE_STRIP` per
    /// obstacle in `global_frame` (namespace `obstacles`, ids in the navigator's order).
    pub fn obstacle_markers(&mut self, stamp: Time) -> Option<MarkerArray> {
        let outlines = self.obstacle_outlines();
        if self.markers_sent.as_ref() == Some(&outlines) {
            return None;
        }
        let header = Header {
            stamp,
            frame_id: self.params.global_frame.clone(),
        };
        let mut markers = vec![Marker {
            header: header.clone(),
            ns: "obstacles".into(),
            action: Marker::DELETEALL,
            ..Marker::default()
        }];
        for (i, o) in outlines.iter().enumerate() {
            markers.push(Marker {
                header: header.clone(),
                ns: "obstacles".into(),
                id: i32::try_from(i).unwrap_or(i32::MAX),
                kind: Marker::LINE_STRIP,
                action: Marker::ADD,
                scale: Vector3 {
                    x: 0.02,
                    y: 0.0,
                    z: 0.0,
                },
                color: ColorRGBA {
                    r: 1.0,
                    g: 0.4,
                    b: 0.0,
                    a: 1.0,
                },
                points: o
                    .iter()
                    .map(|p| Point {
                        x: p[0],
                        y: p[1],
                        z: 0.0,
                    })
                    .collect(),
                ..Marker::default()
            });
        }
        self.markers_sent = Some(outlines);
        Some(MarkerArray { markers })
    }

    /// `/map`.
    pub fn on_map(&mut self, m: &OccupancyGrid) {
        if !m.header.frame_id.is_empty()
            && m.header.frame_id.trim_start_matches('/') != self.params.global_frame
        {
            let text = format!(
                "the map's frame {:?} is taken as global_frame {:?}",
                m.header.frame_id, self.params.global_frame
            );
            self.say_once("map frame", log::Level::Warn, text);
        }
        match grid_to_ros_map(m, self.params.occupied_thresh, self.params.free_thresh) {
            Ok(map) => {
                let (w, h) = map.size();
                self.say(
                    log::Level::Info,
                    format!(
                        "map {w} × {h} at {} m/cell, {} free cells",
                        map.resolution(),
                        map.free_count()
                    ),
                );
                self.map = Some(Arc::new(map));
                self.dirty = true;
            }
            Err(e) => self.say(log::Level::Warn, e.0),
        }
    }

    /// `frame`'s pose in `ancestor`, the identity (said once) where no edge joins them, and
    /// the arrival of the oldest dynamic edge used.
    fn transform(&mut self, ancestor: &str, frame: &str, _now: Instant) -> (Se2, Option<Instant>) {
        match self.tf.lookup(ancestor, frame) {
            Lookup::Found(t, a) => (t, a),
            Lookup::Missing => {
                self.say_once(
                    &format!("identity {ancestor} {frame}"),
                    log::Level::Info,
                    format!("no transform {ancestor} → {frame} published: taken as the identity"),
                );
                (Se2::IDENTITY, None)
            }
        }
    }

    /// The robot's pose in `global_frame` through `odom_frame`, and the oldest dynamic edge.
    fn robot_pose(&mut self, now: Instant) -> (Se2, Option<Instant>) {
        let (g, o, b) = (
            self.params.global_frame.clone(),
            self.params.odom_frame.clone(),
            self.params.robot_base_frame.clone(),
        );
        let (m_o, a1) = self.transform(&g, &o, now);
        let (o_b, a2) = self.transform(&o, &b, now);
        let oldest = match (a1, a2) {
            (Some(x), Some(y)) => Some(x.min(y)),
            (x, y) => x.or(y),
        };
        (m_o.compose(&o_b), oldest)
    }

    /// `/scan`: converted and, when a navigator exists, observed at the laser's pose.
    pub fn on_scan(&mut self, m: &msgs::LaserScan, now: Instant) {
        let scan = match scan_to_harmonav(m) {
            Ok(s) => s,
            Err(e) => {
                self.say(log::Level::Warn, e.0);
                return;
            }
        };
        let period = if m.scan_time > 0.0 && m.scan_time.is_finite() {
            f64::from(m.scan_time)
        } else {
            0.1
        };
        let frame = if m.header.frame_id.is_empty() {
            self.params.robot_base_frame.clone()
        } else {
            m.header.frame_id.clone()
        };
        self.last_scan = Some(LastScan {
            scan,
            frame,
            arrival: now,
            period,
            observed: false,
        });
        if self.nav.is_some() {
            self.observe_last(now);
        }
    }

    /// Hands the latest scan to the navigator at the laser's pose.
    fn observe_last(&mut self, now: Instant) {
        let Some(frame) = self
            .last_scan
            .as_ref()
            .filter(|s| !s.observed)
            .map(|s| s.frame.clone())
        else {
            return;
        };
        let (base, _) = self.robot_pose(now);
        let (b_l, _) = self.transform(&self.params.robot_base_frame.clone(), &frame, now);
        let l = base.compose(&b_l);
        let pose = harmonav::Pose::new(l.x, l.y, l.yaw);
        let Some(last) = self.last_scan.as_mut() else {
            return;
        };
        last.observed = true;
        let result = match &mut self.nav {
            Some(Nav::Star(n)) => n.observe_scan(pose, &last.scan).map(|_| ()),
            Some(Nav::Floor(n)) => n.observe_scan(pose, &last.scan).map(|_| ()),
            None => return,
        };
        match result {
            Ok(()) => self.scan_refused = false,
            Err(e) => {
                self.scan_refused = true;
                self.say(
                    log::Level::Warn,
                    format!("scan refused by the navigator: {e}"),
                );
            }
        }
    }

    /// The navigator's options from the parameters.
    fn options(&self, law: &Law) -> Options {
        let p = &self.params;
        let base = match p.base {
            Base::Holonomic => harmonav::Base::Holonomic,
            Base::Diff => {
                let v_max = if p.v_max > 0.0 { p.v_max } else { DIFF_V_MAX };
                let base = harmonav::Base::diff(v_max, p.omega_max);
                // `Params::validate`: both limits positive, or both 0 (none).
                if p.a_max > 0.0 {
                    base.with_accel(p.a_max, p.alpha_max)
                } else {
                    base
                }
            }
        };
        let mut o = Options::default()
            .with_base(base)
            .with_robot(p.robot_radius, p.margin)
            .with_sensor(p.sensor_range, 360.0)
            .with_control_period(1.0 / p.controller_frequency);
        if p.v_max > 0.0 {
            o = o.with_v_max(p.v_max);
        }
        if let Some(s) = &self.last_scan {
            o.scan.fit_range = o.recommended_fit_range(law, s.period, s.scan.range_min);
        }
        o
    }

    fn law(&self) -> Law {
        match self.params.law {
            LawKind::Kinematic => Law::kinematic(self.params.gain),
            LawKind::Dynamic => Law::dynamic(self.params.mass, self.params.mu),
        }
    }

    /// Builds the navigator for the goal from the robot's pose: on the floor plan of `/map`,
    /// or without one in a disc around the robot; its goal heading is the goal's yaw, if used.
    fn build(&mut self, x: Vector2<f64>, goal: Vector2<f64>) -> Result<Nav, String> {
        let law = self.law();
        let options = self.options(&law);
        let p = &self.params;
        if p.map_topic.is_empty() {
            let r = p.scan_world_radius.max((goal - x).norm() + 1.0);
            let disc = StarShape::circle(x, r).map_err(|e| e.to_string())?;
            let mut nav = Navigator::new(disc, goal, law, options).map_err(|e| e.to_string())?;
            nav.set_goal_heading(self.goal_yaw)
                .map_err(|e| e.to_string())?;
            nav.set_goal_tolerance(p.goal_tolerance())
                .map_err(|e| e.to_string())?;
            nav.set_goal_stateful(p.stateful);
            return Ok(Nav::Star(Box::new(nav)));
        }
        let Some(map) = &self.map else {
            return Err("no map".into());
        };
        let floor = FloorOptions::new(p.max_element, p.robot_radius + p.margin);
        let plan: FloorMap = map
            .to_floor_map(x, goal, &MapOptions::new(floor))
            .map_err(|e| e.to_string())?;
        let mut nav =
            FloorNavigator::new(Arc::new(plan), goal, law, options).map_err(|e| e.to_string())?;
        nav.set_goal_heading(self.goal_yaw)
            .map_err(|e| e.to_string())?;
        nav.set_goal_tolerance(p.goal_tolerance())
            .map_err(|e| e.to_string())?;
        nav.set_goal_stateful(p.stateful);
        Ok(Nav::Floor(Box::new(nav)))
    }

    /// One control step at `now`: the command to publish (zero, with its reason, when
    /// stopped). Each stop is logged once when it begins.
    pub fn step(&mut self, now: Instant) -> Step {
        let mut stop = self.step_inner(now);
        if let Some(why) = self.no_progress(now, &stop) {
            self.clear_goal();
            stop = Err(Stop::NoProgress(why));
        }
        match stop {
            Ok((u, mode)) => {
                if self.last_stop.take().is_some() {
                    self.say(log::Level::Info, "moving".into());
                }
                Step {
                    twist: u,
                    stop: None,
                    mode: Some(mode),
                }
            }
            Err(stop) => {
                self.velocity = Vector2::zeros();
                if self.last_stop.as_ref() != Some(&stop) {
                    self.say(log::Level::Warn, format!("stop: {stop}"));
                    self.last_stop = Some(stop.clone());
                }
                Step {
                    twist: Twist::default(),
                    stop: Some(stop),
                    mode: None,
                }
            }
        }
    }

    /// Nav2's progress check: `Some(why)` when the robot, on its way to a goal, has not moved
    /// `required_movement_radius` from where it last did for `movement_time_allowance`.
    fn no_progress(
        &mut self,
        now: Instant,
        step: &Result<(Twist, &'static str), Stop>,
    ) -> Option<String> {
        let allowance = self.params.movement_time_allowance;
        if allowance <= 0.0 || self.goal.is_none() || self.arrived {
            return None;
        }
        let x = self.last_odom.map(|_| {
            let p = self.robot_pose(now).0;
            Vector2::new(p.x, p.y)
        });
        let radius = self.params.required_movement_radius;
        let (at, since) = self.progress.get_or_insert((None, now));
        match (*at, x) {
            (None, Some(x)) => *at = Some(x),
            (Some(b), Some(x)) if (x - b).norm() >= radius => {
                *at = Some(x);
                *since = now;
            }
            _ => {}
        }
        let waited = now.saturating_duration_since(*since).as_secs_f64();
        if waited <= allowance {
            return None;
        }
        let state = match step {
            Ok((_, mode)) => format!("commanding, mode {mode}"),
            Err(stop) => format!("stopped: {stop}"),
        };
        Some(format!(
            "moved less than {radius} m in {waited:.1} s (movement_time_allowance {allowance} s; \
             last {state})"
        ))
    }

    /// Marks the goal reached at `pose` ([`Stop::Arrived`] until the next goal), said once.
    fn reached(&mut self, pose: Se2) -> Stop {
        if !self.arrived {
            let yaw = if self.goal_yaw.is_some() {
                format!(", yaw {:.4} rad", pose.yaw)
            } else {
                String::new()
            };
            self.say(
                log::Level::Info,
                format!("goal reached at ({:.3}, {:.3}){yaw}", pose.x, pose.y),
            );
        }
        self.arrived = true;
        Stop::Arrived
    }

    fn step_inner(&mut self, now: Instant) -> Result<(Twist, &'static str), Stop> {
        let p = self.params.clone();
        let fresh = |t: Option<Instant>, timeout: f64| {
            t.is_some_and(|t| now.saturating_duration_since(t) <= Duration::from_secs_f64(timeout))
        };
        let Some(goal) = self.goal else {
            return Err(Stop::NoGoal);
        };
        if !p.map_topic.is_empty() && self.map.is_none() {
            return Err(Stop::WaitingForMap);
        }
        let (odom_ok, scan_ok) = (
            fresh(self.last_odom, p.odom_timeout),
            fresh(self.last_scan.as_ref().map(|s| s.arrival), p.scan_timeout),
        );
        // Before the first message of each, always wait; afterwards the safety stop may be
        // turned off (the tests' negative control).
        if self.last_odom.is_none() || (p.stale_stop && !odom_ok) {
            return Err(Stop::StaleOdom);
        }
        if self.last_scan.is_none() || (p.stale_stop && !scan_ok) {
            return Err(Stop::StaleScan);
        }
        let (pose, oldest) = self.robot_pose(now);
        if p.stale_stop && Buffer::stale(oldest, now, Duration::from_secs_f64(p.transform_timeout))
        {
            return Err(Stop::StaleTransform);
        }
        let x = Vector2::new(pose.x, pose.y);
        // A goal with a yaw has arrived when the navigator says so (below), not here.
        if self.arrived || (self.goal_yaw.is_none() && (x - goal).norm() <= p.arrival_radius()) {
            return Err(self.reached(pose));
        }
        if self.dirty {
            self.dirty = false;
            self.nav = None;
            let started = Instant::now();
            match self.build(x, goal) {
                Ok(nav) => {
                    self.nav = Some(nav);
                    self.build_error = None;
                    self.scan_refused = false;
                    self.velocity = Vector2::zeros();
                    self.say(
                        log::Level::Info,
                        format!(
                            "navigator built in {:.3} s ({})",
                            started.elapsed().as_secs_f64(),
                            if p.map_topic.is_empty() {
                                "disc from scans"
                            } else {
                                "floor plan from /map"
                            }
                        ),
                    );
                    // The latest scan is observed before the first command.
                    if let Some(s) = self.last_scan.as_mut() {
                        s.observed = false;
                    }
                    self.observe_last(now);
                }
                Err(e) => self.build_error = Some(e),
            }
        }
        if let Some(e) = &self.build_error {
            return Err(Stop::NoNavigator(e.clone()));
        }
        if self.scan_refused {
            return Err(Stop::ScanRefused);
        }
        if p.base == Base::Diff {
            // (v, ω) by aligned descent on a certified arc (harmonav's `command_pose`).
            let result = match &mut self.nav {
                Some(Nav::Star(n)) => n.command_pose(x, pose.yaw).map_err(|e| e.to_string()),
                Some(Nav::Floor(n)) => n.command_pose(x, pose.yaw).map_err(|e| e.to_string()),
                None => return Err(Stop::NoNavigator("not built".into())),
            };
            let cmd = result.map_err(Stop::Refused)?;
            if cmd.mode == Mode::Halted {
                return Err(Stop::ScanRefused);
            }
            if cmd.steer == Steer::Arrived {
                // At the position and the goal yaw (`Params::goal_tolerance`): (0, 0).
                return Err(self.reached(pose));
            }
            return Ok((
                Twist {
                    linear: Vector3 {
                        x: cmd.v,
                        y: 0.0,
                        z: 0.0,
                    },
                    angular: Vector3 {
                        x: 0.0,
                        y: 0.0,
                        z: cmd.omega,
                    },
                },
                cmd.mode.as_str(),
            ));
        }
        let h = 1.0 / p.controller_frequency;
        let v = self.velocity;
        let result = match &mut self.nav {
            Some(Nav::Star(n)) => command(n, x, v),
            Some(Nav::Floor(n)) => command(n, x, v),
            None => return Err(Stop::NoNavigator("not built".into())),
        };
        let cmd = result.map_err(Stop::Refused)?;
        if cmd.mode == Mode::Halted {
            return Err(Stop::ScanRefused);
        }
        let u = match p.law {
            LawKind::Kinematic => cmd.value,
            LawKind::Dynamic => {
                self.velocity = v + h * cmd.value / p.mass;
                self.velocity
            }
        };
        // The holonomic base: the velocity in the base frame.
        let b = pose.inverse().rotate([u.x, u.y]);
        Ok((
            Twist {
                linear: Vector3 {
                    x: b[0],
                    y: b[1],
                    z: 0.0,
                },
                angular: Vector3::default(),
            },
            cmd.mode.as_str(),
        ))
    }
}

/// The goal's yaw from its orientation, the yaw of the normalised quaternion.
///
/// # Errors
/// A quaternion that is not a rotation: a component not finite, or all four (near) zero.
fn goal_yaw(q: &msgs::Quaternion) -> Result<f64, BadMessage> {
    q.yaw().ok_or_else(|| {
        BadMessage(format!(
            "goal dropped: its orientation ({}, {}, {}, {}) is not a rotation (a component not \
             finite, or all zero; for no orientation send the identity, w = 1)",
            q.x, q.y, q.z, q.w
        ))
    })
}

/// The navigator's command at `x` (velocity state `v`), its error as text.
fn command<W: World>(
    nav: &mut Navigator<W>,
    x: Vector2<f64>,
    v: Vector2<f64>,
) -> Result<harmonav::Command, String> {
    nav.command(x, v).map_err(|e| e.to_string())
}

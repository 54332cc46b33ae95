//! The node's logic without DDS ([`Bridge`]): REP 117's range classes, every bad message, the
//! grid → map_server pipeline, the stops, and closed loops of a holonomic robot through ROS
//! messages (a disc from scans alone, and the floor plan of an occupancy grid), with a
//! negative control of the stale-scan stop; and a differential drive that finishes at the
//! goal's yaw (with its negative control, `use_goal_orientation: false`).

use std::time::{Duration, Instant};

use harmonav::perception::Reading;
use harmonav_ros2::bridge::{Bridge, Stop, grid_cell, grid_to_ros_map, scan_to_harmonav};
use harmonav_ros2::msgs::*;
use harmonav_ros2::params::Params;

fn scan_msg(ranges: Vec<f32>, increment: f32) -> LaserScan {
    LaserScan {
        header: Header {
            stamp: Time::default(),
            frame_id: "laser".into(),
        },
        angle_min: -1.0,
        angle_max: -1.0 + increment * (ranges.len().max(1) - 1) as f32,
        angle_increment: increment,
        time_increment: 0.0,
        scan_time: 0.05,
        range_min: 0.1,
        range_max: 10.0,
        ranges,
        intensities: vec![],
    }
}

#[test]
fn rep_117_range_classes() {
    let m = scan_msg(
        vec![
            1.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            0.05,
            10.0,
            12.0,
            0.1,
        ],
        0.1,
    );
    let s = scan_to_harmonav(&m).unwrap();
    let classes: Vec<Reading> = (0..s.ranges.len()).map(|i| s.reading(i)).collect();
    assert_eq!(
        classes,
        vec![
            Reading::Hit(1.0),
            Reading::NoReturn, // +Inf: no return
            Reading::TooClose, // −Inf: nearer than range_min
            Reading::Invalid,  // NaN: an error
            Reading::Invalid,  // below range_min
            Reading::NoReturn, // at range_max
            Reading::NoReturn, // beyond
            Reading::Hit(f64::from(0.1f32)),
        ]
    );
}

#[test]
fn bad_scans_are_dropped_with_their_reason() {
    let ok = scan_msg(vec![1.0; 4], 0.1);
    assert!(scan_to_harmonav(&ok).is_ok());
    let cases: Vec<(LaserScan, &str)> = vec![
        (scan_msg(vec![1.0; 4], -0.1), "angle_increment"),
        (scan_msg(vec![1.0; 4], 0.0), "angle_increment"),
        (scan_msg(vec![], 0.1), "no ranges"),
        (
            LaserScan {
                angle_min: f32::NAN,
                ..ok.clone()
            },
            "angle_min",
        ),
        (
            LaserScan {
                range_max: 0.05,
                ..ok.clone()
            },
            "range limits",
        ),
        (
            LaserScan {
                range_min: -1.0,
                ..ok.clone()
            },
            "range limits",
        ),
        (
            LaserScan {
                range_max: f32::INFINITY,
                ..ok.clone()
            },
            "range_max",
        ),
    ];
    for (m, why) in cases {
        let e = scan_to_harmonav(&m).unwrap_err();
        assert!(e.0.contains(why), "{e} should name {why}");
    }
}

/// A grid: `w × h` cells of `res`, origin `(ox, oy)`, row 0 at the bottom.
fn grid(w: u32, h: u32, res: f32, origin: (f64, f64), f: impl Fn(f64, f64) -> i8) -> OccupancyGrid {
    let mut data = Vec::with_capacity((w * h) as usize);
    for r in 0..h {
        for c in 0..w {
            let x = origin.0 + (f64::from(c) + 0.5) * f64::from(res);
            let y = origin.1 + (f64::from(r) + 0.5) * f64::from(res);
            data.push(f(x, y));
        }
    }
    OccupancyGrid {
        header: Header {
            stamp: Time::default(),
            frame_id: "map".into(),
        },
        info: MapMetaData {
            map_load_time: Time::default(),
            resolution: res,
            width: w,
            height: h,
            origin: Pose {
                position: Point {
                    x: origin.0,
                    y: origin.1,
                    z: 0.0,
                },
                orientation: Quaternion::default(),
            },
        },
        data,
    }
}

#[test]
fn grid_through_the_map_server_pipeline() {
    use harmonav::floorplan::ros_map::Cell;
    // 3 × 2: bottom row [0, 100, −1], top row [50, 20, 101].
    let mut g = grid(3, 2, 0.5, (-1.0, 2.0), |_, _| 0);
    g.data = vec![0, 100, -1, 50, 20, 101];
    let m = grid_to_ros_map(&g, 0.65, 0.25).unwrap();
    assert_eq!(m.size(), (3, 2));
    assert_eq!(m.resolution(), 0.5);
    assert_eq!(m.origin(), [-1.0, 2.0, 0.0]);
    // The image's row 0 is the grid's top row.
    let cells: Vec<Cell> = [(0, 1), (1, 1), (2, 1), (0, 0), (1, 0), (2, 0)]
        .iter()
        .map(|&(c, r)| m.cell(c, r).unwrap())
        .collect();
    assert_eq!(
        cells,
        vec![
            Cell::Free,
            Cell::Occupied,
            Cell::Unknown,
            Cell::Unknown,
            Cell::Free,
            Cell::Unknown
        ]
    );
    assert_eq!(grid_cell(65, 0.65, 0.25), Cell::Unknown); // ties are not occupied…
    assert_eq!(grid_cell(25, 0.65, 0.25), Cell::Unknown); // …nor free
    assert_eq!(grid_cell(66, 0.65, 0.25), Cell::Occupied);
    // Bad grids.
    let mut bad = g.clone();
    bad.data.pop();
    assert!(
        grid_to_ros_map(&bad, 0.65, 0.25)
            .unwrap_err()
            .0
            .contains("does not match")
    );
    let mut bad = g.clone();
    bad.info.resolution = 0.0;
    assert!(grid_to_ros_map(&bad, 0.65, 0.25).is_err());
    let mut bad = g.clone();
    bad.info.origin.position.x = f64::NAN;
    assert!(grid_to_ros_map(&bad, 0.65, 0.25).is_err());
    let mut bad = g.clone();
    bad.info.width = 0;
    bad.data.clear();
    assert!(grid_to_ros_map(&bad, 0.65, 0.25).is_err());
    let mut bad = g;
    bad.info.origin.orientation = Quaternion {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 0.0,
    };
    assert!(grid_to_ros_map(&bad, 0.65, 0.25).is_err());
}

/// The simulated robot: a holonomic disc with a laser 0.1 m ahead of its centre, heading
/// `YAW` (so base and map frames differ), ray-cast against an occupancy grid.
struct Sim {
    grid: OccupancyGrid,
    x: [f64; 2],
    /// The heading: constant for a holonomic base, integrated for a differential drive.
    yaw: f64,
    diff: bool,
    t: Instant,
    steps: u32,
}

impl Sim {
    fn new(grid: OccupancyGrid, x: [f64; 2]) -> Self {
        Self {
            grid,
            x,
            yaw: YAW,
            diff: false,
            t: Instant::now(),
            steps: 0,
        }
    }
}

const YAW: f64 = 0.3;
const H: f64 = 0.05;
const BEAMS: usize = 360;

impl Sim {
    fn occupied(&self, x: f64, y: f64) -> bool {
        let i = &self.grid.info;
        let res = f64::from(i.resolution);
        let c = ((x - i.origin.position.x) / res).floor();
        let r = ((y - i.origin.position.y) / res).floor();
        if c < 0.0 || r < 0.0 || c >= f64::from(i.width) || r >= f64::from(i.height) {
            return true;
        }
        self.grid.data[r as usize * i.width as usize + c as usize] != 0
    }

    /// The clearance of the robot's centre to the nearest occupied cell (by sampling a disc).
    fn clearance(&self) -> f64 {
        let mut d = f64::INFINITY;
        for k in 0..72 {
            let a = f64::from(k) * std::f64::consts::TAU / 72.0;
            let mut r = 0.0;
            while r < 0.5 {
                if self.occupied(self.x[0] + r * a.cos(), self.x[1] + r * a.sin()) {
                    d = d.min(r);
                    break;
                }
                r += 0.005;
            }
        }
        d
    }

    fn laser(&self) -> [f64; 2] {
        [
            self.x[0] + 0.1 * self.yaw.cos(),
            self.x[1] + 0.1 * self.yaw.sin(),
        ]
    }

    fn scan(&self) -> LaserScan {
        let l = self.laser();
        let inc = std::f64::consts::TAU / BEAMS as f64;
        let ranges = (0..BEAMS)
            .map(|i| {
                let a = self.yaw - std::f64::consts::PI + i as f64 * inc;
                let mut r = 0.0;
                while r < 3.5 {
                    if self.occupied(l[0] + r * a.cos(), l[1] + r * a.sin()) {
                        return r as f32;
                    }
                    r += 0.01;
                }
                f32::INFINITY
            })
            .collect();
        LaserScan {
            header: Header {
                stamp: self.stamp(),
                frame_id: "laser".into(),
            },
            angle_min: -std::f32::consts::PI,
            angle_max: std::f32::consts::PI - inc as f32,
            angle_increment: inc as f32,
            time_increment: 0.0,
            scan_time: H as f32,
            range_min: 0.05,
            range_max: 3.5,
            ranges,
            intensities: vec![],
        }
    }

    fn stamp(&self) -> Time {
        Time::from_seconds(100.0 + f64::from(self.steps) * H)
    }

    fn odom(&self) -> Odometry {
        Odometry {
            header: Header {
                stamp: self.stamp(),
                frame_id: "odom".into(),
            },
            child_frame_id: "base_link".into(),
            pose: PoseWithCovariance {
                pose: Pose {
                    position: Point {
                        x: self.x[0],
                        y: self.x[1],
                        z: 0.0,
                    },
                    orientation: Quaternion::from_yaw(self.yaw),
                },
                covariance: Covariance::default(),
            },
            twist: TwistWithCovariance::default(),
        }
    }

    /// Publishes odometry (and a scan if `scans`), steps the bridge, integrates its twist.
    fn step(&mut self, bridge: &mut Bridge, scans: bool) -> harmonav_ros2::bridge::Step {
        self.t += Duration::from_secs_f64(H);
        self.steps += 1;
        bridge.on_odom(&self.odom(), self.t);
        if scans {
            bridge.on_scan(&self.scan(), self.t);
        }
        let s = bridge.step(self.t);
        if self.diff {
            // The unicycle, exactly over the period (an arc).
            let pose = harmonav::unicycle_arc(
                harmonav::Vector2::new(self.x[0], self.x[1]),
                self.yaw,
                s.twist.linear.x,
                s.twist.angular.z,
                H,
            );
            assert_eq!(s.twist.linear.y, 0.0, "a diff base moves no sideways");
            self.x = [pose.0.x, pose.0.y];
            self.yaw = pose.1;
        } else {
            let (sn, cs) = self.yaw.sin_cos();
            let (vx, vy) = (s.twist.linear.x, s.twist.linear.y);
            self.x[0] += H * (cs * vx - sn * vy);
            self.x[1] += H * (sn * vx + cs * vy);
        }
        s
    }
}

fn laser_static() -> TFMessage {
    TFMessage {
        transforms: vec![TransformStamped {
            header: Header {
                stamp: Time::default(),
                frame_id: "base_link".into(),
            },
            child_frame_id: "laser".into(),
            transform: Transform {
                translation: Vector3 {
                    x: 0.1,
                    y: 0.0,
                    z: 0.2,
                },
                rotation: Quaternion::default(),
            },
        }],
    }
}

fn goal(x: f64, y: f64) -> PoseStamped {
    PoseStamped {
        header: Header {
            stamp: Time::default(),
            frame_id: "map".into(),
        },
        pose: Pose {
            position: Point { x, y, z: 0.0 },
            orientation: Quaternion::default(),
        },
    }
}

/// Runs to arrival (or `max` steps); returns the smallest clearance met.
fn fly(sim: &mut Sim, bridge: &mut Bridge, g: [f64; 2], max: u32) -> f64 {
    let mut clearance = f64::INFINITY;
    for _ in 0..max {
        let s = sim.step(bridge, true);
        clearance = clearance.min(sim.clearance());
        if s.stop == Some(Stop::Arrived) {
            break;
        }
        if let Some(stop) = &s.stop {
            assert!(
                matches!(stop, Stop::StaleScan | Stop::StaleOdom),
                "stopped: {stop} at {:?}; log: {:?}",
                sim.x,
                bridge.drain_log()
            );
        }
    }
    let d = ((sim.x[0] - g[0]).powi(2) + (sim.x[1] - g[1]).powi(2)).sqrt();
    assert!(
        d <= 0.1 + 1e-9,
        "not arrived: {:?} is {d:.3} m from the goal after {} steps; log: {:?}",
        sim.x,
        sim.steps,
        bridge.drain_log()
    );
    clearance
}

/// A 20 m room (walls never seen: the lidar reaches 3.5 m) with a disc of radius 0.4 across
/// the straight line; no map: the disc around the robot from scans alone.
fn open_room() -> OccupancyGrid {
    grid(400, 400, 0.05, (0.0, 0.0), |x, y| {
        let wall = !(0.5..19.5).contains(&x) || !(0.5..19.5).contains(&y);
        let blob = (x - 10.0).powi(2) + (y - 10.1).powi(2) < 0.4 * 0.4;
        if wall || blob { 100 } else { 0 }
    })
}

/// A bridge with `params` and the robot at (8, 10) in [`open_room`], the laser's static
/// transform given.
fn in_open_room(params: Params) -> (Bridge, Sim) {
    let mut bridge = Bridge::new(params);
    let sim = Sim::new(open_room(), [8.0, 10.0]);
    bridge.on_tf(&laser_static(), sim.t, true);
    (bridge, sim)
}

#[test]
fn scans_alone_arrive_and_stop_when_scans_stop() {
    let params = Params {
        map_topic: String::new(),
        ..Params::default()
    };
    let (mut bridge, mut sim) = in_open_room(params.clone());
    // No goal yet: zero, and why.
    assert_eq!(sim.step(&mut bridge, true).stop, Some(Stop::NoGoal));
    bridge.on_goal(&goal(12.0, 10.0), sim.t);
    let clearance = fly(&mut sim, &mut bridge, [12.0, 10.0], 4000);
    assert!(
        clearance > params.robot_radius,
        "contact: clearance {clearance}"
    );
    let log: Vec<String> = bridge.drain_log().into_iter().map(|(_, t)| t).collect();
    // map → odom never published: the identity, said once.
    assert_eq!(
        log.iter()
            .filter(|l| l.contains("no transform map → odom"))
            .count(),
        1,
        "{log:?}"
    );

    // Scans stop mid-way to a new goal: zero within the timeout, said once.
    bridge.on_goal(&goal(9.0, 10.5), sim.t);
    for _ in 0..10 {
        assert_eq!(sim.step(&mut bridge, true).stop, None);
    }
    let mut stopped_after = None;
    for k in 1..=40 {
        let s = sim.step(&mut bridge, false);
        if s.stop == Some(Stop::StaleScan) {
            assert_eq!(s.twist, Twist::default());
            stopped_after = Some(f64::from(k) * H);
            break;
        }
    }
    let after = stopped_after.expect("no stop without scans");
    assert!(
        after <= params.scan_timeout + H + 1e-9,
        "stopped after {after} s"
    );
    let stops = bridge
        .drain_log()
        .into_iter()
        .filter(|(_, t)| t.contains("scan missing or stale"))
        .count();
    assert_eq!(stops, 1);
}

/// The negative control: with the safety stop off, the same stale-scan case keeps moving.
#[test]
fn negative_control_without_the_stale_stop() {
    let params = Params {
        map_topic: String::new(),
        stale_stop: false,
        ..Params::default()
    };
    let mut bridge = Bridge::new(params);
    let mut sim = Sim::new(open_room(), [8.0, 10.0]);
    bridge.on_goal(&goal(12.0, 10.0), sim.t);
    for _ in 0..10 {
        sim.step(&mut bridge, true);
    }
    for _ in 0..40 {
        let s = sim.step(&mut bridge, false);
        assert_ne!(s.stop, Some(Stop::StaleScan));
    }
    let last = sim.step(&mut bridge, false);
    assert!(last.twist.linear.x.hypot(last.twist.linear.y) > 0.0);
}

#[test]
fn floor_plan_from_an_occupancy_grid() {
    // 4 × 3 m inside walls 0.1 m thick, a 0.8 × 1.0 m box in the middle.
    let room = grid(84, 64, 0.05, (-0.1, -0.1), |x, y| {
        let wall = !(0.0..4.0).contains(&x) || !(0.0..3.0).contains(&y);
        let bx = (1.6..2.4).contains(&x) && (1.0..2.0).contains(&y);
        if wall || bx { 100 } else { 0 }
    });
    let params = Params::default();
    let mut bridge = Bridge::new(params.clone());
    let mut sim = Sim::new(room.clone(), [0.6, 0.6]);
    bridge.on_tf(&laser_static(), sim.t, true);
    bridge.on_goal(&goal(3.4, 2.4), sim.t);
    // No map yet: waiting for it, with fresh scans and odometry.
    assert_eq!(sim.step(&mut bridge, true).stop, Some(Stop::WaitingForMap));
    bridge.on_map(&room);
    let clearance = fly(&mut sim, &mut bridge, [3.4, 2.4], 4000);
    assert!(
        clearance > params.robot_radius,
        "contact: clearance {clearance}"
    );
}

/// A differential-drive base (`base: diff`): `(linear.x, angular.z)` from harmonav's
/// `command_pose`, integrated as a unicycle, arrives without contact.
#[test]
fn differential_drive_from_scans_alone() {
    let params = Params {
        map_topic: String::new(),
        base: harmonav_ros2::params::Base::Diff,
        ..Params::default()
    };
    let mut bridge = Bridge::new(params.clone());
    let mut sim = Sim::new(open_room(), [8.0, 10.0]);
    sim.diff = true;
    sim.yaw = 2.0; // facing away from the goal: it must turn first
    bridge.on_tf(&laser_static(), sim.t, true);
    bridge.on_goal(&goal(12.0, 10.0), sim.t);
    let clearance = fly(&mut sim, &mut bridge, [12.0, 10.0], 4000);
    assert!(
        clearance > params.robot_radius,
        "contact: clearance {clearance}"
    );
}

#[test]
fn bad_odometry_and_goals_are_dropped_and_stale_odometry_stops() {
    let params = Params {
        map_topic: String::new(),
        ..Params::default()
    };
    let mut bridge = Bridge::new(params);
    let t0 = Instant::now();
    let mut sim = Sim::new(open_room(), [8.0, 10.0]);
    let mut bad = sim.odom();
    bad.pose.pose.position.x = f64::NAN;
    bridge.on_odom(&bad, t0);
    let mut g = goal(f64::INFINITY, 0.0);
    bridge.on_goal(&g, t0);
    assert_eq!(bridge.step(t0).stop, Some(Stop::NoGoal));
    g.pose.position.x = 12.0;
    bridge.on_goal(&g, t0);
    // Goal given, no odometry: stopped for it.
    assert_eq!(bridge.step(t0).stop, Some(Stop::StaleOdom));
    let log: Vec<String> = bridge.drain_log().into_iter().map(|(_, t)| t).collect();
    assert!(
        log.iter().any(|l| l.contains("odometry dropped")),
        "{log:?}"
    );
    assert!(log.iter().any(|l| l.contains("goal dropped")), "{log:?}");
    for _ in 0..5 {
        sim.step(&mut bridge, true);
    }
    // Odometry stops; scans go on.
    sim.t += Duration::from_secs_f64(0.6);
    bridge.on_scan(&sim.scan(), sim.t);
    assert_eq!(bridge.step(sim.t).stop, Some(Stop::StaleOdom));
}

// The navigate_to_pose action's state machine ([`Navigate`]) over the same simulated robot.

use harmonav_ros2::action::{Navigate, Reply, code};
use ros2_client::action::{GoalId, GoalInfo, GoalStatusEnum};
use ros2_client::action_msgs::CancelGoalResponseEnum;
use ros2_client::builtin_interfaces::Time as RosTime;

fn nav_goal(x: f64, y: f64) -> NavigateToPoseGoal {
    NavigateToPoseGoal {
        pose: goal(x, y),
        behavior_tree: String::new(),
    }
}

/// One step of the robot, then the action's: the feedback, if a goal runs.
fn action_step(
    sim: &mut Sim,
    bridge: &mut Bridge,
    nav: &mut Navigate<u32>,
) -> (harmonav_ros2::bridge::Step, Option<NavigateToPoseFeedback>) {
    let s = sim.step(bridge, true);
    let f = nav.after_step(&s, bridge, sim.t, Time::default());
    (s, f.map(|(_, f)| f))
}

fn cancel_of(id: GoalId) -> GoalInfo {
    GoalInfo {
        goal_id: id,
        stamp: RosTime::ZERO,
    }
}

/// A goal through the action: feedback while it runs (the robot's pose, the distance falling
/// to the tolerance), then succeeded, answered to the result request that waited for it.
#[test]
fn action_goal_succeeds_with_feedback() {
    let params = Params {
        map_topic: String::new(),
        ..Params::default()
    };
    let (mut bridge, mut sim) = in_open_room(params.clone());
    let mut nav: Navigate<u32> = Navigate::new();
    sim.step(&mut bridge, true);
    let id = GoalId::new_random();
    assert!(nav.send_goal(id, &nav_goal(12.0, 10.0), &mut bridge, sim.t, RosTime::ZERO));
    assert_eq!(nav.active(), Some(id));
    nav.result_request(id, 7);
    assert!(nav.take_replies().is_empty(), "answered before the end");
    let status = nav.take_status().expect("a status after acceptance");
    assert_eq!(status.status_list[0].status, GoalStatusEnum::Executing);
    let mut distances = Vec::new();
    for _ in 0..4000 {
        let (s, f) = action_step(&mut sim, &mut bridge, &mut nav);
        if let Some(f) = f {
            let p = &f.current_pose.pose.position;
            assert!((p.x - sim.x[0]).abs() < 0.1 && (p.y - sim.x[1]).abs() < 0.1);
            assert_eq!(f.current_pose.header.frame_id, "map");
            distances.push(f.distance_remaining);
        }
        if s.stop == Some(Stop::Arrived) {
            break;
        }
    }
    assert_eq!(nav.status(id), Some(GoalStatusEnum::Succeeded));
    assert_eq!(nav.active(), None);
    assert_eq!(
        nav.take_replies(),
        vec![Reply {
            to: 7,
            status: GoalStatusEnum::Succeeded,
            result: NavigateToPoseResult::default(),
        }]
    );
    let first = distances[0];
    let last = *distances.last().unwrap();
    assert!((first - 4.0).abs() < 0.1, "first distance {first}");
    assert!(last < 0.2 && last < first, "last distance {last}");
    // Finished goals answer at once.
    nav.result_request(id, 8);
    assert_eq!(nav.take_replies()[0].status, GoalStatusEnum::Succeeded);
    // No feedback without a running goal.
    assert!(action_step(&mut sim, &mut bridge, &mut nav).1.is_none());
}

/// A new goal preempts the running one (aborted, with its result), a pose on `/goal_pose` too;
/// a cancel stops the robot at the next command and ends the goal canceled; cancels of
/// finished and unknown goals, duplicate ids and non-finite goals are answered as ROS says.
#[test]
fn action_preempt_cancel_and_refusals() {
    let params = Params {
        map_topic: String::new(),
        ..Params::default()
    };
    let (mut bridge, mut sim) = in_open_room(params);
    let mut nav: Navigate<u32> = Navigate::new();
    let a = GoalId::new_random();
    assert!(nav.send_goal(a, &nav_goal(12.0, 10.0), &mut bridge, sim.t, RosTime::ZERO));
    nav.result_request(a, 1);
    for _ in 0..10 {
        action_step(&mut sim, &mut bridge, &mut nav);
    }
    let b = GoalId::new_random();
    assert!(nav.send_goal(b, &nav_goal(8.0, 11.5), &mut bridge, sim.t, RosTime::ZERO));
    let replies = nav.take_replies();
    assert_eq!(replies.len(), 1);
    assert_eq!(
        (replies[0].to, replies[0].status),
        (1, GoalStatusEnum::Aborted)
    );
    assert!(replies[0].result.error_msg.contains("preempted"));
    assert_eq!(nav.active(), Some(b));
    assert_eq!(bridge.goal().map(|g| (g.x, g.y)), Some((8.0, 11.5)));

    // A duplicate id and a non-finite goal are rejected; b runs on.
    assert!(!nav.send_goal(b, &nav_goal(9.0, 9.0), &mut bridge, sim.t, RosTime::ZERO));
    let c = GoalId::new_random();
    assert!(!nav.send_goal(
        c,
        &nav_goal(f64::NAN, 9.0),
        &mut bridge,
        sim.t,
        RosTime::ZERO
    ));
    assert_eq!(nav.status(c), None);
    assert_eq!(nav.active(), Some(b));
    assert_eq!(bridge.goal().map(|g| (g.x, g.y)), Some((8.0, 11.5)));
    let mut moving = false;
    for _ in 0..10 {
        let (s, f) = action_step(&mut sim, &mut bridge, &mut nav);
        moving |= s.twist.linear.x.hypot(s.twist.linear.y) > 1e-3;
        assert!(f.is_some());
    }
    assert!(moving);

    // Cancel b: the next command is zero.
    let r = nav.cancel(&cancel_of(b), &mut bridge);
    assert_eq!(r.return_code, CancelGoalResponseEnum::None);
    assert_eq!(r.goals_canceling.len(), 1);
    assert_eq!(r.goals_canceling[0].goal_id, b);
    assert_eq!(nav.status(b), Some(GoalStatusEnum::Canceled));
    let (s, f) = action_step(&mut sim, &mut bridge, &mut nav);
    assert_eq!(
        (s.twist, s.stop, f),
        (Twist::default(), Some(Stop::NoGoal), None)
    );
    nav.result_request(b, 2);
    let replies = nav.take_replies();
    assert_eq!(
        (replies[0].to, replies[0].status),
        (2, GoalStatusEnum::Canceled)
    );

    // Cancels of a finished goal, of an unknown one, and of all (none running).
    let r = nav.cancel(&cancel_of(b), &mut bridge);
    assert_eq!(r.return_code, CancelGoalResponseEnum::GoalTerminated);
    let r = nav.cancel(&cancel_of(GoalId::new_random()), &mut bridge);
    assert_eq!(r.return_code, CancelGoalResponseEnum::UnknownGoal);
    let r = nav.cancel(&cancel_of(GoalId::ZERO), &mut bridge);
    assert_eq!(
        (r.return_code, r.goals_canceling.len()),
        (CancelGoalResponseEnum::None, 0)
    );
    // The result of a goal never seen: status unknown.
    nav.result_request(GoalId::new_random(), 3);
    assert_eq!(nav.take_replies()[0].status, GoalStatusEnum::Unknown);

    // A pose on /goal_pose preempts a running action goal; a zero-id cancel cancels all.
    let d = GoalId::new_random();
    assert!(nav.send_goal(d, &nav_goal(9.0, 9.0), &mut bridge, sim.t, RosTime::ZERO));
    nav.goal_topic(&goal(10.0, 10.0), &mut bridge, sim.t);
    assert_eq!(nav.status(d), Some(GoalStatusEnum::Aborted));
    assert_eq!(nav.active(), None);
    assert_eq!(bridge.goal().map(|g| (g.x, g.y)), Some((10.0, 10.0)));
    let e = GoalId::new_random();
    assert!(nav.send_goal(e, &nav_goal(9.0, 9.0), &mut bridge, sim.t, RosTime::ZERO));
    let r = nav.cancel(&cancel_of(GoalId::ZERO), &mut bridge);
    assert_eq!(r.goals_canceling.len(), 1);
    assert_eq!(nav.status(e), Some(GoalStatusEnum::Canceled));
    // Every change was in a status array; the last lists every goal kept.
    let last = nav.take_status().unwrap();
    assert_eq!(last.status_list.len(), 4);
    nav.shutdown();
}

/// Goals not in free space on `/map` are accepted and aborted at once with Nav2's planner
/// codes; a goal the navigator cannot be built for (too near a wall for the robot's radius)
/// is aborted at the first step. Each time the robot stops.
#[test]
fn action_refused_goals_abort_with_codes() {
    let room = grid(84, 64, 0.05, (-0.1, -0.1), |x, y| {
        let wall = !(0.0..4.0).contains(&x) || !(0.0..3.0).contains(&y);
        let bx = (1.6..2.4).contains(&x) && (1.0..2.0).contains(&y);
        if wall || bx { 100 } else { 0 }
    });
    let mut bridge = Bridge::new(Params::default());
    let mut nav: Navigate<u32> = Navigate::new();
    let mut sim = Sim::new(room.clone(), [0.6, 0.6]);
    bridge.on_tf(&laser_static(), sim.t, true);
    bridge.on_map(&room);
    for (g, want) in [
        ((2.0, 1.5), code::GOAL_OCCUPIED),
        ((10.0, 1.5), code::GOAL_OUTSIDE_MAP),
    ] {
        let id = GoalId::new_random();
        assert!(nav.send_goal(id, &nav_goal(g.0, g.1), &mut bridge, sim.t, RosTime::ZERO));
        assert_eq!(nav.status(id), Some(GoalStatusEnum::Aborted));
        let r = nav.result(id).unwrap();
        assert_eq!(r.error_code, want, "{}", r.error_msg);
        assert_eq!(bridge.goal(), None);
        let (s, _) = action_step(&mut sim, &mut bridge, &mut nav);
        assert_eq!((s.twist, s.stop), (Twist::default(), Some(Stop::NoGoal)));
    }
    let id = GoalId::new_random();
    assert!(nav.send_goal(id, &nav_goal(0.03, 1.5), &mut bridge, sim.t, RosTime::ZERO));
    assert_eq!(nav.status(id), Some(GoalStatusEnum::Executing));
    let (s, f) = action_step(&mut sim, &mut bridge, &mut nav);
    assert_eq!((s.twist, f), (Twist::default(), None));
    assert_eq!(nav.status(id), Some(GoalStatusEnum::Aborted));
    let r = nav.result(id).unwrap();
    assert_eq!(r.error_code, code::NO_VALID_PATH, "{r:?}");
    assert!(!r.error_msg.is_empty());
    assert_eq!(
        action_step(&mut sim, &mut bridge, &mut nav).0.stop,
        Some(Stop::NoGoal)
    );
}

/// One period of a robot whose wheels do not turn: odometry (and a scan if `scans`) from the
/// same pose, the bridge stepped, its command not integrated.
fn stuck_step(sim: &mut Sim, bridge: &mut Bridge, scans: bool) -> harmonav_ros2::bridge::Step {
    sim.t += Duration::from_secs_f64(H);
    sim.steps += 1;
    bridge.on_odom(&sim.odom(), sim.t);
    if scans {
        bridge.on_scan(&sim.scan(), sim.t);
    }
    bridge.step(sim.t)
}

/// Nav2's progress check. A robot that commands but does not move (stuck wheels) is given up
/// after `movement_time_allowance`: the action goal aborted with `FAILED_TO_MAKE_PROGRESS` and
/// a message that says why, the robot stopped from then on. So is one that stands because its
/// scans stopped (a goal from `/goal_pose`: dropped, said once). A robot on its way is not,
/// though its drive is longer than the allowance; and `movement_time_allowance: 0` never gives
/// up (the negative control).
#[test]
fn a_goal_without_progress_is_aborted_and_the_robot_stopped() {
    let allowance = 2.0;
    let params = Params {
        map_topic: String::new(),
        movement_time_allowance: allowance,
        ..Params::default()
    };

    // 1. Stuck wheels, an action goal.
    let (mut bridge, mut sim) = in_open_room(params.clone());
    let mut nav: Navigate<u32> = Navigate::new();
    let id = GoalId::new_random();
    let start = sim.t;
    assert!(nav.send_goal(id, &nav_goal(12.0, 10.0), &mut bridge, sim.t, RosTime::ZERO));
    nav.result_request(id, 1);
    let mut commanded = false;
    let mut given_up = None;
    for _ in 0..200 {
        let s = stuck_step(&mut sim, &mut bridge, true);
        let f = nav.after_step(&s, &mut bridge, sim.t, Time::default());
        if let Some(Stop::NoProgress(why)) = &s.stop {
            assert_eq!(s.twist, Twist::default());
            assert!(f.is_none());
            given_up = Some(((sim.t - start).as_secs_f64(), why.clone()));
            break;
        }
        commanded |= s.stop.is_none() && s.twist.linear.x.hypot(s.twist.linear.y) > 1e-3;
    }
    assert!(commanded, "the navigator never commanded");
    let (after, why) = given_up.expect("a stuck robot was never given up");
    assert!(
        after > allowance && after <= allowance + H + 1e-9,
        "given up after {after} s"
    );
    assert!(why.contains("movement_time_allowance"), "{why}");
    assert!(why.contains("commanding"), "{why}");
    assert_eq!(nav.status(id), Some(GoalStatusEnum::Aborted));
    let r = nav.result(id).unwrap();
    assert_eq!(r.error_code, code::FAILED_TO_MAKE_PROGRESS);
    assert_eq!(code::FAILED_TO_MAKE_PROGRESS, 105);
    assert!(r.error_msg.contains("failed to make progress"), "{r:?}");
    let replies = nav.take_replies();
    assert_eq!(
        (replies[0].to, replies[0].status),
        (1, GoalStatusEnum::Aborted)
    );
    assert_eq!(bridge.goal(), None);
    for _ in 0..5 {
        let s = stuck_step(&mut sim, &mut bridge, true);
        assert_eq!((s.twist, s.stop), (Twist::default(), Some(Stop::NoGoal)));
    }

    // 2. Scans stop on the way (a goal from the topic): stale, then given up.
    let (mut bridge, mut sim) = in_open_room(params.clone());
    bridge.on_goal(&goal(12.0, 10.0), sim.t);
    for _ in 0..5 {
        assert_eq!(sim.step(&mut bridge, true).stop, None);
    }
    let mut stops = Vec::new();
    for _ in 0..100 {
        let s = sim.step(&mut bridge, false);
        if let Some(stop) = s.stop {
            if stops.last() != Some(&stop) {
                stops.push(stop.clone());
            }
            if matches!(stop, Stop::NoProgress(_)) {
                break;
            }
        }
    }
    assert!(
        matches!(stops.as_slice(), [Stop::StaleScan, Stop::NoProgress(why)]
            if why.contains("scan missing or stale")),
        "{stops:?}"
    );
    assert_eq!(bridge.goal(), None);
    let said = bridge
        .drain_log()
        .into_iter()
        .filter(|(_, t)| t.contains("no progress"))
        .count();
    assert_eq!(said, 1);

    // 3. On its way (4 m, longer than the allowance): never given up.
    let (mut bridge, mut sim) = in_open_room(params.clone());
    bridge.on_goal(&goal(12.0, 10.0), sim.t);
    let t0 = sim.t;
    fly(&mut sim, &mut bridge, [12.0, 10.0], 4000);
    assert!((sim.t - t0).as_secs_f64() > allowance);

    // 4. The negative control: allowance 0, stuck for longer, still commanding.
    let (mut bridge, mut sim) = in_open_room(Params {
        movement_time_allowance: 0.0,
        ..params
    });
    bridge.on_goal(&goal(12.0, 10.0), sim.t);
    for _ in 0..100 {
        stuck_step(&mut sim, &mut bridge, true);
    }
    let s = stuck_step(&mut sim, &mut bridge, true);
    assert_eq!(s.stop, None);
    assert!(s.twist.linear.x.hypot(s.twist.linear.y) > 1e-3);
}

/// The perceived obstacles as markers, only when they change: at first a `DELETEALL` alone;
/// on the way past the disc, line strips in `map`, closed, of which one rings the true disc
/// (no point of it inside the disc, its mean radius near the disc grown by `robot_radius +
/// margin`, the perception's fit a little larger); nothing while they
/// stay as they are; a `DELETEALL` alone once the goal is gone.
#[test]
fn perceived_obstacles_as_markers_when_they_change() {
    let params = Params {
        map_topic: String::new(),
        ..Params::default()
    };
    let (mut bridge, mut sim) = in_open_room(params.clone());
    let first = bridge
        .obstacle_markers(Time::default())
        .expect("a first array");
    assert_eq!(first.markers.len(), 1);
    assert_eq!(first.markers[0].action, Marker::DELETEALL);
    assert!(bridge.obstacle_markers(Time::default()).is_none());

    bridge.on_goal(&goal(12.0, 10.0), sim.t);
    let mut arrays = Vec::new();
    let mut steps = 0;
    for _ in 0..4000 {
        let s = sim.step(&mut bridge, true);
        steps += 1;
        if let Some(m) = bridge.obstacle_markers(sim.stamp()) {
            arrays.push(m);
        }
        if s.stop == Some(Stop::Arrived) {
            break;
        }
    }
    assert!(
        !arrays.is_empty() && arrays.len() < steps / 2,
        "{} arrays in {steps} steps",
        arrays.len()
    );
    let last = arrays.last().unwrap();
    assert_eq!(last.markers[0].action, Marker::DELETEALL);
    let strips = &last.markers[1..];
    assert!(!strips.is_empty(), "no obstacle perceived");
    for (i, m) in strips.iter().enumerate() {
        assert_eq!(
            (m.kind, m.action, m.id, m.header.frame_id.as_str()),
            (
                Marker::LINE_STRIP,
                Marker::ADD,
                i32::try_from(i).unwrap(),
                "map"
            )
        );
        assert!(m.points.len() >= 4 && m.points.first() == m.points.last());
        assert!(m.scale.x > 0.0 && m.color.a > 0.0);
    }
    let from_disc = |p: &Point| (p.x - 10.0).hypot(p.y - 10.1);
    let ring = strips
        .iter()
        .find(|m| m.points.iter().all(|p| (0.4..1.0).contains(&from_disc(p))));
    let grown = 0.4 + params.robot_radius + params.margin;
    let ring = ring.unwrap_or_else(|| panic!("no strip rings the disc: {strips:?}"));
    let mean = ring.points.iter().map(from_disc).sum::<f64>() / ring.points.len() as f64;
    // The perception's fit is conservative: the outline lies around the grown disc, not in it.
    assert!(
        mean > grown - 0.05 && mean < grown + 0.25,
        "mean radius {mean}, grown disc {grown}"
    );

    bridge.clear_goal();
    let gone = bridge.obstacle_markers(sim.stamp()).expect("a change");
    assert_eq!(gone.markers.len(), 1);
    assert_eq!(gone.markers[0].action, Marker::DELETEALL);
}

// The goal's yaw on a differential-drive base (`use_goal_orientation`, harmonav's
// `Navigator::set_goal_heading`).

use std::f64::consts::FRAC_PI_2;

use harmonav::tuning::{GOAL_ARRIVAL, GOAL_HEADING_TOLERANCE};

/// `a` in `(−π, π]`.
fn wrap(a: f64) -> f64 {
    a.sin().atan2(a.cos())
}

/// Whether the bridge's goal yaw is `yaw` (to rounding: the quaternion's round trip).
fn goal_yaw_is(bridge: &Bridge, yaw: f64) -> bool {
    bridge.goal_yaw().is_some_and(|y| (y - yaw).abs() < 1e-12)
}

/// A goal at `(x, y)` with yaw `yaw` in `frame`.
fn goal_in(frame: &str, x: f64, y: f64, yaw: f64) -> PoseStamped {
    let mut g = goal(x, y);
    g.header.frame_id = frame.into();
    g.pose.orientation = Quaternion::from_yaw(yaw);
    g
}

/// A diff base from scans alone at (8, 10) facing away from the goals (yaw 2), in
/// [`open_room`]; `use_goal_orientation` as given.
fn diff_in_open_room(use_goal_orientation: bool) -> (Bridge, Sim, Params) {
    let params = Params {
        map_topic: String::new(),
        base: harmonav_ros2::params::Base::Diff,
        use_goal_orientation,
        ..Params::default()
    };
    let (bridge, mut sim) = in_open_room(params.clone());
    sim.diff = true;
    sim.yaw = 2.0;
    (bridge, sim, params)
}

/// What a drive to a goal with a yaw shows: the steps spent within `goal_tolerance` of the
/// goal before arrival, and the smallest clearance met.
struct Drive {
    within_tolerance: u32,
    clearance: f64,
}

/// Steps the diff robot until [`Stop::Arrived`] (at most `max` steps; panics without it).
fn drive_to(sim: &mut Sim, bridge: &mut Bridge, g: [f64; 2], max: u32) -> Drive {
    let tolerance = bridge.params().goal_tolerance;
    let mut drive = Drive {
        within_tolerance: 0,
        clearance: f64::INFINITY,
    };
    for _ in 0..max {
        let d = (sim.x[0] - g[0]).hypot(sim.x[1] - g[1]);
        let s = sim.step(bridge, true);
        drive.clearance = drive.clearance.min(sim.clearance());
        if s.stop == Some(Stop::Arrived) {
            return drive;
        }
        if d <= tolerance {
            drive.within_tolerance += 1;
        }
        assert!(
            matches!(s.stop, None | Some(Stop::StaleScan | Stop::StaleOdom)),
            "stopped: {:?} at {:?}; log: {:?}",
            s.stop,
            sim.x,
            bridge.drain_log()
        );
    }
    panic!(
        "not arrived after {max} steps at {:?}, yaw {}; log: {:?}",
        sim.x,
        sim.yaw,
        bridge.drain_log()
    );
}

/// A diff base given a goal with yaw π/2 on `/goal_pose` drives to within `GOAL_ARRIVAL` of it
/// (not stopping at `goal_tolerance`), turns in place and is declared arrived only at the yaw,
/// within `GOAL_HEADING_TOLERANCE`; then it stands. A second goal at the robot's own position
/// is a turn in place alone. The negative control: with `use_goal_orientation: false` the same
/// drive ends within `goal_tolerance`, the yaw far from π/2.
#[test]
fn differential_drive_finishes_at_the_goal_yaw() {
    let g = [12.0, 10.0];
    let (mut bridge, mut sim, params) = diff_in_open_room(true);
    bridge.on_goal(&goal_in("map", g[0], g[1], FRAC_PI_2), sim.t);
    assert!(goal_yaw_is(&bridge, FRAC_PI_2));
    let drive = drive_to(&mut sim, &mut bridge, g, 4000);
    let d = (sim.x[0] - g[0]).hypot(sim.x[1] - g[1]);
    let e = wrap(sim.yaw - FRAC_PI_2);
    assert!(d < GOAL_ARRIVAL, "arrived {d} m from the goal");
    assert!(
        e.abs() < GOAL_HEADING_TOLERANCE,
        "arrived {e} rad off the goal yaw"
    );
    assert!(
        drive.within_tolerance > 0,
        "never within goal_tolerance before arriving: the test shows nothing"
    );
    assert!(
        drive.clearance > params.robot_radius,
        "contact: {}",
        drive.clearance
    );
    for _ in 0..10 {
        let s = sim.step(&mut bridge, true);
        assert_eq!((s.twist, s.stop), (Twist::default(), Some(Stop::Arrived)));
    }
    let log: Vec<String> = bridge.drain_log().into_iter().map(|(_, t)| t).collect();
    assert!(
        log.iter()
            .any(|l| l.contains("goal reached") && l.contains("yaw")),
        "{log:?}"
    );

    // A goal at the robot's own position: it turns in place to −π/2, and moves not.
    let here = sim.x;
    bridge.on_goal(&goal_in("map", here[0], here[1], -FRAC_PI_2), sim.t);
    drive_to(&mut sim, &mut bridge, here, 400);
    assert!(
        wrap(sim.yaw + FRAC_PI_2).abs() < GOAL_HEADING_TOLERANCE,
        "yaw {}",
        sim.yaw
    );
    assert!((sim.x[0] - here[0]).hypot(sim.x[1] - here[1]) < 1e-12);

    // The negative control: the orientation ignored.
    let (mut bridge, mut sim, _) = diff_in_open_room(false);
    bridge.on_goal(&goal_in("map", g[0], g[1], FRAC_PI_2), sim.t);
    assert_eq!(bridge.goal_yaw(), None);
    fly(&mut sim, &mut bridge, g, 4000);
    let e = wrap(sim.yaw - FRAC_PI_2);
    assert!(
        e.abs() > 0.5,
        "the yaw reached π/2 ({e} off) without being asked"
    );
}

/// Nav2's `xy_goal_tolerance` (0.3 m) and `yaw_goal_tolerance` (0.05 rad): a goal with a yaw
/// turns in place from the first pose within 0.3 m (the robot ends farther than the default
/// 1 cm, which the test above reaches) and is reached within 0.05 rad; a goal without a yaw
/// (the orientation ignored) is reached within 0.3 m, not `goal_tolerance`'s 0.1 m.
#[test]
fn nav2_goal_tolerances_end_the_drive() {
    let g = [12.0, 10.0];
    let (xy, yaw) = (0.3, 0.05);
    for use_goal_orientation in [true, false] {
        let params = Params {
            map_topic: String::new(),
            base: harmonav_ros2::params::Base::Diff,
            use_goal_orientation,
            xy_goal_tolerance: Some(xy),
            yaw_goal_tolerance: yaw,
            ..Params::default()
        };
        let (mut bridge, mut sim) = in_open_room(params.clone());
        sim.diff = true;
        sim.yaw = 2.0;
        bridge.on_goal(&goal_in("map", g[0], g[1], FRAC_PI_2), sim.t);
        let drive = drive_to(&mut sim, &mut bridge, g, 4000);
        let d = (sim.x[0] - g[0]).hypot(sim.x[1] - g[1]);
        assert!(
            d <= xy,
            "{use_goal_orientation}: arrived {d} m from the goal"
        );
        assert!(
            drive.clearance > params.robot_radius,
            "contact: {}",
            drive.clearance
        );
        if use_goal_orientation {
            assert!(
                d > GOAL_ARRIVAL,
                "drove on to {d} m: the tolerance was not read"
            );
            let e = wrap(sim.yaw - FRAC_PI_2);
            assert!(e.abs() < yaw, "arrived {e} rad off the goal yaw");
        } else {
            assert!(d > params.goal_tolerance, "{d}: goal_tolerance was read");
        }
    }
}

/// Nav2's goal checker keys under the plugin's name, in a parameter file as Nav2's
/// controller_server takes them (`goal_checker_plugins`, `general_goal_checker.*`), drive as
/// the bare keys do: the same tolerance, `stateful`, and end pose, bit for bit; the goal's log
/// line says the radius does not latch (`stateful: false`).
#[test]
fn nav2_namespaced_goal_checker_keys_drive_as_the_bare_ones() {
    use harmonav_ros2::params::{Cli, parse_args};
    let g = [12.0, 10.0];
    let file = "/**:
  ros__parameters:
    map_topic: ''
    base: diff
    goal_checker_plugins: [general_goal_checker]
    general_goal_checker:
      plugin: nav2_controller::SimpleGoalChecker
      xy_goal_tolerance: 0.3
      yaw_goal_tolerance: 0.05
      stateful: false
";
    let args: Vec<String> = ["--ros-args", "--params-file", "f.yaml"]
        .map(String::from)
        .to_vec();
    let (Cli::Run(namespaced), _) = parse_args(&args, &|_| Ok(file.to_owned())).unwrap() else {
        panic!()
    };
    let bare = Params {
        map_topic: String::new(),
        base: harmonav_ros2::params::Base::Diff,
        xy_goal_tolerance: Some(0.3),
        yaw_goal_tolerance: 0.05,
        stateful: false,
        ..Params::default()
    };
    assert_eq!(namespaced.goal_tolerance(), bare.goal_tolerance());
    assert_eq!(namespaced.stateful, bare.stateful);
    let ends = [*namespaced, bare].map(|params| {
        let (mut bridge, mut sim) = in_open_room(params);
        sim.diff = true;
        sim.yaw = 2.0;
        bridge.on_goal(&goal_in("map", g[0], g[1], FRAC_PI_2), sim.t);
        drive_to(&mut sim, &mut bridge, g, 4000);
        let log: Vec<String> = bridge.drain_log().into_iter().map(|(_, t)| t).collect();
        assert!(
            log.iter().any(|l| l.contains("latches: false (stateful)")),
            "{log:?}"
        );
        (sim.x, sim.yaw)
    });
    assert_eq!(ends[0], ends[1]);
    let d = (ends[0].0[0] - g[0]).hypot(ends[0].0[1] - g[1]);
    assert!(GOAL_ARRIVAL < d && d <= 0.3, "{d}");
}

/// A goal in another frame: its pose is taken into `map` whole, the yaw rotated by the frame's
/// transform (a static `map → dock`, yaw 1): `(0.5, 0)` at yaw π/2 − 1 in `dock` is
/// `dock`'s origin plus 0.5 m along yaw 1, at yaw π/2 in `map`, where the robot ends.
#[test]
fn a_goal_yaw_in_another_frame_is_rotated_into_the_global_frame() {
    let (mut bridge, mut sim, _) = diff_in_open_room(true);
    let dock = TFMessage {
        transforms: vec![TransformStamped {
            header: Header {
                stamp: Time::default(),
                frame_id: "map".into(),
            },
            child_frame_id: "dock".into(),
            transform: Transform {
                translation: Vector3 {
                    x: 11.5,
                    y: 9.5,
                    z: 0.0,
                },
                rotation: Quaternion::from_yaw(1.0),
            },
        }],
    };
    bridge.on_tf(&dock, sim.t, true);
    let g = [11.5 + 0.5 * 1f64.cos(), 9.5 + 0.5 * 1f64.sin()];
    bridge.on_goal(&goal_in("dock", 0.5, 0.0, FRAC_PI_2 - 1.0), sim.t);
    let at = bridge.goal().unwrap();
    assert!(
        (at.x - g[0]).abs() < 1e-12 && (at.y - g[1]).abs() < 1e-12,
        "{at:?}"
    );
    let yaw = bridge.goal_yaw().unwrap();
    assert!((yaw - FRAC_PI_2).abs() < 1e-12, "goal yaw {yaw}");
    drive_to(&mut sim, &mut bridge, g, 4000);
    assert!(
        wrap(sim.yaw - FRAC_PI_2).abs() < GOAL_HEADING_TOLERANCE,
        "yaw {}",
        sim.yaw
    );
    assert!((sim.x[0] - g[0]).hypot(sim.x[1] - g[1]) < GOAL_ARRIVAL);
}

/// A goal whose quaternion is not a rotation (all zero, or a component not finite) is dropped
/// on `/goal_pose` (said) and rejected by the action; the goal before it stays, yaw and all.
/// Where the orientation is not read (a holonomic base, or `use_goal_orientation: false`) the
/// same goals are taken, as before.
#[test]
fn a_goal_quaternion_that_is_not_a_rotation_is_rejected() {
    let zero = |x, y| {
        let mut g = goal(x, y);
        g.pose.orientation = Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 0.0,
        };
        g
    };
    let nan = |x, y| {
        let mut g = goal_in("map", x, y, 0.0);
        g.pose.orientation.z = f64::NAN;
        g
    };
    let (mut bridge, sim, _) = diff_in_open_room(true);
    let before = goal_in("map", 12.0, 10.0, FRAC_PI_2);
    bridge.set_goal(&before, sim.t).unwrap();
    for bad in [zero(9.0, 9.0), nan(9.0, 9.0)] {
        let e = bridge.set_goal(&bad, sim.t).unwrap_err();
        assert!(e.0.contains("not a rotation"), "{e}");
        assert_eq!(bridge.goal().map(|g| (g.x, g.y)), Some((12.0, 10.0)));
        assert!(goal_yaw_is(&bridge, FRAC_PI_2));
    }
    bridge.drain_log();
    bridge.on_goal(&zero(9.0, 9.0), sim.t);
    let log = bridge.drain_log();
    assert!(
        log.iter()
            .any(|(l, t)| *l == log::Level::Warn && t.contains("w = 1")),
        "{log:?}"
    );
    assert!(goal_yaw_is(&bridge, FRAC_PI_2));

    // Through the action: rejected, the running goal runs on.
    let mut nav: Navigate<u32> = Navigate::new();
    let a = GoalId::new_random();
    assert!(nav.send_goal(
        a,
        &NavigateToPoseGoal {
            pose: before.clone(),
            behavior_tree: String::new(),
        },
        &mut bridge,
        sim.t,
        RosTime::ZERO
    ));
    let b = GoalId::new_random();
    assert!(!nav.send_goal(
        b,
        &NavigateToPoseGoal {
            pose: zero(9.0, 9.0),
            behavior_tree: String::new(),
        },
        &mut bridge,
        sim.t,
        RosTime::ZERO
    ));
    assert_eq!((nav.active(), nav.status(b)), (Some(a), None));
    assert!(goal_yaw_is(&bridge, FRAC_PI_2));

    // Not read, so not checked: a holonomic base and the parameter off take them.
    let holonomic = Params {
        map_topic: String::new(),
        ..Params::default()
    };
    for params in [holonomic, diff_in_open_room(false).2] {
        let mut bridge = Bridge::new(params);
        for g in [zero(9.0, 9.0), nan(9.5, 9.0)] {
            let at = bridge.set_goal(&g, sim.t).unwrap();
            assert_eq!(
                (at.x, at.y, bridge.goal_yaw()),
                (g.pose.position.x, 9.0, None)
            );
        }
    }
}

/// Through the action, a diff base's goal with a yaw succeeds only once the robot has turned to
/// it: while within `goal_tolerance` of the position but not yet at the yaw, it is executing.
#[test]
fn action_goal_with_a_yaw_succeeds_after_the_turn() {
    let (mut bridge, mut sim, params) = diff_in_open_room(true);
    let mut nav: Navigate<u32> = Navigate::new();
    let id = GoalId::new_random();
    let g = NavigateToPoseGoal {
        pose: goal_in("map", 12.0, 10.0, FRAC_PI_2),
        behavior_tree: String::new(),
    };
    assert!(nav.send_goal(id, &g, &mut bridge, sim.t, RosTime::ZERO));
    let mut executing_near = 0;
    for _ in 0..4000 {
        let (s, _) = action_step(&mut sim, &mut bridge, &mut nav);
        if s.stop == Some(Stop::Arrived) {
            break;
        }
        let d = (sim.x[0] - 12.0).hypot(sim.x[1] - 10.0);
        if d <= params.goal_tolerance && nav.status(id) == Some(GoalStatusEnum::Executing) {
            executing_near += 1;
        }
    }
    assert_eq!(nav.status(id), Some(GoalStatusEnum::Succeeded));
    assert!(
        wrap(sim.yaw - FRAC_PI_2).abs() < GOAL_HEADING_TOLERANCE,
        "yaw {}",
        sim.yaw
    );
    assert!(
        executing_near > 0,
        "succeeded as soon as within goal_tolerance"
    );
}

/// On the floor plan of `/map` too (the other navigator): a diff base ends at the goal's yaw.
#[test]
fn differential_drive_on_a_floor_plan_finishes_at_the_goal_yaw() {
    let room = grid(84, 64, 0.05, (-0.1, -0.1), |x, y| {
        let wall = !(0.0..4.0).contains(&x) || !(0.0..3.0).contains(&y);
        let bx = (1.6..2.4).contains(&x) && (1.0..2.0).contains(&y);
        if wall || bx { 100 } else { 0 }
    });
    let params = Params {
        base: harmonav_ros2::params::Base::Diff,
        ..Params::default()
    };
    let mut bridge = Bridge::new(params.clone());
    let mut sim = Sim::new(room.clone(), [0.6, 0.6]);
    sim.diff = true;
    bridge.on_tf(&laser_static(), sim.t, true);
    bridge.on_map(&room);
    let g = [3.4, 2.4];
    bridge.on_goal(&goal_in("map", g[0], g[1], -3.0), sim.t);
    let drive = drive_to(&mut sim, &mut bridge, g, 4000);
    assert!(
        wrap(sim.yaw + 3.0).abs() < GOAL_HEADING_TOLERANCE,
        "yaw {}",
        sim.yaw
    );
    assert!((sim.x[0] - g[0]).hypot(sim.x[1] - g[1]) < GOAL_ARRIVAL);
    assert!(
        drive.clearance > params.robot_radius,
        "contact: {}",
        drive.clearance
    );
}

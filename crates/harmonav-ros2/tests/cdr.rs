//! The hand-written messages against bytes from an independent serialiser: Eclipse Cyclone
//! DDS's Python IDL (`tests/ros2_msgs.py`, run by `python3 tests/ros2_msgs.py >
//! tests/cdr_reference.txt` in a venv with PyPI `cyclonedds`), XCDR1 little endian as ROS 2's
//! DDS RMWs put these types on the wire. Each reference decodes to the expected value and the
//! value encodes to the reference, byte for byte (a field out of order, a wrong width or a
//! missed alignment fails).

use byteorder::LittleEndian;
use harmonav_ros2::msgs::*;
use serde::Serialize;
use serde::de::DeserializeOwned;

fn reference(name: &str) -> Vec<u8> {
    let text = include_str!("cdr_reference.txt");
    let hex = text
        .lines()
        .find_map(|l| l.strip_prefix(name).and_then(|r| r.strip_prefix(' ')))
        .unwrap_or_else(|| panic!("no reference for {name}"));
    (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap())
        .collect()
}

/// Decodes the reference (all of it) and re-encodes the value.
fn round_trip<T: Serialize + DeserializeOwned>(name: &str, expected: &T) -> T {
    let bytes = reference(name);
    let (value, used) = cdr_encoding::from_bytes::<T, LittleEndian>(&bytes).unwrap();
    assert_eq!(used, bytes.len(), "{name}: bytes left over");
    let ours = cdr_encoding::to_vec::<T, LittleEndian>(expected).unwrap();
    assert_eq!(ours, bytes, "{name}: our encoding differs from Cyclone's");
    value
}

fn t(sec: i32, nanosec: u32) -> Time {
    Time { sec, nanosec }
}

fn h(sec: i32, nanosec: u32, frame: &str) -> Header {
    Header {
        stamp: t(sec, nanosec),
        frame_id: frame.into(),
    }
}

fn pose() -> Pose {
    Pose {
        position: Point {
            x: 1.5,
            y: -2.25,
            z: 0.125,
        },
        orientation: Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.382_683_432_365_089_8,
            w: 0.923_879_532_511_286_7,
        },
    }
}

fn v3(x: f64, y: f64, z: f64) -> Vector3 {
    Vector3 { x, y, z }
}

#[test]
fn builtin_and_std() {
    let e = t(-3, 999_999_999);
    assert_eq!(round_trip("time", &e), e);
    let e = h(7, 8, "odom");
    assert_eq!(round_trip("header", &e), e);
    let e = Clock { clock: t(42, 43) };
    assert_eq!(round_trip("clock", &e), e);
    let e = StringMsg {
        data: "stopped: scan missing or stale".into(),
    };
    assert_eq!(round_trip("string", &e), e);
}

#[test]
fn geometry() {
    let e = Twist {
        linear: v3(0.5, -0.25, 0.0),
        angular: v3(0.0, 0.0, 1.5),
    };
    assert_eq!(round_trip("twist", &e), e);
    let e = TwistStamped {
        header: h(1, 2, "b"),
        twist: Twist {
            linear: v3(0.1, 0.0, 0.0),
            angular: Vector3::default(),
        },
    };
    assert_eq!(round_trip("twist_stamped", &e), e);
    let e = PoseStamped {
        header: h(5, 6, "map"),
        pose: pose(),
    };
    let got = round_trip("pose_stamped", &e);
    assert_eq!(got, e);
    assert!((got.pose.orientation.yaw().unwrap() - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
}

#[test]
fn odometry_with_36_covariances() {
    let mut c = [0.0; 36];
    let mut d = [0.0; 36];
    for i in 0..36 {
        c[i] = f64::from(i as u8);
        d[i] = -f64::from(i as u8);
    }
    let e = Odometry {
        header: h(9, 10, "odom"),
        child_frame_id: "base_link".into(),
        pose: PoseWithCovariance {
            pose: pose(),
            covariance: Covariance(c),
        },
        twist: TwistWithCovariance {
            twist: Twist {
                linear: v3(0.2, 0.0, 0.0),
                angular: Vector3::default(),
            },
            covariance: Covariance(d),
        },
    };
    assert_eq!(round_trip("odometry", &e), e);
}

#[test]
fn laser_scan_with_rep_117_values() {
    let e = LaserScan {
        header: h(1_700_000_000, 123_456_789, "laser"),
        angle_min: -3.0,
        angle_max: 3.0,
        angle_increment: 1.5,
        time_increment: 0.001,
        scan_time: 0.1,
        range_min: 0.1,
        range_max: 10.0,
        ranges: vec![1.0, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, 0.05],
        intensities: vec![7.0],
    };
    let got = round_trip("laser_scan", &e);
    assert_eq!(got.header, e.header);
    assert_eq!(got.ranges.len(), 5);
    assert_eq!(&got.ranges[..3], &e.ranges[..3]);
    assert!(got.ranges[3].is_nan());
    assert_eq!(got.ranges[4], 0.05);
    assert_eq!(got.intensities, e.intensities);
    assert_eq!(
        (got.angle_min, got.angle_increment, got.range_max),
        (-3.0, 1.5, 10.0)
    );
}

#[test]
fn occupancy_grid() {
    let e = OccupancyGrid {
        header: h(11, 12, "map"),
        info: MapMetaData {
            map_load_time: t(13, 14),
            resolution: 0.05,
            width: 3,
            height: 2,
            origin: pose(),
        },
        data: vec![0, 100, -1, 50, 0, 0],
    };
    assert_eq!(round_trip("occupancy_grid", &e), e);
}

#[test]
fn tf_message() {
    let e = TFMessage {
        transforms: vec![
            TransformStamped {
                header: h(1, 0, "map"),
                child_frame_id: "odom".into(),
                transform: Transform {
                    translation: v3(1.0, 2.0, 3.0),
                    rotation: pose().orientation,
                },
            },
            TransformStamped {
                header: h(2, 0, "odom"),
                child_frame_id: "base_link".into(),
                transform: Transform::default(),
            },
        ],
    };
    assert_eq!(round_trip("tf_message", &e), e);
}

/// Truncated or garbage bytes are an error, never a panic (the node drops such a message).
#[test]
fn bad_bytes_are_errors() {
    for name in ["laser_scan", "occupancy_grid", "odometry", "tf_message"] {
        let bytes = reference(name);
        for cut in [0, 3, bytes.len() / 2, bytes.len() - 1] {
            match name {
                "laser_scan" => {
                    assert!(
                        cdr_encoding::from_bytes::<LaserScan, LittleEndian>(&bytes[..cut]).is_err()
                    );
                }
                "occupancy_grid" => {
                    assert!(
                        cdr_encoding::from_bytes::<OccupancyGrid, LittleEndian>(&bytes[..cut])
                            .is_err()
                    );
                }
                "odometry" => {
                    assert!(
                        cdr_encoding::from_bytes::<Odometry, LittleEndian>(&bytes[..cut]).is_err()
                    );
                }
                _ => {
                    assert!(
                        cdr_encoding::from_bytes::<TFMessage, LittleEndian>(&bytes[..cut]).is_err()
                    );
                }
            }
        }
    }
    // A sequence length far beyond the bytes.
    let mut bytes = reference("tf_message");
    bytes[..4].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(cdr_encoding::from_bytes::<TFMessage, LittleEndian>(&bytes).is_err());
}

/// Encodes `value` and compares with the reference; decodes the reference and re-encodes it
/// (for ros2-client's wrapper types, which have no `PartialEq`).
fn same_bytes<T: Serialize + DeserializeOwned>(name: &str, value: &T) {
    let bytes = reference(name);
    let ours = cdr_encoding::to_vec::<T, LittleEndian>(value).unwrap();
    assert_eq!(ours, bytes, "{name}: our encoding differs from Cyclone's");
    let (back, used) = cdr_encoding::from_bytes::<T, LittleEndian>(&bytes).unwrap();
    assert_eq!(used, bytes.len(), "{name}: bytes left over");
    assert_eq!(
        cdr_encoding::to_vec::<T, LittleEndian>(&back).unwrap(),
        bytes,
        "{name}: decoded and re-encoded"
    );
}

/// The goal id 1, 2, …, 16 of the references.
fn goal_id() -> ros2_client::action::GoalId {
    let bytes: Vec<u8> = (1..=16).collect();
    cdr_encoding::from_bytes::<ros2_client::action::GoalId, LittleEndian>(&bytes)
        .unwrap()
        .0
}

/// The `navigate_to_pose` action's messages (Jazzy's `NavigateToPose.action`) and the action
/// wrappers ros2-client puts them in (`SendGoal`, `GetResult`, `FeedbackMessage`), with
/// action_msgs' status and cancel types: the layouts of rosidl's generated types.
#[test]
fn navigate_to_pose_action() {
    use ros2_client::action::{
        CancelGoalResponse, FeedbackMessage, GetResultRequest, GetResultResponse, GoalInfo,
        GoalStatusEnum, SendGoalRequest, SendGoalResponse,
    };
    use ros2_client::action_msgs::{CancelGoalResponseEnum, GoalStatus, GoalStatusArray};
    use ros2_client::builtin_interfaces::Time as RosTime;
    let e = Duration {
        sec: 12,
        nanosec: 345,
    };
    assert_eq!(round_trip("duration", &e), e);
    let stamped = PoseStamped {
        header: h(5, 6, "map"),
        pose: pose(),
    };
    let goal = NavigateToPoseGoal {
        pose: stamped.clone(),
        behavior_tree: "bt".into(),
    };
    let request = SendGoalRequest {
        goal_id: goal_id(),
        goal: goal.clone(),
    };
    same_bytes("send_goal_request", &request);
    let (back, _) = cdr_encoding::from_bytes::<SendGoalRequest<NavigateToPoseGoal>, LittleEndian>(
        &reference("send_goal_request"),
    )
    .unwrap();
    assert_eq!(back.goal, goal);
    assert_eq!(back.goal_id, goal_id());
    same_bytes(
        "send_goal_response",
        &SendGoalResponse {
            accepted: true,
            stamp: RosTime::from_nanos(21_000_000_022),
        },
    );
    same_bytes(
        "get_result_request",
        &GetResultRequest { goal_id: goal_id() },
    );
    let result = NavigateToPoseResult {
        error_code: 206,
        error_msg: "occupied".into(),
    };
    same_bytes(
        "get_result_response",
        &GetResultResponse {
            status: GoalStatusEnum::Aborted,
            result: result.clone(),
        },
    );
    let (back, _) =
        cdr_encoding::from_bytes::<GetResultResponse<NavigateToPoseResult>, LittleEndian>(
            &reference("get_result_response"),
        )
        .unwrap();
    assert_eq!(
        (back.status, back.result),
        (GoalStatusEnum::Aborted, result)
    );
    let feedback = NavigateToPoseFeedback {
        current_pose: stamped,
        navigation_time: Duration { sec: 3, nanosec: 4 },
        estimated_time_remaining: Duration { sec: 7, nanosec: 8 },
        number_of_recoveries: -2,
        distance_remaining: 1.25,
    };
    same_bytes(
        "feedback_message",
        &FeedbackMessage {
            goal_id: goal_id(),
            feedback: feedback.clone(),
        },
    );
    let (back, _) =
        cdr_encoding::from_bytes::<FeedbackMessage<NavigateToPoseFeedback>, LittleEndian>(
            &reference("feedback_message"),
        )
        .unwrap();
    assert_eq!(back.feedback, feedback);
    let info = |id, sec: i64, nanosec: i64| GoalInfo {
        goal_id: id,
        stamp: RosTime::from_nanos(sec * 1_000_000_000 + nanosec),
    };
    let ones = cdr_encoding::from_bytes::<ros2_client::action::GoalId, LittleEndian>(&[255u8; 16])
        .unwrap()
        .0;
    same_bytes(
        "goal_status_array",
        &GoalStatusArray {
            status_list: vec![
                GoalStatus {
                    goal_info: info(goal_id(), 1, 2),
                    status: GoalStatusEnum::Executing,
                },
                GoalStatus {
                    goal_info: info(ones, 3, 4),
                    status: GoalStatusEnum::Canceled,
                },
            ],
        },
    );
    // ros2-client's CancelGoalRequest has a private field: the node reads it as a GoalInfo.
    same_bytes("cancel_goal_request", &info(goal_id(), 9, 10));
    let (request, _) = cdr_encoding::from_bytes::<
        ros2_client::action::CancelGoalRequest,
        LittleEndian,
    >(&reference("cancel_goal_request"))
    .unwrap();
    let got = harmonav_ros2::action::cancel_goal_info(&request).unwrap();
    assert_eq!(got.goal_id, goal_id());
    assert_eq!(got.stamp.to_nanos(), 9_000_000_010);
    same_bytes(
        "cancel_goal_response",
        &CancelGoalResponse {
            return_code: CancelGoalResponseEnum::None,
            goals_canceling: vec![info(goal_id(), 9, 10)],
        },
    );
}

/// `visualization_msgs/MarkerArray` (the perceived obstacles' outlines): a DELETEALL and a
/// line strip with every field set, the optional ones too. (rclpy's Fast CDR serialiser gives
/// the same bytes but for the padding, which it leaves unwritten.)
#[test]
fn marker_array() {
    let head = h(3, 4, "map");
    let e = MarkerArray {
        markers: vec![
            Marker {
                header: head.clone(),
                ns: "obstacles".into(),
                id: 0,
                kind: 0,
                action: Marker::DELETEALL,
                ..Marker::default()
            },
            Marker {
                header: head,
                ns: "obstacles".into(),
                id: 7,
                kind: Marker::LINE_STRIP,
                action: Marker::ADD,
                pose: pose(),
                scale: v3(0.02, 0.0, 0.0),
                color: ColorRGBA {
                    r: 1.0,
                    g: 0.5,
                    b: 0.25,
                    a: 0.75,
                },
                lifetime: Duration { sec: 1, nanosec: 2 },
                frame_locked: true,
                points: vec![
                    Point {
                        x: 1.0,
                        y: 2.0,
                        z: 0.0,
                    },
                    Point {
                        x: -3.5,
                        y: 0.25,
                        z: 1.0,
                    },
                ],
                colors: vec![ColorRGBA {
                    r: 0.125,
                    ..ColorRGBA::default()
                }],
                texture_resource: "t".into(),
                texture: CompressedImage {
                    header: h(0, 0, "cam"),
                    format: "png".into(),
                    data: vec![1, 2, 3],
                },
                uv_coordinates: vec![UVCoordinate { u: 0.5, v: -1.0 }],
                text: "abc".into(),
                mesh_resource: "m".into(),
                mesh_file: MeshFile {
                    filename: "f.stl".into(),
                    data: vec![9],
                },
                mesh_use_embedded_materials: true,
            },
        ],
    };
    assert_eq!(round_trip("marker_array", &e), e);
}

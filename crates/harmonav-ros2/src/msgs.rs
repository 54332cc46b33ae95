//! The ROS 2 messages the node exchanges, written by hand and laid out field for field like
//! their `.msg` files (ros2-client has no message packages): serde structs that CDR
//! (de)serialises in declaration order, so a field out of order is a wire error that the unit
//! tests (bytes from an independent serialiser, Cyclone DDS's) catch.
//!
//! `float64[36]` is [`Covariance`]: serde's arrays stop at 32 elements.

use serde::de::{self, SeqAccess, Visitor};
use serde::ser::SerializeTuple;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// `builtin_interfaces/msg/Time`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Time {
    /// Seconds.
    pub sec: i32,
    /// Nanoseconds, `< 1e9`.
    pub nanosec: u32,
}

impl Time {
    /// Seconds as a float.
    #[must_use]
    pub fn seconds(&self) -> f64 {
        f64::from(self.sec) + 1e-9 * f64::from(self.nanosec)
    }

    /// The time at `t` seconds (`t ≥ 0`, rounded down to the nanosecond; saturating).
    #[must_use]
    pub fn from_seconds(t: f64) -> Self {
        let t = t.max(0.0);
        let sec = t.floor();
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let nanosec = (((t - sec) * 1e9) as u32).min(999_999_999);
        #[allow(clippy::cast_possible_truncation)]
        let sec = sec.min(f64::from(i32::MAX)) as i32;
        Self { sec, nanosec }
    }

    /// Whether the stamp is the zero time (publishers that do not stamp).
    #[must_use]
    pub fn is_zero(&self) -> bool {
        self.sec == 0 && self.nanosec == 0
    }
}

/// `std_msgs/msg/Header`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Stamp.
    pub stamp: Time,
    /// Frame.
    pub frame_id: String,
}

/// `geometry_msgs/msg/Vector3`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// `geometry_msgs/msg/Point`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Point {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// `geometry_msgs/msg/Quaternion` (the `.msg` default is the identity, `w = 1`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

impl Default for Quaternion {
    fn default() -> Self {
        Self::from_yaw(0.0)
    }
}

impl Quaternion {
    /// The rotation by `yaw` about z.
    #[must_use]
    pub fn from_yaw(yaw: f64) -> Self {
        let (s, c) = (0.5 * yaw).sin_cos();
        Self {
            x: 0.0,
            y: 0.0,
            z: s,
            w: c,
        }
    }

    /// The yaw (rotation about z) of the normalised quaternion; `None` when a component is
    /// not finite or the norm is zero.
    #[must_use]
    pub fn yaw(&self) -> Option<f64> {
        let n = (self.x * self.x + self.y * self.y + self.z * self.z + self.w * self.w).sqrt();
        if !(n.is_finite() && n > 1e-9) {
            return None;
        }
        let (x, y, z, w) = (self.x / n, self.y / n, self.z / n, self.w / n);
        Some((2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)))
    }
}

/// `geometry_msgs/msg/Pose`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position.
    pub position: Point,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `geometry_msgs/msg/PoseStamped`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PoseStamped {
    /// Header.
    pub header: Header,
    /// Pose.
    pub pose: Pose,
}

/// `geometry_msgs/msg/Twist`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Twist {
    /// Linear velocity, m/s.
    pub linear: Vector3,
    /// Angular velocity, rad/s.
    pub angular: Vector3,
}

/// `geometry_msgs/msg/TwistStamped`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TwistStamped {
    /// Header.
    pub header: Header,
    /// Twist.
    pub twist: Twist,
}

/// `float64[36]`: a 6 × 6 covariance, row-major.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Covariance(pub [f64; 36]);

impl Default for Covariance {
    fn default() -> Self {
        Self([0.0; 36])
    }
}

impl Serialize for Covariance {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        // A fixed-size array: a tuple in serde, no length on the wire (CDR).
        let mut t = s.serialize_tuple(36)?;
        for v in &self.0 {
            t.serialize_element(v)?;
        }
        t.end()
    }
}

impl<'de> Deserialize<'de> for Covariance {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Covariance;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("36 float64")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Covariance, A::Error> {
                let mut out = [0.0; 36];
                for (i, v) in out.iter_mut().enumerate() {
                    *v = seq
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                Ok(Covariance(out))
            }
        }
        d.deserialize_tuple(36, V)
    }
}

/// `geometry_msgs/msg/PoseWithCovariance`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PoseWithCovariance {
    /// Pose.
    pub pose: Pose,
    /// Covariance.
    pub covariance: Covariance,
}

/// `geometry_msgs/msg/TwistWithCovariance`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TwistWithCovariance {
    /// Twist.
    pub twist: Twist,
    /// Covariance.
    pub covariance: Covariance,
}

/// `nav_msgs/msg/Odometry`: the pose of `child_frame_id` in `header.frame_id` (odom →
/// base_link), the twist in `child_frame_id`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Odometry {
    /// Header (`frame_id`: the odometry frame).
    pub header: Header,
    /// The robot's base frame.
    pub child_frame_id: String,
    /// Pose in `header.frame_id`.
    pub pose: PoseWithCovariance,
    /// Twist in `child_frame_id`.
    pub twist: TwistWithCovariance,
}

/// `sensor_msgs/msg/LaserScan`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LaserScan {
    /// Header (`frame_id`: the laser's frame; `stamp`: the first beam's time).
    pub header: Header,
    /// First beam's angle, rad.
    pub angle_min: f32,
    /// Last beam's angle, rad.
    pub angle_max: f32,
    /// Angle between beams, rad.
    pub angle_increment: f32,
    /// Time between beams, s.
    pub time_increment: f32,
    /// Time between scans, s.
    pub scan_time: f32,
    /// Smallest valid range, m.
    pub range_min: f32,
    /// Largest valid range, m.
    pub range_max: f32,
    /// Ranges, m (REP 117: `−Inf` too close, `NaN` error, `+Inf` no return).
    pub ranges: Vec<f32>,
    /// Intensities (device units; may be empty).
    pub intensities: Vec<f32>,
}

/// `nav_msgs/msg/MapMetaData`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MapMetaData {
    /// When the map was loaded.
    pub map_load_time: Time,
    /// m/cell.
    pub resolution: f32,
    /// Cells per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// The pose of cell (0, 0)'s corner in the map frame.
    pub origin: Pose,
}

/// `nav_msgs/msg/OccupancyGrid`: row-major from cell (0, 0) at `origin`, occupancy 0–100, −1
/// unknown.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OccupancyGrid {
    /// Header (`frame_id`: the map frame).
    pub header: Header,
    /// Metadata.
    pub info: MapMetaData,
    /// Cells.
    pub data: Vec<i8>,
}

/// `geometry_msgs/msg/Transform`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    /// Translation.
    pub translation: Vector3,
    /// Rotation.
    pub rotation: Quaternion,
}

/// `geometry_msgs/msg/TransformStamped`: `child_frame_id`'s pose in `header.frame_id`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TransformStamped {
    /// Header (the parent frame).
    pub header: Header,
    /// The child frame.
    pub child_frame_id: String,
    /// The transform.
    pub transform: Transform,
}

/// `tf2_msgs/msg/TFMessage` (on `/tf` and `/tf_static`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TFMessage {
    /// Transforms.
    pub transforms: Vec<TransformStamped>,
}

/// `rosgraph_msgs/msg/Clock` (on `/clock`; ros2-client subscribes it as
/// `builtin_interfaces/msg/Time`, which never matches a simulator's publisher).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Clock {
    /// The simulated time.
    pub clock: Time,
}

/// `nav_msgs/msg/Path`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Path {
    /// Header.
    pub header: Header,
    /// Poses.
    pub poses: Vec<PoseStamped>,
}

/// `std_msgs/msg/String` (the node's status line).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StringMsg {
    /// The text.
    pub data: String,
}

/// `builtin_interfaces/msg/Duration`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Duration {
    /// Seconds.
    pub sec: i32,
    /// Nanoseconds, `< 1e9`.
    pub nanosec: u32,
}

impl Duration {
    /// The duration of `t` seconds (`t ≥ 0`, rounded down to the nanosecond; saturating; a
    /// non-finite or negative `t` is zero).
    #[must_use]
    pub fn from_seconds(t: f64) -> Self {
        let Time { sec, nanosec } = Time::from_seconds(if t.is_finite() { t } else { 0.0 });
        Self { sec, nanosec }
    }

    /// Seconds as a float.
    #[must_use]
    pub fn seconds(&self) -> f64 {
        f64::from(self.sec) + 1e-9 * f64::from(self.nanosec)
    }
}

/// `nav2_msgs/action/NavigateToPose`'s goal (`NavigateToPose_Goal`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NavigateToPoseGoal {
    /// Where to go (its orientation is not used: harmonav steers to a point).
    pub pose: PoseStamped,
    /// Nav2's behaviour tree; harmonav has none and ignores it.
    pub behavior_tree: String,
}

/// `nav2_msgs/action/NavigateToPose`'s result in Jazzy (`NavigateToPose_Result`): Jazzy's
/// `.action` defines only `NONE = 0`; the node's other codes are in
/// [`crate::action::code`].
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NavigateToPoseResult {
    /// 0: no error.
    pub error_code: u16,
    /// Why, when `error_code` is not 0 (and why a goal was canceled or preempted).
    pub error_msg: String,
}

/// `nav2_msgs/action/NavigateToPose`'s feedback in Jazzy (`NavigateToPose_Feedback`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NavigateToPoseFeedback {
    /// The robot's pose in `global_frame`.
    pub current_pose: PoseStamped,
    /// Since the goal was accepted.
    pub navigation_time: Duration,
    /// `distance_remaining` over the commanded speed (zero when not moving).
    pub estimated_time_remaining: Duration,
    /// Always 0: harmonav has no recovery behaviours.
    pub number_of_recoveries: i16,
    /// m, the straight line from the robot to the goal.
    pub distance_remaining: f32,
}

/// `std_msgs/msg/ColorRGBA`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ColorRGBA {
    /// Red, 0–1.
    pub r: f32,
    /// Green, 0–1.
    pub g: f32,
    /// Blue, 0–1.
    pub b: f32,
    /// Opacity, 0–1 (0 is invisible in RViz).
    pub a: f32,
}

/// `visualization_msgs/msg/UVCoordinate`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct UVCoordinate {
    /// u.
    pub u: f32,
    /// v.
    pub v: f32,
}

/// `visualization_msgs/msg/MeshFile`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MeshFile {
    /// The file's name.
    pub filename: String,
    /// Its bytes.
    pub data: Vec<u8>,
}

/// `sensor_msgs/msg/CompressedImage`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CompressedImage {
    /// Header.
    pub header: Header,
    /// `jpeg`, `png`, ….
    pub format: String,
    /// The compressed bytes.
    pub data: Vec<u8>,
}

/// `visualization_msgs/msg/Marker` (Humble's layout onwards, with the texture and mesh
/// fields).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// Header: the frame the points are in.
    pub header: Header,
    /// Namespace: with `id`, names the marker.
    pub ns: String,
    /// Id within the namespace.
    pub id: i32,
    /// [`Marker::LINE_STRIP`], ….
    #[serde(rename = "type")]
    pub kind: i32,
    /// [`Marker::ADD`], [`Marker::DELETE`], [`Marker::DELETEALL`].
    pub action: i32,
    /// The pose of the marker's own frame in `header.frame_id`.
    pub pose: Pose,
    /// Scale (a line's width is `scale.x`).
    pub scale: Vector3,
    /// Colour.
    pub color: ColorRGBA,
    /// How long the marker lives; zero: until deleted.
    pub lifetime: Duration,
    /// Re-transform the marker into its frame every frame.
    pub frame_locked: bool,
    /// The points of a line strip, list, ….
    pub points: Vec<Point>,
    /// Per-point colours (empty: `color`).
    pub colors: Vec<ColorRGBA>,
    /// Texture (unused here).
    pub texture_resource: String,
    /// Texture (unused here).
    pub texture: CompressedImage,
    /// Texture coordinates (unused here).
    pub uv_coordinates: Vec<UVCoordinate>,
    /// Text (unused here).
    pub text: String,
    /// Mesh (unused here).
    pub mesh_resource: String,
    /// Mesh (unused here).
    pub mesh_file: MeshFile,
    /// Mesh (unused here).
    pub mesh_use_embedded_materials: bool,
}

impl Marker {
    /// `type`: a line through `points` in order.
    pub const LINE_STRIP: i32 = 4;
    /// `action`: add or replace.
    pub const ADD: i32 = 0;
    /// `action`: delete the marker `(ns, id)`.
    pub const DELETE: i32 = 2;
    /// `action`: delete every marker (of this publisher's topic).
    pub const DELETEALL: i32 = 3;
}

/// `visualization_msgs/msg/MarkerArray`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MarkerArray {
    /// The markers, applied in order.
    pub markers: Vec<Marker>,
}

impl ros2_client::Message for NavigateToPoseGoal {}
impl ros2_client::Message for NavigateToPoseResult {}
impl ros2_client::Message for NavigateToPoseFeedback {}

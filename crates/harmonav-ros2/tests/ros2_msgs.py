"""ROS 2 messages as Eclipse Cyclone DDS (PyPI `cyclonedds`) IDL structs, named as rosidl names
them on the wire (`sensor_msgs::msg::dds_::LaserScan_` on `rt/scan`): the independent peer of
harmonav-ros2's hand-written serde structs. Field order follows the .msg files."""

from dataclasses import dataclass, field

from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import (
    array, float32, float64, int8, int16, int32, sequence, uint8, uint16, uint32,
)


@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32 = 0
    nanosec: uint32 = 0


@dataclass
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time = field(default_factory=Time)
    frame_id: str = ""


@dataclass
class Vector3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0


@dataclass
class Point(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0


@dataclass
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0
    w: float64 = 1.0


@dataclass
class Pose(IdlStruct, typename="geometry_msgs::msg::dds_::Pose_"):
    position: Point = field(default_factory=Point)
    orientation: Quaternion = field(default_factory=Quaternion)


@dataclass
class PoseStamped(IdlStruct, typename="geometry_msgs::msg::dds_::PoseStamped_"):
    header: Header = field(default_factory=Header)
    pose: Pose = field(default_factory=Pose)


@dataclass
class Twist(IdlStruct, typename="geometry_msgs::msg::dds_::Twist_"):
    linear: Vector3 = field(default_factory=Vector3)
    angular: Vector3 = field(default_factory=Vector3)


@dataclass
class TwistStamped(IdlStruct, typename="geometry_msgs::msg::dds_::TwistStamped_"):
    header: Header = field(default_factory=Header)
    twist: Twist = field(default_factory=Twist)


@dataclass
class PoseWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::PoseWithCovariance_"):
    pose: Pose = field(default_factory=Pose)
    covariance: array[float64, 36] = field(default_factory=lambda: [0.0] * 36)


@dataclass
class TwistWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::TwistWithCovariance_"):
    twist: Twist = field(default_factory=Twist)
    covariance: array[float64, 36] = field(default_factory=lambda: [0.0] * 36)


@dataclass
class Odometry(IdlStruct, typename="nav_msgs::msg::dds_::Odometry_"):
    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    pose: PoseWithCovariance = field(default_factory=PoseWithCovariance)
    twist: TwistWithCovariance = field(default_factory=TwistWithCovariance)


@dataclass
class LaserScan(IdlStruct, typename="sensor_msgs::msg::dds_::LaserScan_"):
    header: Header = field(default_factory=Header)
    angle_min: float32 = 0.0
    angle_max: float32 = 0.0
    angle_increment: float32 = 0.0
    time_increment: float32 = 0.0
    scan_time: float32 = 0.0
    range_min: float32 = 0.0
    range_max: float32 = 0.0
    ranges: sequence[float32] = field(default_factory=list)
    intensities: sequence[float32] = field(default_factory=list)


@dataclass
class MapMetaData(IdlStruct, typename="nav_msgs::msg::dds_::MapMetaData_"):
    map_load_time: Time = field(default_factory=Time)
    resolution: float32 = 0.0
    width: uint32 = 0
    height: uint32 = 0
    origin: Pose = field(default_factory=Pose)


@dataclass
class OccupancyGrid(IdlStruct, typename="nav_msgs::msg::dds_::OccupancyGrid_"):
    header: Header = field(default_factory=Header)
    info: MapMetaData = field(default_factory=MapMetaData)
    data: sequence[int8] = field(default_factory=list)


@dataclass
class Transform(IdlStruct, typename="geometry_msgs::msg::dds_::Transform_"):
    translation: Vector3 = field(default_factory=Vector3)
    rotation: Quaternion = field(default_factory=Quaternion)


@dataclass
class TransformStamped(IdlStruct, typename="geometry_msgs::msg::dds_::TransformStamped_"):
    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    transform: Transform = field(default_factory=Transform)


@dataclass
class TFMessage(IdlStruct, typename="tf2_msgs::msg::dds_::TFMessage_"):
    transforms: sequence[TransformStamped] = field(default_factory=list)


@dataclass
class Clock(IdlStruct, typename="rosgraph_msgs::msg::dds_::Clock_"):
    clock: Time = field(default_factory=Time)


@dataclass
class String(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    data: str = ""


@dataclass
class Duration(IdlStruct, typename="builtin_interfaces::msg::dds_::Duration_"):
    sec: int32 = 0
    nanosec: uint32 = 0


# The navigate_to_pose action (nav2_msgs/action/NavigateToPose as in Jazzy) and action_msgs, as
# rosidl lays an action out on the wire: three services (rq/<name>/_action/send_goalRequest,
# …) and two topics (rt/<name>/_action/feedback, …/status).


@dataclass
class UUID(IdlStruct, typename="unique_identifier_msgs::msg::dds_::UUID_"):
    uuid: array[uint8, 16] = field(default_factory=lambda: [0] * 16)


@dataclass
class NavigateToPoseGoal(IdlStruct, typename="nav2_msgs::action::dds_::NavigateToPose_Goal_"):
    pose: PoseStamped = field(default_factory=PoseStamped)
    behavior_tree: str = ""


@dataclass
class NavigateToPoseResult(IdlStruct, typename="nav2_msgs::action::dds_::NavigateToPose_Result_"):
    error_code: uint16 = 0
    error_msg: str = ""


@dataclass
class NavigateToPoseFeedback(IdlStruct, typename="nav2_msgs::action::dds_::NavigateToPose_Feedback_"):
    current_pose: PoseStamped = field(default_factory=PoseStamped)
    navigation_time: Duration = field(default_factory=Duration)
    estimated_time_remaining: Duration = field(default_factory=Duration)
    number_of_recoveries: int16 = 0
    distance_remaining: float32 = 0.0


@dataclass
class SendGoalRequest(IdlStruct, typename="nav2_msgs::action::dds_::NavigateToPose_SendGoal_Request_"):
    goal_id: UUID = field(default_factory=UUID)
    goal: NavigateToPoseGoal = field(default_factory=NavigateToPoseGoal)


@dataclass
class SendGoalResponse(IdlStruct, typename="nav2_msgs::action::dds_::NavigateToPose_SendGoal_Response_"):
    accepted: bool = False
    stamp: Time = field(default_factory=Time)


@dataclass
class GetResultRequest(IdlStruct, typename="nav2_msgs::action::dds_::NavigateToPose_GetResult_Request_"):
    goal_id: UUID = field(default_factory=UUID)


@dataclass
class GetResultResponse(IdlStruct, typename="nav2_msgs::action::dds_::NavigateToPose_GetResult_Response_"):
    status: int8 = 0
    result: NavigateToPoseResult = field(default_factory=NavigateToPoseResult)


@dataclass
class FeedbackMessage(IdlStruct, typename="nav2_msgs::action::dds_::NavigateToPose_FeedbackMessage_"):
    goal_id: UUID = field(default_factory=UUID)
    feedback: NavigateToPoseFeedback = field(default_factory=NavigateToPoseFeedback)


@dataclass
class GoalInfo(IdlStruct, typename="action_msgs::msg::dds_::GoalInfo_"):
    goal_id: UUID = field(default_factory=UUID)
    stamp: Time = field(default_factory=Time)


@dataclass
class GoalStatus(IdlStruct, typename="action_msgs::msg::dds_::GoalStatus_"):
    goal_info: GoalInfo = field(default_factory=GoalInfo)
    status: int8 = 0


@dataclass
class GoalStatusArray(IdlStruct, typename="action_msgs::msg::dds_::GoalStatusArray_"):
    status_list: sequence[GoalStatus] = field(default_factory=list)


@dataclass
class CancelGoalRequest(IdlStruct, typename="action_msgs::srv::dds_::CancelGoal_Request_"):
    goal_info: GoalInfo = field(default_factory=GoalInfo)


@dataclass
class CancelGoalResponse(IdlStruct, typename="action_msgs::srv::dds_::CancelGoal_Response_"):
    return_code: int8 = 0
    goals_canceling: sequence[GoalInfo] = field(default_factory=list)


@dataclass
class ColorRGBA(IdlStruct, typename="std_msgs::msg::dds_::ColorRGBA_"):
    r: float32 = 0.0
    g: float32 = 0.0
    b: float32 = 0.0
    a: float32 = 0.0


@dataclass
class UVCoordinate(IdlStruct, typename="visualization_msgs::msg::dds_::UVCoordinate_"):
    u: float32 = 0.0
    v: float32 = 0.0


@dataclass
class MeshFile(IdlStruct, typename="visualization_msgs::msg::dds_::MeshFile_"):
    filename: str = ""
    data: sequence[uint8] = field(default_factory=list)


@dataclass
class CompressedImage(IdlStruct, typename="sensor_msgs::msg::dds_::CompressedImage_"):
    header: Header = field(default_factory=Header)
    format: str = ""
    data: sequence[uint8] = field(default_factory=list)


@dataclass
class Marker(IdlStruct, typename="visualization_msgs::msg::dds_::Marker_"):
    header: Header = field(default_factory=Header)
    ns: str = ""
    id: int32 = 0
    type: int32 = 0
    action: int32 = 0
    pose: Pose = field(default_factory=Pose)
    scale: Vector3 = field(default_factory=Vector3)
    color: ColorRGBA = field(default_factory=ColorRGBA)
    lifetime: Duration = field(default_factory=Duration)
    frame_locked: bool = False
    points: sequence[Point] = field(default_factory=list)
    colors: sequence[ColorRGBA] = field(default_factory=list)
    texture_resource: str = ""
    texture: CompressedImage = field(default_factory=CompressedImage)
    uv_coordinates: sequence[UVCoordinate] = field(default_factory=list)
    text: str = ""
    mesh_resource: str = ""
    mesh_file: MeshFile = field(default_factory=MeshFile)
    mesh_use_embedded_materials: bool = False


@dataclass
class MarkerArray(IdlStruct, typename="visualization_msgs::msg::dds_::MarkerArray_"):
    markers: sequence[Marker] = field(default_factory=list)


def samples():
    """One message of each type with distinct, awkward values (odd string lengths, so that
    the alignment after them matters; inf and nan ranges; negative cells)."""
    inf, nan = float("inf"), float("nan")
    h = Header(stamp=Time(sec=1700000000, nanosec=123456789), frame_id="laser")
    q = Quaternion(x=0.0, y=0.0, z=0.3826834323650898, w=0.9238795325112867)
    pose = Pose(position=Point(x=1.5, y=-2.25, z=0.125), orientation=q)
    return {
        "time": Time(sec=-3, nanosec=999999999),
        "header": Header(stamp=Time(sec=7, nanosec=8), frame_id="odom"),
        "twist": Twist(linear=Vector3(x=0.5, y=-0.25, z=0.0), angular=Vector3(x=0.0, y=0.0, z=1.5)),
        "twist_stamped": TwistStamped(header=Header(stamp=Time(sec=1, nanosec=2), frame_id="b"), twist=Twist(linear=Vector3(x=0.1))),
        "pose_stamped": PoseStamped(header=Header(stamp=Time(sec=5, nanosec=6), frame_id="map"), pose=pose),
        "odometry": Odometry(
            header=Header(stamp=Time(sec=9, nanosec=10), frame_id="odom"),
            child_frame_id="base_link",
            pose=PoseWithCovariance(pose=pose, covariance=[float(i) for i in range(36)]),
            twist=TwistWithCovariance(twist=Twist(linear=Vector3(x=0.2)), covariance=[-float(i) for i in range(36)]),
        ),
        "laser_scan": LaserScan(
            header=h, angle_min=-3.0, angle_max=3.0, angle_increment=1.5, time_increment=0.001,
            scan_time=0.1, range_min=0.1, range_max=10.0,
            ranges=[1.0, inf, -inf, nan, 0.05], intensities=[7.0],
        ),
        "occupancy_grid": OccupancyGrid(
            header=Header(stamp=Time(sec=11, nanosec=12), frame_id="map"),
            info=MapMetaData(map_load_time=Time(sec=13, nanosec=14), resolution=0.05, width=3, height=2, origin=pose),
            data=[0, 100, -1, 50, 0, 0],
        ),
        "tf_message": TFMessage(transforms=[
            TransformStamped(header=Header(stamp=Time(sec=1, nanosec=0), frame_id="map"), child_frame_id="odom",
                             transform=Transform(translation=Vector3(x=1.0, y=2.0, z=3.0), rotation=q)),
            TransformStamped(header=Header(stamp=Time(sec=2, nanosec=0), frame_id="odom"), child_frame_id="base_link"),
        ]),
        "clock": Clock(clock=Time(sec=42, nanosec=43)),
        "string": String(data="stopped: scan missing or stale"),
        "duration": Duration(sec=12, nanosec=345),
        "send_goal_request": SendGoalRequest(
            goal_id=UUID(uuid=list(range(1, 17))),
            goal=NavigateToPoseGoal(pose=PoseStamped(header=Header(stamp=Time(sec=5, nanosec=6), frame_id="map"), pose=pose),
                                    behavior_tree="bt"),
        ),
        "send_goal_response": SendGoalResponse(accepted=True, stamp=Time(sec=21, nanosec=22)),
        "get_result_request": GetResultRequest(goal_id=UUID(uuid=list(range(1, 17)))),
        "get_result_response": GetResultResponse(status=6, result=NavigateToPoseResult(error_code=206, error_msg="occupied")),
        "feedback_message": FeedbackMessage(
            goal_id=UUID(uuid=list(range(1, 17))),
            feedback=NavigateToPoseFeedback(
                current_pose=PoseStamped(header=Header(stamp=Time(sec=5, nanosec=6), frame_id="map"), pose=pose),
                navigation_time=Duration(sec=3, nanosec=4), estimated_time_remaining=Duration(sec=7, nanosec=8),
                number_of_recoveries=-2, distance_remaining=1.25,
            ),
        ),
        "goal_status_array": GoalStatusArray(status_list=[
            GoalStatus(goal_info=GoalInfo(goal_id=UUID(uuid=list(range(1, 17))), stamp=Time(sec=1, nanosec=2)), status=2),
            GoalStatus(goal_info=GoalInfo(goal_id=UUID(uuid=[255] * 16), stamp=Time(sec=3, nanosec=4)), status=5),
        ]),
        "cancel_goal_request": CancelGoalRequest(goal_info=GoalInfo(goal_id=UUID(uuid=list(range(1, 17))), stamp=Time(sec=9, nanosec=10))),
        "cancel_goal_response": CancelGoalResponse(return_code=0, goals_canceling=[
            GoalInfo(goal_id=UUID(uuid=list(range(1, 17))), stamp=Time(sec=9, nanosec=10)),
        ]),
        "marker_array": MarkerArray(markers=[
            Marker(header=Header(stamp=Time(sec=3, nanosec=4), frame_id="map"), ns="obstacles", id=0,
                   type=0, action=3),
            Marker(header=Header(stamp=Time(sec=3, nanosec=4), frame_id="map"), ns="obstacles", id=7,
                   type=4, action=0, pose=pose, scale=Vector3(x=0.02),
                   color=ColorRGBA(r=1.0, g=0.5, b=0.25, a=0.75), lifetime=Duration(sec=1, nanosec=2),
                   frame_locked=True, points=[Point(x=1.0, y=2.0), Point(x=-3.5, y=0.25, z=1.0)],
                   colors=[ColorRGBA(r=0.125)], texture_resource="t",
                   texture=CompressedImage(header=Header(frame_id="cam"), format="png", data=[1, 2, 3]),
                   uv_coordinates=[UVCoordinate(u=0.5, v=-1.0)], text="abc", mesh_resource="m",
                   mesh_file=MeshFile(filename="f.stl", data=[9]), mesh_use_embedded_materials=True),
        ]),
    }


if __name__ == "__main__":
    # The reference bytes of tests/cdr.rs: XCDR1, little endian (what ROS 2's DDS RMWs put on
    # the wire for these types), the 4-byte encapsulation header stripped.
    import sys

    for name, msg in samples().items():
        b = msg.serialize(use_version_2=False)
        assert b[:2] == b"\x00\x01", (name, b[:4])
        sys.stdout.write(f"{name} {b[4:].hex()}\n")

"""The second independent peer of harmonav-ros2's end-to-end test (tests/e2e.rs): the simulated
robot of `peer_world.py` on a real ROS 2 stack, rclpy over `rmw_fastrtps_cpp` (Fast DDS, the
default middleware of recent ROS 2 releases), from PyPI's wheels of the ROS packages; message
types are rosidl's generated ones, not hand-written. It publishes `/map` (reliable, transient
local), `/scan` (sensor-data QoS, best effort), `/odom` and `/goal_pose`, integrates
`/cmd_vel` at 20 Hz, and judges as the Cyclone peer does (`peer_world.drive`): arrival, no
contact with its truth, a stop within the timeout when its scans stop, a zero command after
SIGTERM; and, through rclpy's graph API, that the Rust node is listed with its topics and
their types, its status on `/harmonav/status`, and (in the room it knows from scans alone)
its perceived obstacles on `/harmonav/obstacles` (`visualization_msgs/MarkerArray`) around
the disc of the truth.

Not here, for want of a wheel: nav2_msgs (so goals go through `/goal_pose`, not the
`navigate_to_pose` action; the Cyclone peer tests the action) and tf2_msgs (so no
`/tf_static`: the laser is at base_link, its scans stamped in `base_link`, and the node takes
the edge as the identity). Prints one JSON line; exit 0 when every check passed, 1 otherwise.

Only for a private network namespace: the Rust test refuses to run it elsewhere."""

import argparse
import array
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rclpy  # noqa: E402
from geometry_msgs.msg import PoseStamped, Twist  # noqa: E402
from nav_msgs.msg import OccupancyGrid, Odometry  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.utilities import get_rmw_implementation_identifier  # noqa: E402
from rclpy.qos import (  # noqa: E402
    DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data,
)
from sensor_msgs.msg import LaserScan  # noqa: E402
from std_msgs.msg import String  # noqa: E402
from visualization_msgs.msg import Marker, MarkerArray  # noqa: E402

from peer_world import H, RANGE_MAX, RANGE_MIN, Robot, drive, scan_angles, scan_ranges  # noqa: E402

NODE = "harmonav"  # the Rust node's name (params::NODE_NAME)


class Peer(Robot):
    def __init__(self, args):
        super().__init__(args.world, False)
        self.args = args
        self.node = rclpy.create_node("harmonav_rclpy_peer", start_parameter_services=False)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL,
                             history=HistoryPolicy.KEEP_LAST)
        n = self.node
        self.map_pub = n.create_publisher(OccupancyGrid, "map", latched) \
            if args.world == "floor" else None
        self.scan_pub = n.create_publisher(LaserScan, "scan", qos_profile_sensor_data)
        self.odom_pub = n.create_publisher(Odometry, "odom", 10)
        self.goal_pub = n.create_publisher(PoseStamped, "goal_pose", 10)
        self.events = 0
        self.statuses = []
        n.create_subscription(Twist, "cmd_vel", self._on_cmd, 10)
        n.create_subscription(String, "harmonav/status", self._on_status, latched)
        self.marker_arrays = []
        n.create_subscription(MarkerArray, "harmonav/obstacles", self._on_markers, latched)
        self.executor = SingleThreadedExecutor()
        self.executor.add_node(n)

    def _on_cmd(self, t):
        self.events += 1
        self.on_twist(t)

    def _on_status(self, s):
        self.events += 1
        self.statuses.append(s.data)

    def _on_markers(self, a):
        self.events += 1
        self.marker_arrays.append(a)

    def poll(self):
        # Every callback ready now, without waiting.
        for _ in range(50):
            before = self.events
            self.executor.spin_once(timeout_sec=0)
            if self.events == before:
                break

    def stamp(self):
        return self.node.get_clock().now().to_msg()

    def publish_map(self):
        ox, oy, w, h, data = self.world.grid()
        g = OccupancyGrid()
        g.header.frame_id = "map"
        g.header.stamp = self.stamp()
        g.info.resolution = 0.05
        g.info.width, g.info.height = w, h
        g.info.origin.position.x, g.info.origin.position.y = ox, oy
        g.data = array.array("b", data)
        self.map_pub.publish(g)

    def publish_odom(self):
        o = Odometry()
        o.header.stamp = self.stamp()
        o.header.frame_id = "odom"
        o.child_frame_id = "base_link"
        o.pose.pose.position.x, o.pose.pose.position.y = self.x
        o.pose.pose.orientation.z = math.sin(self.yaw / 2)
        o.pose.pose.orientation.w = math.cos(self.yaw / 2)
        self.odom_pub.publish(o)

    def publish_scan(self):
        s = LaserScan()
        s.header.stamp = self.stamp()
        s.header.frame_id = "base_link"  # no tf2_msgs wheel: the laser at the base
        s.angle_min, s.angle_max, s.angle_increment = scan_angles()
        s.scan_time = H
        s.range_min, s.range_max = RANGE_MIN, RANGE_MAX
        s.ranges = array.array("f", scan_ranges(self.world, self.x, self.yaw, laser=0.0))
        self.scan_pub.publish(s)

    def send_goal(self, g):
        self.goal = g
        p = PoseStamped()
        p.header.stamp = self.stamp()
        p.header.frame_id = "map"
        p.pose.position.x, p.pose.position.y = g
        self.goal_pub.publish(p)


def graph(peer, out):
    """The Rust node as rclpy's graph API sees it."""
    n = peer.node
    names = [name for name, _ in n.get_node_names_and_namespaces()]
    topics = dict(n.get_topic_names_and_types())
    out["graph"] = {"nodes": sorted(names), "cmd_vel": topics.get("/cmd_vel"),
                    "scan": topics.get("/scan")}
    c = out["checks"]
    c["graph_lists_node"] = NODE in names
    c["graph_cmd_vel_type"] = topics.get("/cmd_vel") == ["geometry_msgs/msg/Twist"]
    c["graph_scan_subscribed"] = n.count_subscribers("/scan") >= 1
    c["graph_odom_subscribed"] = n.count_subscribers("/odom") >= 1


def markers(peer, out):
    """The perceived obstacles on `/harmonav/obstacles`: some line strip in `map` rings each
    disc of the truth (every point outside it, none more than 0.6 m away)."""
    strips = [m for a in peer.marker_arrays for m in a.markers
              if m.type == Marker.LINE_STRIP and m.action == Marker.ADD and m.header.frame_id == "map"]
    out["marker_arrays"] = len(peer.marker_arrays)
    for cx, cy, r in peer.world.discs:
        out["checks"]["markers_ring_disc"] = any(
            len(m.points) > 3 and all(r <= math.hypot(p.x - cx, p.y - cy) <= r + 0.6 for p in m.points)
            for m in strips)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--world", choices=["floor", "scans"], required=True)
    ap.add_argument("--node-pid", type=int, help="send it SIGTERM at the end and check the zero")
    ap.add_argument("--scan-timeout", type=float, default=0.5)
    ap.add_argument("--arrive", action="store_true", help="drive to the goal first")
    ap.add_argument("--max-time", type=float, default=90.0)
    args = ap.parse_args()
    args.diff = False
    rclpy.init()
    peer = Peer(args)
    out = {"world": args.world, "rmw": get_rmw_implementation_identifier(), "checks": {}}
    if peer.map_pub is not None:
        peer.publish_map()
    t0 = time.monotonic()
    # A RustDDS node joining after Fast DDS gets data ~1.2 s late: wait for its commands and
    # for its goal subscription before the first goal.
    end = t0 + 30.0
    while time.monotonic() < end and (peer.cmds == 0 or peer.goal_pub.get_subscription_count() == 0):
        peer.tick(True, [])
    if peer.cmds == 0:
        print(json.dumps({"error": "no command from the node within 30 s"}), flush=True)
        return 1
    out["discovery_s"] = round(time.monotonic() - t0, 3)
    graph(peer, out)
    ok = all(out["checks"].values())
    ok = drive(peer, args, out) and ok
    markers(peer, out)
    moving = [s for s in peer.statuses if s.startswith("moving")]
    out["statuses"] = len(peer.statuses)
    out["checks"]["status_moving"] = bool(moving)
    ok = ok and bool(moving) and out["checks"].get("markers_ring_disc", True)
    out["ok"] = ok
    print(json.dumps(out), flush=True)
    peer.node.destroy_node()
    rclpy.try_shutdown()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

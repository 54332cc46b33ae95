"""The independent peer of harmonav-ros2's end-to-end test (tests/e2e.rs): a robot simulator on
Eclipse Cyclone DDS (PyPI `cyclonedds`), speaking ROS 2's wire names and QoS without any ROS
install. It owns the truth (`peer_world.py`: a room of axis-aligned boxes and discs), publishes
what a robot would (`/map` transient local, `/scan` best effort from its own ray casting,
`/odom`, `/tf_static` base_link → laser, `/goal_pose`), integrates `/cmd_vel` at 20 Hz as a
holonomic base, and judges: arrival, no contact with its truth, a stop within the timeout when
its scans stop, a zero command when the node is sent SIGTERM. With `--action` it sends its goals
through the `navigate_to_pose` action instead (rosidl's wire layout, the "enhanced" service
mapping's plain payloads): arrival with feedback and a succeeded result, a goal preempted by the
next, a cancel that stops the robot, and a goal in an occupied cell aborted with its code.
Prints one JSON line; exit 0 when every asked check passed, 1 otherwise.

Only for a private network namespace: the Rust test refuses to run it elsewhere."""

import argparse
import dataclasses
import json
import math
import os
import signal
import sys
import time
import types
import uuid

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from cyclonedds.core import Policy, Qos  # noqa: E402
from cyclonedds.domain import DomainParticipant  # noqa: E402
from cyclonedds.idl import IdlStruct  # noqa: E402
from cyclonedds.idl.types import array, int32, uint8, uint32  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402
from cyclonedds.sub import DataReader  # noqa: E402
from cyclonedds.topic import Topic  # noqa: E402
from cyclonedds.util import duration  # noqa: E402

import ros2_msgs as m  # noqa: E402

from peer_world import (  # noqa: E402
    H, LASER, RADIUS, RANGE_MAX, RANGE_MIN, TOLERANCE, Robot, drive, scan_angles, scan_ranges,
    worlds,
)


def grid_msg(world):
    """The world's map as a `nav_msgs/OccupancyGrid` in `map`."""
    ox, oy, w, h, data = world.grid()
    info = m.MapMetaData(resolution=0.05, width=w, height=h,
                         origin=m.Pose(position=m.Point(x=ox, y=oy)))
    return m.OccupancyGrid(header=m.Header(frame_id="map"), info=info, data=data)


def stamp(t):
    return m.Time(sec=int(t), nanosec=int((t - int(t)) * 1e9))


class Peer(Robot):
    def __init__(self, args):
        super().__init__(args.world, args.diff)
        self.args = args
        dp = DomainParticipant(int(os.environ.get("ROS_DOMAIN_ID", "0")))
        self.dp = dp
        rel = Policy.Reliability.Reliable(max_blocking_time=duration(seconds=1))
        latched = Qos(rel, Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
        sensor = Qos(Policy.Reliability.BestEffort, Policy.History.KeepLast(5))
        reliable = Qos(rel, Policy.History.KeepLast(10))

        def writer(name, ty, qos):
            return DataWriter(dp, Topic(dp, "rt/" + name, ty), qos=qos)

        self.map_w = writer("map", m.OccupancyGrid, latched) if args.world == "floor" else None
        self.scan_w = writer("scan", m.LaserScan, sensor)
        self.odom_w = writer("odom", m.Odometry, reliable)
        self.goal_w = writer("goal_pose", m.PoseStamped, reliable)
        self.tf_static_w = writer("tf_static", m.TFMessage, latched)
        cmd_ty = m.TwistStamped if args.stamped else m.Twist
        self.cmd_r = DataReader(dp, Topic(dp, "rt/cmd_vel", cmd_ty),
                                qos=Qos(Policy.Reliability.BestEffort, Policy.History.KeepLast(10)))
        if args.action:
            self.action = ActionClient(dp, "navigate_to_pose", reliable, args.cyclone_mapping)

    def poll(self):
        for s in self.cmd_r.take(N=100):
            if not isinstance(s, (m.Twist, m.TwistStamped)):
                continue  # an InvalidSample: the writer's disposal when the node leaves
            self.on_twist(s.twist if self.args.stamped else s)

    def odom(self):
        now = time.time()
        q = m.Quaternion(z=math.sin(self.yaw / 2), w=math.cos(self.yaw / 2))
        pose = m.Pose(position=m.Point(x=self.x[0], y=self.x[1]), orientation=q)
        return m.Odometry(header=m.Header(stamp=stamp(now), frame_id="odom"), child_frame_id="base_link",
                          pose=m.PoseWithCovariance(pose=pose))

    def scan(self):
        amin, amax, inc = scan_angles()
        ranges = scan_ranges(self.world, self.x, self.yaw)
        return m.LaserScan(header=m.Header(stamp=stamp(time.time()), frame_id="laser"),
                           angle_min=amin, angle_max=amax, angle_increment=inc,
                           scan_time=H, range_min=RANGE_MIN, range_max=RANGE_MAX, ranges=ranges)

    def send_goal(self, g):
        self.goal = g
        self.goal_w.write(m.PoseStamped(header=m.Header(stamp=stamp(time.time()), frame_id="map"),
                                        pose=m.Pose(position=m.Point(x=g[0], y=g[1]))))

    def publish_odom(self):
        self.odom_w.write(self.odom())

    def publish_scan(self):
        self.scan_w.write(self.scan())


def cyclone_wire(cls):
    """`cls` with rmw_cyclonedds_cpp's service header in front of its fields (the client GUID's
    last 8 bytes, the sequence number's high and low words), under the same DDS type name."""
    ann = {"guid": array[uint8, 8], "seq_high": int32, "seq_low": uint32, **cls.__annotations__}
    defaults = {"guid": dataclasses.field(default_factory=lambda: [0] * 8), "seq_high": 0, "seq_low": 0}
    for f in dataclasses.fields(cls):
        defaults[f.name] = dataclasses.field(default_factory=f.default_factory) \
            if f.default_factory is not dataclasses.MISSING else f.default
    body = lambda ns: ns.update({"__annotations__": ann, **defaults})  # noqa: E731
    new = types.new_class(cls.__name__, (IdlStruct,), {"typename": cls.__idl_typename__}, body)
    return dataclasses.dataclass(new)


# action_msgs/msg/GoalStatus's values.
SUCCEEDED, CANCELED, ABORTED = 4, 5, 6


class ActionClient:
    """A navigate_to_pose client on bare DDS: its three services as request/reply topic pairs
    (rq/<name>/_action/send_goalRequest, rr/…Reply, …) and its feedback and status topics.
    A reply is taken as the answer to the oldest request of its kind still open."""

    def __init__(self, dp, name, qos, cyclone):
        base = name + "/_action/"
        self.seq = 0
        wire = cyclone_wire if cyclone else (lambda c: c)
        self.SendGoalRequest, self.GetResultRequest, self.CancelGoalRequest = (
            wire(m.SendGoalRequest), wire(m.GetResultRequest), wire(m.CancelGoalRequest))

        def service(srv, req, rep):
            rep = wire(rep)
            w = DataWriter(dp, Topic(dp, "rq/" + base + srv + "Request", req), qos=qos)
            r = DataReader(dp, Topic(dp, "rr/" + base + srv + "Reply", rep), qos=qos)
            return w, r

        self.goal_w, self.goal_r = service("send_goal", self.SendGoalRequest, m.SendGoalResponse)
        self.result_w, self.result_r = service("get_result", self.GetResultRequest, m.GetResultResponse)
        self.cancel_w, self.cancel_r = service("cancel_goal", self.CancelGoalRequest, m.CancelGoalResponse)
        self.feedback_r = DataReader(dp, Topic(dp, "rt/" + base + "feedback", m.FeedbackMessage), qos=qos)
        latched = Qos(Policy.Reliability.Reliable(max_blocking_time=duration(seconds=1)),
                      Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
        self.status_r = DataReader(dp, Topic(dp, "rt/" + base + "status", m.GoalStatusArray), qos=latched)
        self.feedback = []  # (goal id bytes, feedback)
        self.results = {}  # goal id bytes → GetResultResponse
        self.pending_results = []  # goal ids asked for, in order
        self.statuses = {}  # goal id bytes → latest status

    def matched(self):
        return all(w.get_publication_matched_status().current_count > 0
                   for w in (self.goal_w, self.result_w, self.cancel_w))

    @staticmethod
    def valid(samples, ty):
        return [x for x in samples if type(x).__name__ == ty.__name__]

    def request(self, ty, **fields):
        """A request with the next sequence number (used by the Cyclone header only)."""
        self.seq += 1
        if "seq_low" in ty.__annotations__:
            fields.update(guid=[7] * 8, seq_low=self.seq)
        return ty(**fields)

    def poll(self):
        for f in self.valid(self.feedback_r.take(N=100), m.FeedbackMessage):
            self.feedback.append((bytes(f.goal_id.uuid), f.feedback))
        for r in self.valid(self.result_r.take(N=100), m.GetResultResponse):
            # The reply names no goal: results come in the order the goals end, which in
            # run_action is the order they were sent.
            if self.pending_results:
                self.results[self.pending_results.pop(0)] = r
        for a in self.valid(self.status_r.take(N=100), m.GoalStatusArray):
            for st in a.status_list:
                self.statuses[bytes(st.goal_info.goal_id.uuid)] = st.status

    def send_goal(self, peer, g, timeout=5.0):
        """The goal's id and whether it was accepted (None: no answer); asks for its result."""
        gid = uuid.uuid4().bytes
        goal = m.NavigateToPoseGoal(pose=m.PoseStamped(
            header=m.Header(stamp=stamp(time.time()), frame_id="map"),
            pose=m.Pose(position=m.Point(x=g[0], y=g[1]))))
        self.goal_w.write(self.request(self.SendGoalRequest, goal_id=m.UUID(uuid=list(gid)), goal=goal))
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            got = self.valid(self.goal_r.take(N=10), m.SendGoalResponse)
            if got:
                self.pending_results.append(gid)
                self.result_w.write(self.request(self.GetResultRequest, goal_id=m.UUID(uuid=list(gid))))
                return gid, got[-1].accepted
            peer.tick(True, [])
        return gid, None

    def cancel(self, peer, gid, timeout=5.0):
        self.cancel_w.write(self.request(self.CancelGoalRequest,
                                         goal_info=m.GoalInfo(goal_id=m.UUID(uuid=list(gid)))))
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            got = self.valid(self.cancel_r.take(N=10), m.CancelGoalResponse)
            if got:
                return got[-1]
            peer.tick(True, [])
        return None

    def wait_result(self, peer, gid, timeout, on_tick=None):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            self.poll()
            if gid in self.results:
                return self.results[gid]
            peer.tick(True, [])
            if on_tick:
                on_tick()
        return None


def run_action(peer, out):
    """The action's checks; returns whether all passed."""
    a, c = peer.action, out["checks"]
    end = time.monotonic() + 10.0
    while not a.matched() and time.monotonic() < end:
        peer.tick(True, [])
    c["action_matched"] = a.matched()
    start, goal = worlds(peer.args.world)[1:]
    clearance = [math.inf]

    def watch():
        clearance[0] = min(clearance[0], peer.world.clearance(peer.x))

    # 1. To the goal: accepted, feedback with a falling distance, succeeded.
    t1 = time.monotonic()
    g1, ok1 = a.send_goal(peer, goal)
    r1 = a.wait_result(peer, g1, peer.args.max_time, watch)
    d = math.hypot(peer.x[0] - goal[0], peer.x[1] - goal[1])
    fb = [f.distance_remaining for g, f in a.feedback if g == g1]
    out["action_arrival_s"] = round(time.monotonic() - t1, 2)
    out["action_final_distance"] = round(d, 4)
    out["action_feedback"] = {"n": len(fb), "first": fb and round(fb[0], 3), "last": fb and round(fb[-1], 3)}
    c["goal_accepted"] = ok1 is True
    c["succeeded"] = r1 is not None and r1.status == SUCCEEDED and r1.result.error_code == 0
    c["arrived_in_tolerance"] = d <= TOLERANCE
    c["feedback_distance_falls"] = len(fb) > 5 and fb[0] > 1.0 and fb[-1] < 0.3
    c["no_contact"] = clearance[0] > RADIUS
    out["min_clearance"] = round(clearance[0], 4)

    # 2. A goal preempted by the next: aborted with its result.
    g2, ok2 = a.send_goal(peer, start)
    for _ in range(10):
        peer.tick(True, [])
    g3, ok3 = a.send_goal(peer, (start[0], goal[1]))
    r2 = a.wait_result(peer, g2, 5.0)
    c["preempted_aborted"] = bool(ok2 and ok3) and r2 is not None and r2.status == ABORTED \
        and "preempted" in r2.result.error_msg

    # 3. Cancel while moving: zero on /cmd_vel within a few periods, result canceled.
    moving = False
    for _ in range(40):
        peer.tick(True, [])
        if math.hypot(*peer.cmd) > 1e-3:
            moving = True
            break
    t3 = time.monotonic()
    resp = a.cancel(peer, g3)
    stopped_after = None
    while time.monotonic() - t3 < 2.0:
        peer.tick(True, [])
        if peer.cmd == (0.0, 0.0):
            stopped_after = time.monotonic() - t3
            break
    r3 = a.wait_result(peer, g3, 5.0)
    out["cancel_stop_after_s"] = stopped_after and round(stopped_after, 3)
    c["cancel_accepted"] = resp is not None and resp.return_code == 0 and \
        [bytes(i.goal_id.uuid) for i in resp.goals_canceling] == [g3]
    c["cancel_stops"] = moving and stopped_after is not None and stopped_after < 0.5
    c["canceled"] = r3 is not None and r3.status == CANCELED

    # 4. A goal in an occupied cell (the floor world's box): accepted, aborted with 206.
    if peer.args.world == "floor":
        g4, ok4 = a.send_goal(peer, (2.0, 1.5))
        r4 = a.wait_result(peer, g4, 5.0)
        out["occupied_result"] = r4 and {"status": r4.status, "error_code": r4.result.error_code,
                                         "error_msg": r4.result.error_msg}
        c["occupied_aborted"] = ok4 is True and r4 is not None and r4.status == ABORTED \
            and r4.result.error_code == 206
    for _ in range(5):
        peer.tick(True, [])
    a.poll()
    c["status_topic"] = a.statuses.get(g1) == SUCCEEDED and a.statuses.get(g3) == CANCELED
    return all(c.values())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--world", choices=["floor", "scans"], required=True)
    ap.add_argument("--stamped", action="store_true")
    ap.add_argument("--diff", action="store_true", help="a differential-drive base: (linear.x, angular.z)")
    ap.add_argument("--node-pid", type=int, help="send it SIGTERM at the end and check the zero")
    ap.add_argument("--scan-timeout", type=float, default=0.5)
    ap.add_argument("--arrive", action="store_true", help="drive to the goal first")
    ap.add_argument("--max-time", type=float, default=90.0)
    ap.add_argument("--action", action="store_true", help="goals through navigate_to_pose")
    ap.add_argument("--cyclone-mapping", action="store_true",
                    help="the action's services with rmw_cyclonedds_cpp's header in the payload")
    args = ap.parse_args()
    peer = Peer(args)
    out = {"world": args.world, "checks": {}}

    static = m.TransformStamped(header=m.Header(frame_id="base_link"), child_frame_id="laser",
                                transform=m.Transform(translation=m.Vector3(x=LASER, z=0.2)))
    peer.tf_static_w.write(m.TFMessage(transforms=[static]))
    if peer.map_w is not None:
        peer.map_w.write(grid_msg(peer.world))
    t0 = time.monotonic()
    if not peer.wait_for_node(30.0):
        print(json.dumps({"error": "no command from the node within 30 s"}))
        return 1
    out["discovery_s"] = round(time.monotonic() - t0, 3)

    if args.action:
        ok = run_action(peer, out)
        if args.node_pid:
            os.kill(args.node_pid, signal.SIGTERM)
            time.sleep(0.5)
    else:
        ok = drive(peer, args, out)
    out["ok"] = ok
    print(json.dumps(out), flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

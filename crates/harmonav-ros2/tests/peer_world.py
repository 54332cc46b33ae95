"""The simulated robot, shared by harmonav-ros2's two independent peers (tests/e2e.rs):
`ros2_peer.py` (Eclipse Cyclone DDS with ROS 2's wire names) and `rclpy_peer.py` (a real ROS 2
stack, rclpy on Fast DDS). No DDS here: the truth (a room of axis-aligned boxes and discs), its
lidar (ray casting), its map (a raster of the mapped shapes), the robot's motion over one
period of a held command (holonomic, or a unicycle arc), the period itself over a transport
that each peer supplies ([`Robot`]), and the checks of a drive to a goal ([`drive`])."""

import math
import os
import signal
import time

H = 0.05  # the simulator's period (20 Hz), the node's controller_frequency
RADIUS = 0.1  # the robot's radius (the node's robot_radius)
YAW = 0.3  # the robot's constant heading: base_link is turned against map
LASER = 0.1  # the laser 0.1 m ahead of the base
BEAMS = 1080
RANGE_MAX = 3.5
RANGE_MIN = 0.05
TOLERANCE = 0.15  # arrival: within this of the goal (the node's goal_tolerance 0.1, plus slack)


class World:
    def __init__(self, room, boxes, discs, mapped_boxes, mapped_discs):
        self.room = room  # (x0, y0, x1, y1): the free interior
        self.boxes = boxes  # [(x0, y0, x1, y1)]
        self.discs = discs  # [(cx, cy, r)]
        self.mapped_boxes = mapped_boxes
        self.mapped_discs = mapped_discs

    def ray(self, p, a):
        """Distance along the ray from p at angle a to the first surface."""
        dx, dy = math.cos(a), math.sin(a)
        best = math.inf
        x0, y0, x1, y1 = self.room
        for o, d, lo, hi in ((p[0], dx, x0, x1), (p[1], dy, y0, y1)):
            if d > 1e-12:
                best = min(best, (hi - o) / d)
            elif d < -1e-12:
                best = min(best, (lo - o) / d)
        for bx0, by0, bx1, by1 in self.boxes:
            tmin, tmax = 0.0, math.inf
            ok = True
            for o, d, lo, hi in ((p[0], dx, bx0, bx1), (p[1], dy, by0, by1)):
                if abs(d) < 1e-12:
                    if not lo <= o <= hi:
                        ok = False
                        break
                else:
                    t1, t2 = (lo - o) / d, (hi - o) / d
                    tmin, tmax = max(tmin, min(t1, t2)), min(tmax, max(t1, t2))
            if ok and tmin <= tmax:
                best = min(best, tmin)
        for cx, cy, r in self.discs:
            fx, fy = p[0] - cx, p[1] - cy
            b = fx * dx + fy * dy
            c = fx * fx + fy * fy - r * r
            disc = b * b - c
            if disc >= 0:
                t = -b - math.sqrt(disc)
                if t >= 0:
                    best = min(best, t)
        return best

    def clearance(self, p):
        """Distance from p to the nearest surface of the truth."""
        x0, y0, x1, y1 = self.room
        d = min(p[0] - x0, x1 - p[0], p[1] - y0, y1 - p[1])
        for bx0, by0, bx1, by1 in self.boxes:
            ex = max(bx0 - p[0], 0.0, p[0] - bx1)
            ey = max(by0 - p[1], 0.0, p[1] - by1)
            d = min(d, math.hypot(ex, ey))
        for cx, cy, r in self.discs:
            d = min(d, math.hypot(p[0] - cx, p[1] - cy) - r)
        return d

    def grid(self, res=0.05):
        """The map as `(origin_x, origin_y, width, height, cells)`: the mapped shapes
        rasterised, walls 0.1 m thick, row 0 at the bottom, 100 occupied and 0 free."""
        x0, y0, x1, y1 = self.room
        ox, oy = x0 - 0.1, y0 - 0.1
        w = int(round((x1 - x0 + 0.2) / res))
        h = int(round((y1 - y0 + 0.2) / res))
        data = []
        for r in range(h):
            for c in range(w):
                x, y = ox + (c + 0.5) * res, oy + (r + 0.5) * res
                occ = not (x0 <= x <= x1 and y0 <= y <= y1)
                occ = occ or any(a <= x <= b and c_ <= y <= d for a, c_, b, d in self.mapped_boxes)
                occ = occ or any(math.hypot(x - cx, y - cy) <= rr for cx, cy, rr in self.mapped_discs)
                data.append(100 if occ else 0)
        return ox, oy, w, h, data


def worlds(name):
    """The world, the start and the goal."""
    if name == "floor":
        # A 4 × 3 m room with a mapped box in the middle.
        box = (1.6, 1.0, 2.4, 2.0)
        w = World((0.0, 0.0, 4.0, 3.0), [box], [], [box], [])
        return w, (0.6, 0.6), (3.4, 2.4)
    # A 20 m room whose walls the lidar never reaches, a disc across the straight line.
    w = World((0.0, 0.0, 20.0, 20.0), [], [(10.0, 10.1, 0.4)], [], [])
    return w, (8.0, 10.0), (12.0, 10.0)


def scan_ranges(world, x, yaw, laser=LASER):
    """The lidar's ranges from the robot at `x` heading `yaw` (the laser `laser` ahead of the
    base, BEAMS beams from −π counter-clockwise, +inf for no return): with `scan_angles`."""
    lx, ly = x[0] + laser * math.cos(yaw), x[1] + laser * math.sin(yaw)
    inc = 2 * math.pi / BEAMS
    ranges = []
    for i in range(BEAMS):
        r = world.ray((lx, ly), yaw - math.pi + i * inc)
        ranges.append(r if r < RANGE_MAX else math.inf)
    return ranges


def scan_angles():
    """`(angle_min, angle_max, angle_increment)` of `scan_ranges`."""
    inc = 2 * math.pi / BEAMS
    return -math.pi, math.pi - inc, inc


def integrate(x, yaw, cmd, diff):
    """The pose after holding `cmd` for H: `(linear.x, angular.z)` as a unicycle's exact arc
    when `diff`, else `(linear.x, linear.y)` in the base frame. Returns `(x, yaw)`."""
    if diff:
        v, w = cmd
        turn = w * H
        sinc = 1.0 - turn * turn / 24.0 if abs(turn) < 1e-4 else math.sin(turn / 2) / (turn / 2)
        mid = yaw + turn / 2
        return [x[0] + v * H * sinc * math.cos(mid), x[1] + v * H * sinc * math.sin(mid)], yaw + turn
    vx, vy = cmd
    c, s = math.cos(yaw), math.sin(yaw)
    return [x[0] + H * (c * vx - s * vy), x[1] + H * (s * vx + c * vy)], yaw


class Robot:
    """The simulated robot's state and period. A peer subclasses it with its transport:
    `publish_odom()`, `publish_scan()`, `poll()` (hands each `/cmd_vel` twist waiting to
    `on_twist`) and `send_goal(g)`."""

    def __init__(self, world, diff):
        self.world, self.x, self.goal = worlds(world)
        self.x = list(self.x)
        self.yaw = YAW
        self.diff = diff
        self.cmd = (0.0, 0.0)
        self.cmds = 0
        self.last_cmd_at = None
        self.sideways = False

    def on_twist(self, t):
        """A command received (a `Twist`'s fields): held from now on."""
        self.cmd = (t.linear.x, t.angular.z if self.diff else t.linear.y)
        if self.diff and t.linear.y != 0.0:
            self.sideways = True
        self.cmds += 1
        self.last_cmd_at = time.monotonic()

    def take_cmds(self):
        """Takes the commands waiting; whether there was one."""
        n = self.cmds
        self.poll()
        return self.cmds > n

    def tick(self, scans, latencies):
        """One period: odometry, a scan (the answer's latency measured), the command held."""
        start = time.monotonic()
        self.publish_odom()
        if scans:
            self.take_cmds()
            self.publish_scan()
            sent = time.monotonic()
            # The node answers each scan at once: wait for the next command (≤ one period).
            while time.monotonic() - sent < H * 0.9:
                if self.take_cmds():
                    latencies.append(time.monotonic() - sent)
                    break
                time.sleep(0.0005)
        else:
            self.take_cmds()
        self.x, self.yaw = integrate(self.x, self.yaw, self.cmd, self.diff)
        rest = H - (time.monotonic() - start)
        if rest > 0:
            time.sleep(rest)

    def wait_for_node(self, timeout):
        """Until the node's commands arrive (it publishes zero before any goal), with
        odometry and scans going so that it sees a fresh robot."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            self.tick(True, [])
            if self.cmds > 0:
                return True
        return False


def drive(robot, args, out):
    """Goals through the goal topic, judged against the truth: with `args.arrive` to the
    world's goal (arrival, no contact); then a goal 4 m away and the scans stopped (a stop
    within `args.scan_timeout`); with `args.node_pid` SIGTERM while moving (a zero command).
    Fills `out` (its `checks`, the latencies); returns whether every check passed."""
    ok = True
    latencies = []
    clearance = math.inf
    goal = robot.goal
    if args.arrive:
        robot.send_goal(goal)
        t1 = time.monotonic()
        arrived_at = None
        while time.monotonic() - t1 < args.max_time:
            robot.tick(True, latencies)
            clearance = min(clearance, robot.world.clearance(robot.x))
            d = math.hypot(robot.x[0] - goal[0], robot.x[1] - goal[1])
            if d <= TOLERANCE and robot.cmd == (0.0, 0.0):
                arrived_at = time.monotonic() - t1
                break
        d = math.hypot(robot.x[0] - goal[0], robot.x[1] - goal[1])
        out["checks"]["arrived"] = arrived_at is not None
        out["arrival_s"] = arrived_at and round(arrived_at, 2)
        out["final_distance"] = round(d, 4)
        out["min_clearance"] = round(clearance, 4)
        out["checks"]["no_contact"] = clearance > RADIUS
        ok = ok and arrived_at is not None and clearance > RADIUS

    # Stale scans: a new goal 4 m away (the robot is still on its way when the timeout
    # expires, so a zero can only come from the stale-scan stop), moving, then scans stop.
    start, far = worlds(args.world)[1:]
    back = start if args.arrive else far
    robot.send_goal(back)
    moving = False
    for _ in range(40):
        robot.tick(True, latencies)
        clearance = min(clearance, robot.world.clearance(robot.x))
        if math.hypot(*robot.cmd) > 1e-3:
            moving = True
            break
    out["checks"]["moving_before_stale"] = moving
    stopped_after = None
    t2 = time.monotonic()
    while time.monotonic() - t2 < 3.0:
        robot.tick(False, latencies)
        if robot.cmd == (0.0, 0.0) and robot.last_cmd_at and robot.last_cmd_at > t2:
            stopped_after = time.monotonic() - t2
            break
    out["stale_stop_after_s"] = stopped_after and round(stopped_after, 3)
    # Within the timeout, plus one period each for the node's check, the peer's and the wire.
    stop_ok = stopped_after is not None and stopped_after <= args.scan_timeout + 3 * H + 0.05
    out["checks"]["stale_stop"] = stop_ok
    ok = ok and moving and stop_ok

    if args.node_pid:
        # Moving again, then SIGTERM: the last command received must be zero.
        for _ in range(40):
            robot.tick(True, latencies)
            if math.hypot(*robot.cmd) > 1e-3:
                break
        was_moving = math.hypot(*robot.cmd) > 1e-3
        os.kill(args.node_pid, signal.SIGTERM)
        end = time.monotonic() + 2.0
        while time.monotonic() < end:
            robot.take_cmds()
            time.sleep(0.01)
        zero = robot.cmd == (0.0, 0.0)
        out["checks"]["moving_before_sigterm"] = was_moving
        out["checks"]["zero_after_sigterm"] = zero
        ok = ok and was_moving and zero

    if latencies:
        latencies.sort()
        out["scan_to_cmd_ms"] = {
            "n": len(latencies),
            "median": round(1e3 * latencies[len(latencies) // 2], 2),
            "p95": round(1e3 * latencies[int(0.95 * (len(latencies) - 1))], 2),
            "max": round(1e3 * latencies[-1], 2),
        }
    if robot.diff:
        out["checks"]["no_sideways"] = not robot.sideways
        ok = ok and not robot.sideways
    return ok

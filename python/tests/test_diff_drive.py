"""Differential-drive robots in Python (issue 53, item 3): `base="diff"` with `v_max` and
`omega_max`, `command_pose(position, yaw)` returning `(v, omega)`, on either world. The robot is
integrated exactly (the unicycle under a zero-order hold is a circular arc), its disc checked
along every arc, and the bounds at every command."""

import copy
import math
import pickle

import numpy as np
import pytest

import harmonav

RADIUS, MARGIN, H = 0.18, 0.05, 0.1
V_MAX, OMEGA_MAX = 0.5, 2.0
BOUNDARY = harmonav.circle([0.0, 0.0], 4.0)
OBSTACLES = [harmonav.circle([0.0, 0.0], 0.8), harmonav.circle([1.6, 1.4], 0.5),
             harmonav.ellipse([-1.4, -1.6], [0.6, 0.3], angle_deg=20.0)]
START, GOAL = np.array([-2.8, 0.2]), np.array([2.8, -0.3])
# The L room of crates/harmonav/tests/diff_drive.rs; the start at the end of its other arm.
L_ROOM = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 1.5], [1.5, 1.5], [1.5, 4.0], [0.0, 4.0]])
L_START, L_GOAL = np.array([0.75, 3.5]), [3.5, 0.75]
# A longer L room (tests/test_floor_navigator.py's), where the default heading policy escapes.
L_OUTER = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [2.0, 2.0], [2.0, 6.0], [0.0, 6.0]])


def diff_star(**kwargs):
    options = dict(law="kinematic", radius=RADIUS, margin=MARGIN, control_period=H,
                   base="diff", v_max=V_MAX, omega_max=OMEGA_MAX)
    options.update(kwargs)
    nav = harmonav.Navigator(BOUNDARY, GOAL, **options)
    for shape in OBSTACLES:
        nav.add_obstacle(shape)
    return nav


def diff_floor(**kwargs):
    options = dict(radius=0.1, margin=0.1, control_period=H, base="diff", v_max=V_MAX,
                   omega_max=OMEGA_MAX, max_element=0.1)
    options.update(kwargs)
    return harmonav.FloorNavigator(L_ROOM, L_GOAL, **options)


def arc(x, yaw, v, omega, t):
    """The pose after holding (v, omega) for t from (x, yaw): the exact arc."""
    turn = omega * t
    half = 0.5 * turn
    sinc = 1.0 - half * half / 6.0 if abs(half) < 1e-4 else math.sin(half) / half
    mid = yaw + half
    return x + v * t * sinc * np.array([math.cos(mid), math.sin(mid)]), yaw + turn


def clearance(p):
    """The distance from p to the true obstacles and the boundary (the robot's disc clear of
    them iff it is at least RADIUS)."""
    d = min(float(s.signed_distance(p)) for s in OBSTACLES)
    return min(d, -float(BOUNDARY.signed_distance(p)))


def drive(nav, x, yaw, steps, check, tolerance=0.05):
    """Integrates the unicycle exactly under nav.command_pose; `check(p)` at 8 points of every
    arc. Returns the final pose, the commands and the steps taken."""
    commands = []
    for _ in range(steps):
        v, omega = nav.command_pose(x, yaw)
        commands.append((v, omega))
        assert 0.0 <= v <= V_MAX and abs(omega) <= OMEGA_MAX, (v, omega)
        for t in np.linspace(H / 8, H, 8):
            check(arc(x, yaw, v, omega, t)[0])
        x, yaw = arc(x, yaw, v, omega, H)
        if np.linalg.norm(x - nav.goal) < tolerance:
            break
    return x, yaw, commands


@pytest.mark.parametrize("yaw", [0.0, math.pi, math.pi / 2, -2.5, 0.3],
                         ids=["towards", "away", "wall", "back-left", "slight"])
def test_a_diff_robot_reaches_the_goal_within_its_bounds_clear_of_every_obstacle(yaw):
    nav = diff_star()
    assert nav.base == "diff" and nav.omega_max == OMEGA_MAX and nav.steer is None

    def clear(p):
        assert clearance(p) >= RADIUS - 1e-9, p

    x, _, commands = drive(nav, START.copy(), yaw, 1500, clear)
    assert np.linalg.norm(x - GOAL) < 0.05, x
    assert nav.steer in ("ahead", "shortened", "turning", "stopped")
    assert nav.certified
    # It turned in place when facing away (v = 0, omega at its bound at the start).
    if yaw == math.pi:
        assert commands[0][0] == 0.0 and abs(commands[0][1]) == OMEGA_MAX


@pytest.mark.parametrize("k", range(0, 8, 3))
def test_a_diff_robot_on_a_floor_plan_turns_the_corner(k):
    nav = diff_floor()
    assert nav.base == "diff"

    def clear(p):
        assert nav.wall_distance(p) >= 0.1 - 1e-9, p

    x, _, _ = drive(nav, L_START.copy(), -math.pi + math.pi / 4 * k, 1500, clear, 0.01)
    assert np.linalg.norm(x - nav.goal) < 0.01, x


def test_a_diff_robot_escapes_a_rest_point_of_a_floor_plan():
    nav = harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], radius=0.1, margin=0.1, control_period=H,
                                  base="diff", v_max=V_MAX, omega_max=OMEGA_MAX,
                                  max_element=0.1)
    x, _, _ = drive(nav, np.array([1.0, 5.4]), 0.0, 2000, lambda p: None)
    assert np.linalg.norm(x - nav.goal) < 0.05, (x, nav.mode, nav.steer)


def test_the_holonomic_base_is_the_default_and_unchanged():
    plain = harmonav.Navigator(BOUNDARY, GOAL, radius=RADIUS, margin=MARGIN)
    named = harmonav.Navigator(BOUNDARY, GOAL, radius=RADIUS, margin=MARGIN, base="holonomic")
    assert plain.base == named.base == "holonomic" and plain.omega_max is None
    for nav in (plain, named):
        nav.add_obstacle(OBSTACLES[0])
    x = START.copy()
    for _ in range(50):
        a, b = plain.command(x), named.command(x)
        np.testing.assert_array_equal(a, b)
        x = x + plain.control_period * a
    with pytest.raises(ValueError, match="`base`.*holonomic"):
        plain.command_pose(x, 0.0)


def test_v_max_keeps_its_meaning_and_bounds_the_base():
    """With base="diff", v_max is the kinematic law's top speed and the base's forward bound."""
    nav = diff_star(v_max=0.2)
    x, yaw = START.copy(), 0.0
    top = 0.0
    for _ in range(60):
        v, omega = nav.command_pose(x, yaw)
        assert v <= 0.2
        top = max(top, v)
        x, yaw = arc(x, yaw, v, omega, H)
    assert top == pytest.approx(0.2)
    # The holonomic command of the same navigator is capped at v_max too.
    assert np.linalg.norm(nav.command(x)) <= 0.2 + 1e-12


def constructors():
    yield "star", lambda **o: harmonav.Navigator(BOUNDARY, GOAL, **o)
    yield "floor", lambda **o: harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], max_element=0.2,
                                                       **o)


BAD = [
    (dict(base="tank", v_max=0.5, omega_max=2.0), "unknown base \"tank\""),
    (dict(base=None), "base"),
    (dict(base="diff", v_max=0.5), "`omega_max` is required"),
    (dict(base="diff", omega_max=2.0), "`v_max` is required"),
    (dict(base="diff", v_max=0.5, omega_max=0.0), "`omega_max` must be finite and positive"),
    (dict(base="diff", v_max=0.5, omega_max=-1.0), "`omega_max` must be finite and positive"),
    (dict(base="diff", v_max=0.5, omega_max=float("nan")), "`omega_max`"),
    (dict(base="diff", v_max=0.5, omega_max=float("inf")), "`omega_max`"),
    (dict(base="diff", v_max=0.0, omega_max=2.0), "`v_max`"),
    (dict(base="diff", v_max=-0.5, omega_max=2.0), "`v_max`"),
    (dict(base="diff", v_max=float("inf"), omega_max=2.0), "`v_max`"),
    (dict(base="diff", v_max=float("nan"), omega_max=2.0), "`v_max`"),
    (dict(base="diff", v_max=0.5, omega_max=2e12), "`omega_max`"),
    (dict(omega_max=2.0), "`omega_max`.*base=\"diff\""),
    (dict(base="diff", v_max=0.5, omega_max=2.0, law="dynamic"), "`base`"),
    (dict(base="diff", v_max=0.5, omega_max=2.0, a_max=1.0), "`alpha_max` is required"),
    (dict(base="diff", v_max=0.5, omega_max=2.0, alpha_max=1.0), "`a_max` is required"),
    (dict(base="diff", v_max=0.5, omega_max=2.0, a_max=-1.0, alpha_max=1.0),
     "`a_max` must be finite and positive"),
    (dict(base="diff", v_max=0.5, omega_max=2.0, a_max=1.0, alpha_max=float("nan")),
     "`alpha_max`"),
    (dict(a_max=1.0, alpha_max=1.0), "`a_max`.*base=\"diff\""),
]


@pytest.mark.parametrize("options,words", BAD, ids=lambda p: str(p))
def test_a_bad_base_or_bound_is_a_value_error_naming_it_in_either_world(options, words):
    for name, make in constructors():
        error = TypeError if options.get("base", "") is None else ValueError
        with pytest.raises(error, match=words):
            make(**options)


@pytest.mark.parametrize("make", [diff_star, diff_floor], ids=["star", "floor"])
def test_command_pose_refuses_a_bad_pose_and_changes_nothing(make):
    nav = make()
    x = L_START.copy() if hasattr(nav, "delta") else START.copy()
    before = repr(nav.__reduce__()[2])
    with pytest.raises(ValueError, match="yaw"):
        nav.command_pose(x, float("nan"))
    with pytest.raises(ValueError, match="position"):
        nav.command_pose([float("inf"), 0.0], 0.0)
    with pytest.raises(TypeError):
        nav.command_pose(x, "north")
    assert nav.steer is None and repr(nav.__reduce__()[2]) == before
    nav.command_pose(x, 0.0)
    state = nav.__reduce__()[2]
    assert state[-1][0] == "pose" and list(state[-1][1]) == list(x) and state[-1][2] == 0.0


def copies(nav):
    yield "copy", copy.copy(nav)
    yield "deepcopy", copy.deepcopy(nav)
    for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
        yield f"pickle {protocol}", pickle.loads(pickle.dumps(nav, protocol=protocol))


def limited_star():
    return diff_star(a_max=0.5, alpha_max=4.0)


@pytest.mark.parametrize("make", [diff_star, diff_floor, limited_star],
                         ids=["star", "floor", "accel"])
def test_a_restored_diff_navigator_commands_bit_for_bit_as_the_original(make):
    nav = make()
    floor = hasattr(nav, "delta")
    x, yaw = (L_START.copy(), -1.0) if floor else (START.copy(), 2.0)
    for _ in range(30):
        v, omega = nav.command_pose(x, yaw)
        x, yaw = arc(x, yaw, v, omega, H)
    _, _, state = nav.__reduce__()
    # The last pose command is kept (it replaces the ones before it); under acceleration
    # limits every one, each counting from the last.
    assert state[-1] == ("pose", list(state[-1][1]), state[-1][2]) and state[-1][0] == "pose"
    assert [e[0] for e in state].count("pose") == (30 if nav.accel else 1)
    twins = list(copies(nav))

    def run(n, x, yaw):
        out = []
        for _ in range(40):
            v, omega = n.command_pose(x, yaw)
            out.append((v, omega, n.mode, n.steer))
            x, yaw = arc(x, yaw, v, omega, H)
        return out

    want = run(nav, x, yaw)
    assert any(v > 0 for v, *_ in want)
    for how, twin in twins:
        assert twin.base == "diff" and twin.omega_max == OMEGA_MAX, how
        # Bit for bit: floats compared with ==, and their signs.
        got = run(twin, x, yaw)
        assert got == want, how
        assert [math.copysign(1, g[1]) for g in got] == [math.copysign(1, w[1]) for w in want]


def test_a_pickle_of_a_diff_navigator_rebuilds_it_with_its_base():
    nav = diff_star()
    cls, args, state = nav.__reduce__()
    rebuilt = cls(*args)
    assert rebuilt.base == "diff" and rebuilt.omega_max == OMEGA_MAX
    partial, _, _ = diff_floor().__reduce__()
    assert partial.keywords["base"] == "diff" and partial.keywords["omega_max"] == OMEGA_MAX
    # A state entry that does not parse is refused, naming the class and entry.
    with pytest.raises(TypeError, match="entry 0"):
        rebuilt.__setstate__([("pose", [0.0, 0.0])])


def test_acceleration_limits_bound_every_change_and_the_robot_arrives_clear():
    """`a_max` and `alpha_max`: from rest, consecutive commands differ by at most `a_max·h` and
    `alpha_max·h`, every arc keeps the margin, and the robot arrives (docs/unicycle.md §10)."""
    nav = limited_star()
    assert nav.accel == (0.5, 4.0) and diff_star().accel is None
    def clear(p):
        assert clearance(p) >= RADIUS + MARGIN - 1e-9, p

    x, yaw, commands = drive(nav, START.copy(), 0.0, 3000, clear)
    assert np.linalg.norm(x - GOAL) < 0.05
    last = (0.0, 0.0)
    for v, omega in commands:
        assert abs(v - last[0]) <= 0.5 * H * (1 + 1e-12), (v, last)
        assert abs(omega - last[1]) <= 4.0 * H * (1 + 1e-12), (omega, last)
        last = (v, omega)


def heading_error(goal_yaw, yaw):
    return math.atan2(math.sin(goal_yaw - yaw), math.cos(goal_yaw - yaw))


@pytest.mark.parametrize("make", [diff_star, limited_star], ids=["star", "accel"])
def test_a_goal_heading_is_reached_by_turning_in_place_at_the_goal(make):
    """`set_goal_heading`: at the goal (within 1 cm) the robot turns in place to the goal yaw,
    then stands (`"arrived"`); copies and pickles keep the yaw; a bad yaw is refused by name.
    The negative control: the same loop without it ends facing elsewhere (docs/unicycle.md
    section 3.5)."""
    goal_yaw = math.pi / 2
    nav = make()
    assert nav.goal_heading is None
    nav.set_goal_heading(goal_yaw)
    assert nav.goal_heading == goal_yaw
    x, yaw, turning = START.copy(), math.pi, 0
    # Under acceleration limits the base brakes from the first pose within 1 cm and may roll
    # out (the radius latches, `goal_latched`): at most v²/(2 a_max) from there.
    entry, rolled, last = None, 0.0, 0.0
    for _ in range(1500):
        v, omega = nav.command_pose(x, yaw)
        assert 0.0 <= v <= V_MAX and abs(omega) <= OMEGA_MAX, (v, omega)
        if entry is None and np.linalg.norm(x - GOAL) < 0.01:
            entry = last
        assert nav.goal_latched == (entry is not None)
        if entry is not None:
            rolled += v * H
        if nav.steer == "to-goal-heading":
            turning += 1
            assert v == 0.0 and entry is not None, (v, x)
        last = v
        for t in np.linspace(H / 8, H, 8):
            assert clearance(arc(x, yaw, v, omega, t)[0]) > RADIUS
        x, yaw = arc(x, yaw, v, omega, H)
        if nav.steer == "arrived":
            break
    assert nav.steer == "arrived" and turning > 0
    assert abs(heading_error(goal_yaw, yaw)) < 1e-3
    assert rolled <= (entry**2 / (2 * 0.5) if make is limited_star else 0.0) * (1 + 1e-9)
    assert np.linalg.norm(x - GOAL) < 0.01 + rolled
    for how, twin in copies(nav):
        assert twin.goal_heading == goal_yaw, how
        assert twin.command_pose(x, yaw) == (0.0, 0.0) and twin.steer == "arrived", how
    for bad in [float("nan"), float("inf")]:
        with pytest.raises(ValueError, match="goal_yaw"):
            nav.set_goal_heading(bad)
        assert nav.goal_heading == goal_yaw
    nav.set_goal_heading(None)
    assert nav.goal_heading is None

    # Without a goal yaw the robot arrives facing wherever it approached from.
    free = make()
    x, yaw, _ = drive(free, START.copy(), math.pi, 1500, lambda p: None, tolerance=0.01)
    assert np.linalg.norm(x - GOAL) < 0.01
    assert abs(heading_error(goal_yaw, yaw)) > 1e-3


@pytest.mark.parametrize("make", [diff_star, limited_star], ids=["star", "accel"])
def test_a_goal_tolerance_ends_the_turn_where_it_says(make):
    """`set_goal_tolerance(xy, yaw)` (Nav2's `xy_goal_tolerance`, `yaw_goal_tolerance`): the
    turn in place begins at the first pose within `xy` of the goal and the robot stands within
    `xy` and `yaw`; copies and pickles keep it; a bad bound is refused by name. The negative
    control: the default tolerance (0.01 m) drives on past the first pose within 0.3 m."""
    goal_yaw, xy, tol = math.pi / 2, 0.3, 0.05
    nav = make()
    assert nav.goal_tolerance == (0.01, 1e-3)
    nav.set_goal_heading(goal_yaw)
    nav.set_goal_tolerance(xy=xy, yaw=tol)
    assert nav.goal_tolerance == (xy, tol)
    # A bound not given keeps its value.
    nav.set_goal_tolerance(xy=0.5)
    assert nav.goal_tolerance == (0.5, tol)
    nav.set_goal_tolerance(xy=xy)
    assert nav.goal_tolerance == (xy, tol)
    limited = make is limited_star
    x, yaw, within, last = START.copy(), math.pi, None, 0.0
    for _ in range(1500):
        v, omega = nav.command_pose(x, yaw)
        if within is None and np.linalg.norm(x - GOAL) < xy:
            within = x.copy()
        if within is not None:
            # It stops at once, or brakes as fast as the limits allow (then stands).
            assert v == 0.0 or (limited and v < last), (v, last, x)
        last = v
        x, yaw = arc(x, yaw, v, omega, H)
        if nav.steer == "arrived":
            break
    assert nav.steer == "arrived" and within is not None
    if not limited:
        assert np.array_equal(x, within), (x, within)
    assert 0.01 < np.linalg.norm(x - GOAL) < xy
    assert abs(heading_error(goal_yaw, yaw)) < tol
    for how, twin in copies(nav):
        assert twin.goal_tolerance == (xy, tol), how
        assert twin.command_pose(x, yaw) == (0.0, 0.0) and twin.steer == "arrived", how
    for kw, name in [({"xy": 0.0}, "xy_goal_tolerance"), ({"yaw": float("nan")}, "yaw_goal_tolerance")]:
        with pytest.raises(ValueError, match=name):
            nav.set_goal_tolerance(**kw)
        assert nav.goal_tolerance == (xy, tol)

    # The default drives on: it is still moving at the first pose within 0.3 m.
    free = make()
    free.set_goal_heading(goal_yaw)
    x, yaw = START.copy(), math.pi
    for _ in range(1500):
        v, omega = free.command_pose(x, yaw)
        if np.linalg.norm(x - GOAL) < xy:
            break
        x, yaw = arc(x, yaw, v, omega, H)
    assert v > 0.0, v


@pytest.mark.parametrize("make", [diff_star, diff_floor, limited_star],
                         ids=["star", "floor", "accel"])
def test_the_goal_radius_latches_and_copies_keep_the_latch(make):
    """`set_goal_tolerance(stateful=…)` (Nav2's goal checker's `stateful`, default True): once
    `command_pose` has had a pose within `xy` of the goal, the robot only turns in place there,
    wherever the pose is (`goal_latched`); copies and pickles keep the latch, although the
    latching command is followed by others (without acceleration limits the log keeps only
    the last command unless told). The negative control: unlatched (`stateful=False`) the same
    far pose drives. A different tolerance releases the latch."""
    nav = make()
    assert nav.goal_stateful is True and nav.goal_latched is False
    nav.set_goal_heading(math.pi / 2)
    nav.set_goal_tolerance(xy=0.1, yaw=0.05)
    goal = np.asarray(L_GOAL if make is diff_floor else GOAL)
    near, far = goal + np.array([0.05, 0.0]), goal + np.array([-1.0, 0.2])
    nav.command_pose(far, 0.0)
    assert not nav.goal_latched
    nav.command_pose(near, 0.0)
    assert nav.goal_latched and nav.steer == "to-goal-heading"
    for _ in range(3):
        v, _ = nav.command_pose(far, 0.0)
        assert v == 0.0 and nav.steer == "to-goal-heading"
    for how, twin in copies(nav):
        assert twin.goal_latched and twin.goal_stateful, how
        assert twin.command_pose(far, 0.0) == nav.command_pose(far, 0.0), how
        assert twin.steer == "to-goal-heading", how
    state = nav.__reduce__()[2]
    assert ("goal-tolerance", 0.1, 0.05, True) in [tuple(e) for e in state]

    off = make()
    off.set_goal_heading(math.pi / 2)
    off.set_goal_tolerance(xy=0.1, yaw=0.05, stateful=False)
    assert off.goal_stateful is False and off.goal_tolerance == (0.1, 0.05)
    off.command_pose(near, 0.0)
    assert not off.goal_latched
    for _ in range(3):
        off.command_pose(far, 0.0)
    assert off.steer not in ("to-goal-heading", "arrived"), off.steer
    for how, twin in copies(off):
        assert twin.goal_stateful is False, how

    nav.set_goal_tolerance(yaw=0.06)
    assert not nav.goal_latched and nav.goal_stateful


@pytest.mark.parametrize("release", ["tolerance", "heading", "stateful"])
def test_a_setter_that_released_the_latch_releases_it_in_copies(release):
    """After a latching command, a setter call with another value releases the latch even if
    the next call sets the first value back (the same value alone keeps it): a copy must
    replay both calls, not one merged entry, and so be unlatched and command as the original
    does at a far pose (it drives; a latched copy would turn in place)."""
    nav = diff_star()
    nav.set_goal_heading(math.pi / 2)
    nav.set_goal_tolerance(xy=0.1, yaw=0.05)
    near, far = np.asarray(GOAL) + np.array([0.05, 0.0]), np.asarray(GOAL) + np.array([-1.0, 0.2])
    nav.command_pose(near, 0.0)
    assert nav.goal_latched
    if release == "tolerance":
        nav.set_goal_tolerance(xy=0.3)
        nav.set_goal_tolerance(xy=0.1)
    elif release == "heading":
        nav.set_goal_heading(None)
        nav.set_goal_heading(math.pi / 2)
    else:
        nav.set_goal_tolerance(stateful=False)
        nav.set_goal_tolerance(stateful=True)
    assert not nav.goal_latched
    for how, twin in copies(nav):
        assert not twin.goal_latched, how
        assert twin.command_pose(far, 0.0) == nav.command_pose(far, 0.0), how
        assert nav.steer not in ("to-goal-heading", "arrived"), how


def test_a_goal_tolerance_entry_without_stateful_is_unlatched():
    """A state pickled before `stateful` (`("goal-tolerance", xy, yaw)`, when the radius did
    not latch) restores unlatched, as it ran; a `stateful` that is not a bool is refused,
    naming the entry."""
    nav = diff_star()
    nav.set_goal_heading(1.0)
    nav.set_goal_tolerance(xy=0.2, yaw=0.1, stateful=True)
    cls, args, state = nav.__reduce__()
    old = [e[:3] if e[0] == "goal-tolerance" else e for e in state]
    rebuilt = cls(*args)
    rebuilt.__setstate__(old)
    assert rebuilt.goal_tolerance == (0.2, 0.1) and rebuilt.goal_stateful is False
    bad = [("goal-tolerance", 0.2, 0.1, "yes") if e[0] == "goal-tolerance" else e for e in state]
    with pytest.raises(TypeError, match="entry"):
        cls(*args).__setstate__(bad)

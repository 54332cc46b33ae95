"""Navigator: the README's loop arrives, bad input is refused and leaves the state unchanged."""

import math

import numpy as np
import pytest

import harmonav

TRUTH = [([-1.5, 0.4], 0.5), ([0.6, -0.5], 0.6), ([2.0, 1.2], 0.4)]


def loop(law, hz, radius=0.1):
    """A robot loop with its own integrator and perception (discs within 1 m), as
    examples/own_loop.rs; returns (time, closest clearance, discoveries)."""
    boundary = harmonav.circle([0.0, 0.0], 4.0)
    goal = np.array([3.0, 0.0])
    nav = harmonav.Navigator(
        boundary, goal, law=law, gain=1.0, mass=1.0, mu=10.0, sensor=(1.0, 60.0), radius=radius, margin=0.05
    )
    world = [harmonav.circle(c, r) for c, r in TRUTH]
    seen = [False] * len(world)
    x, v, h, t = np.array([-3.2, -0.3]), np.zeros(2), 1.0 / hz, 0.0
    closest = np.inf
    while np.linalg.norm(x - goal) > 0.01:
        for i, o in enumerate(world):
            if not seen[i] and o.signed_distance(x) < 1.0:
                assert nav.add_obstacle(o) == sum(seen)
                seen[i] = True
        cmd = nav.command(x, v)
        assert cmd.shape == (2,)
        if law == "kinematic":
            x = x + h * cmd
        else:
            v = v + h * cmd  # semi-implicit Euler, m = 1 kg
            x = x + h * v
            assert np.linalg.norm(v) < nav.speed_bound
        t += h
        closest = min(closest, min(o.signed_distance(x) for o in world) - radius)
        assert t < 120.0, f"no arrival: x = {x}"
    return t, closest, sum(seen)


def test_kinematic_loop_at_100_hz_arrives_without_collision():
    t, closest, found = loop("kinematic", 100.0)
    assert closest > 0.0 and found >= 1
    assert t < 30.0


def test_dynamic_loop_at_1_khz_arrives_below_the_speed_bound():
    t, closest, found = loop("dynamic", 1000.0)
    assert closest > 0.0 and found >= 1


def test_an_obstacle_against_the_wall_joins_it_unless_the_goal_is_behind_it():
    # Reaching the boundary, the shape joins it (docs/maths/12-range-scans.md §12.21).
    room = harmonav.circle([0, 0], 4.0)
    nav = harmonav.Navigator(room, [3.0, 0.0], radius=0.0, margin=0.0)
    assert nav.add_obstacle(harmonav.circle([3.9, 2.0], 0.5)) == 0
    assert nav.obstacle_count == 1
    # A goal behind the shape, as seen from the room's centre: the join is refused, and
    # nothing changes.
    behind = 3.97 * np.array([np.cos(0.125), np.sin(0.125)])
    nav = harmonav.Navigator(room, behind, radius=0.0, margin=0.0)
    x = np.array([-2.0, 0.3])
    before = nav.command(x)
    with pytest.raises(ValueError, match="boundary"):
        nav.add_obstacle(harmonav.circle([3.8, 0.0], 0.5))
    assert nav.obstacle_count == 0
    np.testing.assert_array_equal(nav.command(x), before)


def test_a_refused_obstacle_changes_nothing():
    nav = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0])
    nav.add_obstacle(harmonav.circle([0.0, 0.0], 1.0))
    x = np.array([-2.0, 0.3])
    before = nav.command(x)
    k = nav.k
    for bad, word in [
        (harmonav.circle([0.5, 0.0], 1.0), "overlap"),
        (harmonav.circle([3.0, 0.0], 0.5), "goal"),
        (harmonav.circle([-2.0, 0.3], 0.5), "robot"),
    ]:
        with pytest.raises(ValueError, match=word):
            nav.add_obstacle(bad)
    assert nav.k == k and nav.obstacle_count == 1
    np.testing.assert_array_equal(nav.command(x), before)


def test_bad_states_raise_and_nan_does_not_crash():
    nav = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], law="dynamic")
    nav.add_obstacle(harmonav.circle([0.0, 0.0], 1.0))
    with pytest.raises(ValueError, match="finite"):
        nav.command([np.nan, 0.0])
    with pytest.raises(ValueError, match="finite"):
        nav.command([1.0, 2.0], [np.inf, 0.0])
    with pytest.raises(ValueError, match="inside"):
        nav.command([0.0, 0.5])
    with pytest.raises(ValueError):
        nav.command([10.0, 0.0])
    assert np.all(np.isfinite(nav.command([-2.0, 0.3], [0.1, 0.0])))
    assert 0.0 < nav.theta([-2.0, 0.3]) < 1.0


@pytest.mark.parametrize(
    "kwargs, word",
    [
        (dict(law="pid"), "kinematic"),
        (dict(gain=-1.0), "gain"),
        (dict(law="dynamic", mass=0.0), "mass"),
        (dict(sensor=(1.0, 0.0)), "aperture"),
        (dict(radius=-0.1), "radius"),
        (dict(k="n+1"), "auto"),
        (dict(damping="critical"), "paper"),
        (dict(speed="fast"), "speed policy"),
        (dict(v_max=0.0), "v_max"),
        (dict(v_max=float("nan")), "v_max"),
        (dict(v_max=-1.0), "v_max"),
        (dict(v_max=float("inf")), "v_max"),
        (dict(speed="Auto"), "speed policy"),
        # Arguments the law does not use are checked too: a NaN left in one would only
        # surface when the law is switched.
        (dict(mass=float("nan")), "`mass`"),
        (dict(mu=-1.0), "`mu`"),
        (dict(law="dynamic", gain=float("inf")), "`gain`"),
        (dict(free_memory=-1), "`free_memory`: must be an integer from 0 to 256"),
        (dict(law="pid", gain=float("nan")), "unknown law"),  # the law's name first
    ],
)
def test_bad_options_are_refused(kwargs, word):
    with pytest.raises(ValueError, match=word):
        harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], **kwargs)


# Options that the constructor accepted and that made the dynamic `command` return
# [-inf, nan] (issue 23), and their neighbours at the other end of the ranges.
EXTREME = [
    dict(law="dynamic", rho_min=5e-324),
    dict(law="dynamic", sensor=(1.0, 1e-320)),
    dict(law="dynamic", mass=1e308, mu=1e308),
    dict(law="dynamic", mass=5e-324),
    dict(law="dynamic", mu=1e308),
    dict(law="dynamic", mu=5e-324),
    dict(law="dynamic", sensor=(1e308, 360.0)),
    dict(law="kinematic", gain=1e308),
    dict(law="kinematic", gain=5e-324),
    dict(law="kinematic", rho_min=5e-324),
]


@pytest.mark.parametrize("kwargs", EXTREME, ids=lambda kw: ",".join(f"{k}={v}" for k, v in kw.items()))
def test_extreme_options_give_finite_commands_or_value_errors(kwargs):
    """Never a NaN or an infinity handed back: either the constructor or `command` raises
    `ValueError` naming the problem, or every command, Θ and the speed bound are finite."""
    try:
        nav = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], **kwargs)
        nav.add_obstacle(harmonav.circle([0.0, 0.0], 1.0))
    except ValueError as e:
        assert any(name in str(e) for name in kwargs), str(e)
        return
    if nav.speed_bound is not None:
        assert np.isfinite(nav.speed_bound)
    rng = np.random.default_rng(11)
    for _ in range(50):
        x = rng.uniform(-3.5, 3.5, size=2)
        v = rng.uniform(-1.0, 1.0, size=2)
        if harmonav.circle([0.0, 0.0], 1.05).contains(x) or np.linalg.norm(x) > 3.9:
            continue
        try:
            cmd = nav.command(x, v)
        except ValueError as e:
            assert "finite" in str(e), str(e)
            with pytest.raises(ValueError):
                nav.command(x, v)  # refused again: the refusal changed nothing
            continue
        assert cmd.shape == (2,) and np.all(np.isfinite(cmd)), (x, v, cmd)
        assert np.isfinite(nav.theta(x))


def test_a_velocity_whose_norm_overflows_is_refused_and_changes_nothing():
    """Finite components of 1.5e308 made the speed at the next discovery overflow, and the
    command after it [-inf, nan] (issue 23): the navigator refuses the state, and the refusal
    leaves the last position as it was: an obstacle over the refused position, but clear of
    the last accepted one, is still accepted."""
    nav = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], law="dynamic")
    nav.command([-2.0, 0.3], [0.5, 0.0])
    # Named as out of range (issue 56, D19.2: the velocity is finite, its energy overflows).
    for huge in ([1.5e308, 1.5e308], [1e200, 0.0]):
        with pytest.raises(ValueError, match="velocity.*1e154"):
            nav.command([-1.3, 0.3], huge)
    nav.add_obstacle(harmonav.circle([-1.35, 0.35], 0.3))
    assert nav.obstacle_count == 1
    assert np.all(np.isfinite(nav.command([-2.0, 0.3], [0.5, 0.0])))


@pytest.mark.parametrize("law,hz", [("kinematic", 20), ("kinematic", 100), ("dynamic", 250)])
def test_every_command_is_safe_to_hold_for_the_control_period(law, hz):
    """The README's loop at the rate it states with `control_period`: no true shape touched, no
    grown shape entered (margin 0.05), every command finite, and the goal reached; `mode` tells
    the shortened commands apart."""
    boundary = harmonav.circle([0.0, 0.0], 4.0)
    goal = np.array([3.0, 0.0])
    h = 1.0 / hz
    nav = harmonav.Navigator(boundary, goal, law=law, radius=0.1, margin=0.05, control_period=h)
    assert nav.control_period == h
    world = [harmonav.circle(c, r) for c, r in TRUTH]
    seen = [False] * len(world)
    x, v, t, modes = np.array([-3.2, -0.3]), np.zeros(2), 0.0, set()
    while np.linalg.norm(x - goal) > 0.01:
        for i, o in enumerate(world):
            if not seen[i] and o.signed_distance(x) < 1.0:
                nav.add_obstacle(o)
                seen[i] = True
        cmd = nav.command(x, v)
        modes.add(nav.mode)
        assert np.all(np.isfinite(cmd))
        if law == "kinematic":
            x = x + h * cmd
        else:
            v = v + h * cmd
            x = x + h * v
        t += h
        gap = min(o.signed_distance(x) for o in world) - 0.1
        assert gap > 0.05 - 1e-9, f"t = {t:.2f}: clearance {gap} below the margin"
        assert t < 120.0, f"no arrival: x = {x}"
    assert modes <= {"law", "capped"}, modes


def test_a_robot_in_the_margin_band_is_led_back_out():
    """An obstacle perceived late, whose margin band holds the robot, is accepted, and the
    commands lead out (`mode == "recovering"`) without touching it."""
    rock = harmonav.circle([0.0, 0.0], 1.0)
    nav = harmonav.Navigator(harmonav.circle([0, 0], 5.0), [3.0, 0.0], radius=0.1, margin=0.2)
    x = np.array([-1.2, 0.05])
    nav.command(x)
    nav.add_obstacle(rock)
    modes = []
    for _ in range(50):
        x = x + nav.control_period * nav.command(x)
        modes.append(nav.mode)
        assert rock.signed_distance(x) > 0.1
    assert modes[0] == "recovering" and modes[-1] != "recovering", modes
    assert nav.clearance(x) > 0.0


@pytest.mark.parametrize(
    "kwargs,word", [(dict(control_period=0.0), "control_period"), (dict(hold="exact"), "hold")]
)
def test_bad_hold_options_are_refused(kwargs, word):
    with pytest.raises(ValueError, match=word):
        harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], **kwargs)


def test_the_speed_policy_keeps_the_direction_and_auto_stops_at_the_goal():
    """`speed="auto"` (the default) and `speed="paper"` command the same direction; "auto" moves
    at `v_max` far from the goal and its 100 Hz loop stops at the goal in finite time."""
    boundary = harmonav.circle([0, 0], 5.0)
    auto = harmonav.Navigator(boundary, [0.0, 0.0])
    paper = harmonav.Navigator(boundary, [0.0, 0.0], speed="paper")
    x = np.array([3.0, 1.0])
    a, p = auto.command(x), paper.command(x)
    np.testing.assert_allclose(a / np.linalg.norm(a), p / np.linalg.norm(p), atol=1e-12)
    assert abs(np.linalg.norm(a) - math.sqrt(2.0)) < 1e-12
    slow = harmonav.Navigator(boundary, [0.0, 0.0], v_max=0.5)
    assert abs(np.linalg.norm(slow.command(x)) - 0.5) < 1e-12
    for step in range(1000):
        if np.linalg.norm(x) < 1e-9:
            break
        x = x + 0.01 * auto.command(x)
    assert np.linalg.norm(x) < 1e-9 and step * 0.01 < 3.0


def test_the_auto_speed_never_steps_past_the_goal_at_any_period():
    """The hold caps the held step at the distance to the goal (`h|u| ≤ |x − x_d|`): at 20 Hz
    and 5 Hz the loop lands on the goal instead of crossing it and coming back."""
    boundary = harmonav.circle([0, 0], 5.0)
    goal = np.array([1.0, 0.5])
    for h in (0.05, 0.2):
        nav = harmonav.Navigator(boundary, goal, control_period=h)
        x = np.array([-3.0, 1.0])
        for _ in range(int(30 / h)):
            r = np.linalg.norm(x - goal)
            if r < 1e-12:
                break
            u = nav.command(x)
            assert h * np.linalg.norm(u) <= r * (1 + 1e-12)
            x = x + h * u
        assert np.linalg.norm(x - goal) < 1e-9

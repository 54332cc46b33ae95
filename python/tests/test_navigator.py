"""Navigator: the README's loop arrives, bad input is refused and leaves the state unchanged."""

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
        (harmonav.circle([3.9, 2.0], 0.5), "boundary"),
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
    ],
)
def test_bad_options_are_refused(kwargs, word):
    with pytest.raises(ValueError, match=word):
        harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], **kwargs)

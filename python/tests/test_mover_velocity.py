"""`harmonav.Mover(..., velocity=[vx, vy])` (issue 54): a tracked velocity that the certificate
never uses and KeepRight's anticipation does (docs/movers.md §7). It round-trips through the
constructor, a dict, the repr and pickle; a bad one is refused by name; it never changes a
command the filter certifies alone, and it lets the anticipation see a mover crossing ahead that
a mover reported at rest hides."""

import pickle

import numpy as np
import pytest

import harmonav


def test_velocity_is_optional_and_round_trips():
    m = harmonav.Mover([1.0, 2.0], 0.3, 1.2)
    assert m.velocity is None and "velocity" not in repr(m)
    v = harmonav.Mover([1.0, 2.0], 0.3, 1.2, velocity=[0.5, -0.25])
    np.testing.assert_array_equal(v.velocity, [0.5, -0.25])
    assert repr(v).endswith("kind='noncooperative', velocity=[0.5, -0.25])")
    assert v != m
    for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
        twin = pickle.loads(pickle.dumps(v, protocol=protocol))
        assert twin == v
        np.testing.assert_array_equal(twin.velocity, [0.5, -0.25])
    nav = harmonav.Navigator(harmonav.circle([0, 0], 6.0), [3.0, 0.0], radius=0.2,
                             control_period=0.05, v_max=1.0)
    nav.set_movers([dict(centre=[1.0, 2.0], radius=0.3, speed_bound=1.2,
                         velocity=(0.5, -0.25)), dict(centre=[-1, -2], radius=0.1,
                                                      speed_bound=0.0, velocity=None)])
    got = nav.movers
    np.testing.assert_array_equal(got[0].velocity, [0.5, -0.25])
    assert got[1].velocity is None


@pytest.mark.parametrize("velocity", [[float("nan"), 0.0], [0.0, float("inf")], [1.0, 2.0, 3.0]])
def test_a_bad_velocity_is_refused_by_name(velocity):
    with pytest.raises(ValueError, match="velocity"):
        harmonav.Mover([0.0, 0.0], 0.1, 1.0, velocity=velocity)
    nav = harmonav.Navigator(harmonav.circle([0, 0], 6.0), [3.0, 0.0], radius=0.2)
    with pytest.raises(ValueError, match=r"movers\[1\]\.velocity"):
        nav.set_movers([harmonav.Mover([2.0, 2.0], 0.1, 1.0),
                        dict(centre=[-2.0, 2.0], radius=0.1, speed_bound=1.0,
                             velocity=velocity)])
    assert nav.movers == []


def test_velocity_only_turns_the_nominal():
    """A mover 1.5 m ahead and 1 m to the left, crossing the robot's path at 0.5 m/s: reported
    at rest it is no collision course (no turn), reported with its velocity it is, 2.5 s ahead
    (KeepRight turns the nominal clockwise); either way the command is certified."""
    def first_command(velocity):
        nav = harmonav.Navigator(harmonav.circle([0, 0], 6.0), [4.0, 0.0], radius=0.2,
                                 margin=0.05, control_period=0.1, v_max=0.5)
        nav.set_movers([harmonav.Mover([0.5, 1.0], 0.2, 0.5, velocity=velocity)])
        u = nav.command([-1.0, 0.0])
        assert nav.certified
        return u
    still, crossing = first_command(None), first_command([0.0, -0.5])
    assert still[1] == pytest.approx(0.0, abs=1e-9)  # straight to the goal
    assert crossing[1] < -0.05  # turned clockwise (to the right)

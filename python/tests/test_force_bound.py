"""A force-bounded dynamic robot in Python (issue 54, docs/movers.md §2): the keyword
`force_bound`, every force within it, the modes `"bounded"` and `"braking"`, `certified`, on
either world's navigator, and a pickle that keeps the bound."""

import math
import pickle

import numpy as np
import pytest

import harmonav

RADIUS, MARGIN, H, F = 0.2, 0.05, 0.02, 1.5
BOUNDARY = harmonav.circle([0.0, 0.0], 6.0)
DISC = harmonav.circle([0.0, 0.3], 0.8)
L_OUTER = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [2.0, 2.0], [2.0, 6.0], [0.0, 6.0]])


def star(**kwargs):
    options = dict(law="dynamic", radius=RADIUS, margin=MARGIN, control_period=H,
                   force_bound=F)
    options.update(kwargs)
    nav = harmonav.Navigator(BOUNDARY, [4.0, 0.0], **options)
    nav.add_obstacle(DISC)
    return nav


def fly(nav, start, goal, periods):
    """The user's loop (`v += h f/m; x += h v`, m = 1): the forces, the modes and whether the
    robot came to rest within 5 cm of the goal."""
    x, v = np.array(start, dtype=float), np.zeros(2)
    forces, modes = [], []
    for _ in range(periods):
        f = np.asarray(nav.command(x, v))
        forces.append(float(np.hypot(*f)))
        modes.append(nav.mode)
        assert nav.certified, (nav.mode, x)
        v = v + H * f
        x = x + H * v
        if math.hypot(*(x - goal)) < 0.05 and math.hypot(*v) < 0.05:
            return forces, modes, True
    return forces, modes, False


def test_every_force_is_within_the_bound_and_the_robot_arrives_around_a_disc():
    nav = star()
    forces, modes, arrived = fly(nav, [-4.0, 0.0], np.array([4.0, 0.0]), 3000)
    assert arrived
    assert max(forces) <= F
    assert "bounded" in modes
    # Without the bound the same flight asks for more than F.
    free, _, _ = fly(star(force_bound=None), [-4.0, 0.0], np.array([4.0, 0.0]), 3000)
    assert max(free) > F


def test_a_pickled_copy_keeps_the_bound_and_commands_as_the_original():
    nav = star()
    twin = pickle.loads(pickle.dumps(nav))
    assert (nav.force_bound, twin.force_bound, star(force_bound=None).force_bound) == (F, F, None)
    x, v = np.array([-4.0, 0.0]), np.zeros(2)
    for _ in range(200):
        f, g = nav.command(x, v), twin.command(x, v)
        np.testing.assert_array_equal(f, g)
        assert nav.mode == twin.mode
        v = v + H * np.asarray(f)
        x = x + H * v


@pytest.mark.parametrize("value", [float("nan"), 0.0, -1.0, float("inf")])
def test_a_bad_bound_is_a_value_error_naming_it(value):
    with pytest.raises(ValueError, match="force_bound"):
        star(force_bound=value)


def test_the_kinematic_law_refuses_a_force_bound():
    with pytest.raises(ValueError, match="force_bound.*dynamic law"):
        harmonav.Navigator(BOUNDARY, [4.0, 0.0], law="kinematic", force_bound=2.0)


def test_a_state_that_cannot_stop_in_time_brakes_uncertified():
    nav = star(force_bound=1.0, control_period=0.01)
    # 2 m/s towards the boundary 0.55 m away (grown by radius + margin): 2 m to stop at 1 m/s².
    f = nav.command([5.2, 0.0], [2.0, 0.0])
    assert nav.mode == "braking" and not nav.certified
    assert math.hypot(*(np.asarray(f) + [1.0, 0.0])) < 1e-12


def test_a_floor_navigator_takes_the_same_bound():
    nav = harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], law="dynamic", radius=0.1, margin=0.1,
                                  control_period=H, force_bound=1.0, max_element=0.1)
    forces, _, arrived = fly(nav, [1.0, 5.4], np.array([5.4, 1.0]), 6000)
    assert arrived
    assert max(forces) <= 1.0

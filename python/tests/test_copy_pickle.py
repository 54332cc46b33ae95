"""`copy.copy`, `copy.deepcopy` and pickle for `Shape` and `Navigator` (issue 23: neither could be
copied). A copy behaves as the original: the same outline and distances for a shape; for a
navigator the same known obstacles, `k`, damping state and last position, so the same commands,
and changing the copy leaves the original as it was."""

import copy
import inspect
import pickle

import numpy as np
import pytest

import harmonav

SHAPES = [
    harmonav.circle([0.5, -1.0], 0.7),
    harmonav.ellipse([-2.0, 1.0], [0.8, 0.3], angle_deg=30.0),
    harmonav.polygon([[0.6, 0.6], [1.6, 0.6], [1.6, 1.6], [0.6, 1.6]], 0.1),
    harmonav.star([2.5, -1.0], 0.5, [(3, 0.1, 0.0), (7, 0.01, -0.02)]),
    harmonav.tabulated([0.0, 2.0], list(0.6 + 0.2 * np.cos(3 * np.linspace(0, 2 * np.pi, 64,
                                                                              endpoint=False)))),
]
PROBES = np.random.default_rng(7).uniform(-3, 3, size=(200, 2))
PROTOCOLS = range(pickle.HIGHEST_PROTOCOL + 1)


def copies(obj):
    """Every way to copy `obj`: copy, deepcopy, and a pickle round trip at every protocol."""
    yield "copy", copy.copy(obj)
    yield "deepcopy", copy.deepcopy(obj)
    for protocol in PROTOCOLS:
        yield f"pickle {protocol}", pickle.loads(pickle.dumps(obj, protocol=protocol))


@pytest.mark.parametrize("shape", SHAPES, ids=repr)
def test_a_copied_shape_is_the_same_shape(shape):
    for how, twin in copies(shape):
        assert isinstance(twin, harmonav.Shape), how
        assert repr(twin) == repr(shape), how
        np.testing.assert_array_equal(twin.outline(300), shape.outline(300), err_msg=how)
        np.testing.assert_array_equal(twin.signed_distance(PROBES), shape.signed_distance(PROBES))
        np.testing.assert_array_equal(twin.center, shape.center)


def test_a_shape_pickles_as_a_call_of_its_constructor():
    """The pickle names the public constructor (`harmonav.star`), so that it does not depend on
    the extension's internals."""
    data = pickle.dumps(SHAPES[3], protocol=0)
    assert b"harmonav" in data and b"star" in data


def test_a_tabulated_star_of_equal_radii_is_a_disc_and_bad_radii_are_refused():
    """`tabulated` (the form of a perceived radial hull): equal radii give the disc (the cells
    are constant), so its distances are the circle's; too few, non-positive or non-finite radii
    raise a ValueError naming `radii`."""
    disc = harmonav.tabulated([0.5, -1.0], [0.7] * 32)
    np.testing.assert_allclose(disc.signed_distance(PROBES), SHAPES[0].signed_distance(PROBES),
                               atol=1e-4)
    for bad in ([0.7] * 7, [0.7] * 31 + [0.0], [0.7] * 31 + [float("nan")]):
        with pytest.raises(ValueError, match="radii"):
            harmonav.tabulated([0.0, 0.0], bad)


def world():
    """A dynamic navigator that has moved and discovered two obstacles: under
    `damping="paper"` its damping depends on the speed at the latest discovery, and its
    refusals on the last position, neither of which is a constructor argument."""
    nav = harmonav.Navigator(
        harmonav.circle([0, 0], 4.0),
        [3.0, 0.0],
        law="dynamic",
        mass=2.0,
        mu=5.0,
        sensor=(1.5, 90.0),
        radius=0.1,
        margin=0.05,
        k="paper",
        damping="paper",
        rho_min=0.1,
    )
    nav.command([-3.2, -0.3], [0.4, 0.1])
    nav.add_obstacle(harmonav.circle([-1.5, 0.4], 0.5))
    nav.command([-2.4, -0.6], [0.6, -0.2])  # the speed at the next discovery
    nav.add_obstacle(harmonav.circle([0.6, -0.5], 0.6))
    x, v = np.array([-1.0, -0.9]), np.array([0.5, 0.05])
    nav.command(x, v)
    return nav, x, v


def test_a_copied_navigator_commands_as_the_original():
    nav, x, v = world()
    # Fast enough that the energy V reaches μ, where the damping uses the discovery speed.
    probes = [(x, [2.1, 0.3]), (x + [0.05, 0.0], [-1.9, 0.8]), (np.array([2.0, 1.0]), [0.0, 2.0])]
    want = [nav.command(*p) for p in probes]
    nav.command(x, v)  # back to the state the copies are taken in
    # A fresh navigator with the same obstacles commands differently (no discovery speed): the
    # comparison below can tell whether the copy carries the state.
    fresh = harmonav.Navigator(
        harmonav.circle([0, 0], 4.0), [3.0, 0.0], law="dynamic", mass=2.0, mu=5.0,
        sensor=(1.5, 90.0), radius=0.1, margin=0.05, k="paper", damping="paper", rho_min=0.1,
    )
    fresh.add_obstacle(harmonav.circle([-1.5, 0.4], 0.5))
    fresh.add_obstacle(harmonav.circle([0.6, -0.5], 0.6))
    assert any(not np.array_equal(fresh.command(*p), w) for p, w in zip(probes, want))
    for how, twin in copies(nav):
        assert isinstance(twin, harmonav.Navigator), how
        assert (twin.k, twin.obstacle_count, twin.speed_bound) == (nav.k, 2, nav.speed_bound), how
        np.testing.assert_array_equal(twin.goal, nav.goal)
        for p, w in zip(probes, want):
            twin.command(x, v)
            np.testing.assert_array_equal(twin.command(*p), w, err_msg=how)
        assert twin.theta(x) == nav.theta(x), how


def test_a_pickle_holds_every_constructor_argument():
    """The arguments `__reduce__` stores bind to the constructor's parameters as they were given
    (one that is dropped or out of order would not)."""
    given = dict(
        law="dynamic", gain=2.5, mass=2.0, mu=5.0, sensor=(1.5, 90.0), radius=0.1,
        margin=0.05, k="paper", damping="paper", rho_min=0.1, control_period=0.02, hold="paper",
        speed="paper", v_max=0.7,
        range_noise=0.03, max_obstacle_depth=1.5, growth_threshold=0.04, fit_range=2.0,
        free_memory=3,
    )
    boundary = harmonav.circle([0, 0], 4.0)
    nav = harmonav.Navigator(boundary, [3.0, 0.0], **given)
    cls, args, state = nav.__reduce__()
    assert cls is harmonav.Navigator and state == []
    bound = inspect.signature(harmonav.Navigator).bind(*args).arguments
    assert repr(bound.pop("boundary")) == repr(boundary)
    assert list(bound.pop("goal")) == [3.0, 0.0]
    assert {name: tuple(v) if name == "sensor" else v for name, v in bound.items()} == given


def test_a_copy_remembers_the_last_position():
    """The last commanded position is state too: an obstacle over it is refused by the copy."""
    nav = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0])
    nav.command([-1.0, 0.0])
    for how, twin in copies(nav):
        with pytest.raises(ValueError, match="robot"):
            twin.add_obstacle(harmonav.circle([-1.0, 0.2], 0.5))
        assert twin.obstacle_count == 0, how


def test_changing_a_copy_leaves_the_original_unchanged():
    nav, x, v = world()
    before = (nav.k, nav.obstacle_count, nav.command(x, v).tolist())
    for how, twin in copies(nav):
        twin.add_obstacle(harmonav.circle([2.0, 2.0], 0.4))
        twin.command(x + [0.1, 0.1], 3 * v)
        assert twin.obstacle_count == 3, how
        assert (nav.k, nav.obstacle_count, nav.command(x, v).tolist()) == before, how
    # And the other way round: changing the original leaves an earlier copy as it was.
    twin = copy.deepcopy(nav)
    nav.add_obstacle(harmonav.circle([2.0, 2.0], 0.4))
    assert twin.obstacle_count == 2
    assert twin.command(x, v).tolist() == before[2]


def test_a_corrupt_navigator_state_is_refused_and_changes_nothing():
    nav = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0])
    nav.add_obstacle(harmonav.circle([0.0, 0.0], 1.0))
    _, _, state = nav.__reduce__()
    with pytest.raises(ValueError, match="overlap"):
        nav.__setstate__(state + [("add", harmonav.circle([0.5, 0.0], 1.0))])
    with pytest.raises((TypeError, ValueError)):
        nav.__setstate__([("teleport", [0, 0])])
    assert nav.obstacle_count == 1
    nav.__setstate__(state)
    assert nav.obstacle_count == 1


def test_a_pickled_kinematic_navigator_keeps_its_speed_policy_and_v_max():
    """`speed` and `v_max` survive pickle: the copy commands exactly as the original, and
    differently from a navigator with the default speed."""
    kwargs = dict(speed="paper", v_max=0.5)
    nav = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], **kwargs)
    default = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0])
    x = [-2.0, 0.5]
    twin = pickle.loads(pickle.dumps(nav))
    np.testing.assert_array_equal(twin.command(x), nav.command(x))
    assert np.linalg.norm(nav.command(x)) <= 0.5 + 1e-12
    assert not np.array_equal(default.command(x), nav.command(x))

"""`copy.copy`, `copy.deepcopy` and pickle for `Shape` and `Navigator` (issue 23: neither could be
copied). A copy behaves as the original: the same outline and distances for a shape; for a
navigator the same known obstacles, `k`, damping state and last position, so the same commands,
and changing the copy leaves the original as it was."""

import copy
import inspect
import pathlib
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
        free_memory=3, base="holonomic", omega_max=None, a_max=None, alpha_max=None,
        force_bound=3.0, comfort=0.2,
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


# Hostile round 2026-12-06, D16: FloorNavigator pickles as Navigator does; Field and Scenario
# pickle; FloorPlan, Field and Scenario are immutable, so copying returns the same object;
# FloorPlan refuses pickle with a message that says what to do.

ROOM = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [2.0, 2.0], [2.0, 6.0], [0.0, 6.0]])
PILLAR = np.array([[0.8, 3.8], [1.2, 3.8], [1.2, 4.2], [0.8, 4.2]])
REPO = pathlib.Path(__file__).resolve().parents[2]


def floor_world(**kwargs):
    """A dynamic floor navigator that has moved, added a box and perceived nothing yet: its
    state (the last position, the discovery speed) is not a constructor argument."""
    nav = harmonav.FloorNavigator(
        ROOM, [5.4, 1.0], [PILLAR], law="dynamic", mass=2.0, mu=5.0, radius=0.1, margin=0.05,
        max_element=0.1, damping="paper", heading="paper", free_memory=4, **kwargs,
    )
    nav.command([1.0, 5.4], [0.0, -0.3])
    nav.add_obstacle(harmonav.circle([1.0, 3.0], 0.25))
    x, v = np.array([1.0, 2.0]), np.array([0.1, -0.4])
    nav.command(x, v)
    return nav, x, v


def test_a_pickled_floor_navigator_commands_as_the_original():
    nav, x, v = floor_world()
    probes = [(x, [0.6, -0.2]), (x + [0.05, 0.02], [-0.5, 0.4]), (np.array([4.0, 1.0]), [0.8, 0.0])]
    want = [nav.command(*p) for p in probes]
    nav.command(x, v)
    # A fresh navigator with the same obstacle commands differently (no discovery speed): the
    # comparison below can tell whether the copy carries the state.
    fresh = harmonav.FloorNavigator(
        ROOM, [5.4, 1.0], [PILLAR], law="dynamic", mass=2.0, mu=5.0, radius=0.1, margin=0.05,
        max_element=0.1, damping="paper", heading="paper", free_memory=4,
    )
    fresh.add_obstacle(harmonav.circle([1.0, 3.0], 0.25))
    assert any(not np.array_equal(fresh.command(*p), w) for p, w in zip(probes, want))
    for how, twin in copies(nav):
        assert isinstance(twin, harmonav.FloorNavigator), how
        assert (twin.k, twin.delta, twin.elements) == (nav.k, nav.delta, nav.elements), how
        for p, w in zip(probes, want):
            twin.command(x, v)
            np.testing.assert_array_equal(twin.command(*p), w, err_msg=how)
        assert twin.theta(x) == nav.theta(x), how
        # The last position is state too: an obstacle over it is refused by the copy.
        with pytest.raises(ValueError, match="robot"):
            twin.add_obstacle(harmonav.circle(probes[-1][0], 0.2))


def test_a_floor_navigator_pickle_holds_its_walls_and_keywords():
    nav, _, _ = floor_world(speed="paper", v_max=0.5)
    partial, args, state = nav.__reduce__()
    assert partial.func is harmonav.FloorNavigator
    assert partial.keywords["law"] == "dynamic" and partial.keywords["free_memory"] == 4
    assert partial.keywords["speed"] == "paper" and partial.keywords["v_max"] == 0.5
    outer, goal, holes = args
    assert len(outer) == len(ROOM) and len(holes) == 1 and list(goal) == [5.4, 1.0]
    assert [e[0] for e in state] == ["escapes", "command", "add", "command"]
    # The state replays on the navigator as it is, and a corrupt one changes nothing.
    k = nav.k
    with pytest.raises(ValueError, match="FloorNavigator state, entry 4"):
        nav.__setstate__(state + [("add", harmonav.circle([5.4, 1.0], 0.3))])
    with pytest.raises(TypeError, match="FloorNavigator state, entry 0"):
        nav.__setstate__([("teleport", [0, 0])])
    assert nav.k == k


def test_a_floor_navigator_from_a_map_pickles_as_its_walls():
    yaml = REPO / "scenarios" / "floorplans" / "maps" / "office.yaml"
    nav = harmonav.FloorNavigator.from_map(yaml, [1.5, 1.5], [8.5, 6.5], radius=0.1, margin=0.1)
    twin = pickle.loads(pickle.dumps(nav))
    assert (twin.elements, twin.k, twin.delta) == (nav.elements, nav.k, nav.delta)
    for x in ([1.5, 1.5], [4.0, 3.0], [8.0, 6.0]):
        np.testing.assert_array_equal(twin.command(x), nav.command(x))


def test_a_floor_navigator_pickles_its_perceived_obstacles():
    room = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 3.0], [0.0, 3.0]])
    nav = harmonav.FloorNavigator(room, [5.5, 1.8], radius=0.1, margin=0.1, max_element=0.1)
    # A box seen by a 360-beam scan from (1.5, 1.5): its near face at x = 2.6.
    a = np.arange(360) * (2 * np.pi / 360)
    r = np.full(360, np.inf)
    facing = np.abs(np.tan(a)) < 0.35 / 1.1
    r[facing & (np.cos(a) > 0)] = 1.1 / np.cos(a[facing & (np.cos(a) > 0)])
    assert nav.observe_scan([1.5, 1.5], 0.0, r, 0.0, 2 * np.pi / 360, 4.0).changed
    twin = pickle.loads(pickle.dumps(nav))
    assert len(twin.obstacles) == len(nav.obstacles) == 1
    np.testing.assert_array_equal(
        twin.obstacles[0].outline(64), nav.obstacles[0].outline(64)
    )
    np.testing.assert_array_equal(twin.command([1.5, 1.5]), nav.command([1.5, 1.5]))


def test_a_recovery_that_lifts_the_discovery_speed_survives_pickle():
    """A dynamic navigator's recovery out of a margin band lifts the discovery speed that its
    switched damping uses. The pickle keeps that command even after later ones (before, only
    the last command was kept, and the lift was lost)."""
    kwargs = dict(law="dynamic", mass=1.0, mu=5.0, radius=0.1, margin=0.2, k="paper",
                  damping="paper", sensor=(1.5, 90.0))
    nav = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], **kwargs)
    nav.command([-1.0, -1.5], [0.0, 0.0])
    nav.add_obstacle(harmonav.circle([0.0, 0.0], 1.0))
    # In the margin band: 1.15 from the centre, clear of the true disc grown by the radius.
    nav.command([-1.15, 0.0], [0.9, 0.0])
    assert nav.mode == "recovering"
    x, v = np.array([-2.5, 1.5]), np.array([0.3, 0.0])
    nav.command(x, v)
    probes = [(np.array([-1.45, 0.3]), [1.2, -0.4]), (np.array([-1.4, -0.5]), [1.5, 0.5])]
    want = [nav.command(*p) for p in probes]
    nav.command(x, v)
    unlifted = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], **kwargs)
    unlifted.command([-1.0, -1.5], [0.0, 0.0])
    unlifted.add_obstacle(harmonav.circle([0.0, 0.0], 1.0))
    unlifted.command(x, v)
    assert any(not np.array_equal(unlifted.command(*p), w) for p, w in zip(probes, want))
    for how, twin in copies(nav):
        for p, w in zip(probes, want):
            twin.command(x, v)
            np.testing.assert_array_equal(twin.command(*p), w, err_msg=how)


def test_immutable_objects_copy_as_themselves_and_pickle_or_say_why_not(tmp_path):
    scenario_file = tmp_path / "mixed.toml"
    scenario_file.write_text((REPO / "scenarios" / "shapes" / "mixed.toml").read_text())
    scenario = harmonav.Scenario.load(scenario_file)
    plan = harmonav.FloorPlan.load(REPO / "scenarios" / "floorplans" / "l-room.toml")
    field = harmonav.Field(harmonav.circle([0, 0], 4.0), [SHAPES[0], SHAPES[2]], [3.0, 0.0],
                           k="paper", margin=0.1)
    for obj in (scenario, plan, field, scenario.field()):
        assert copy.copy(obj) is obj and copy.deepcopy(obj) is obj
    with pytest.raises(TypeError, match=r"FloorPlan.*FloorPlan\.load\(path\)"):
        pickle.dumps(plan)
    # A scenario pickles as its path and text: it unpickles with the file gone.
    data = [pickle.dumps(scenario, protocol=p) for p in PROTOCOLS]
    from_scenario = pickle.dumps(scenario.field())
    scenario_file.unlink()
    for d in data:
        twin = pickle.loads(d)
        assert (twin.name, twin.path) == (scenario.name, scenario.path)
        assert twin.shortest_path()[0] == scenario.shortest_path()[0]
    pts = np.random.default_rng(3).uniform(-3, 3, (100, 2))
    for how, twin in copies(field):
        assert repr(twin) == repr(field), how
        np.testing.assert_array_equal(twin.eval(pts)[0], field.eval(pts)[0], err_msg=how)
    np.testing.assert_array_equal(
        pickle.loads(from_scenario).eval(pts)[0], scenario.field().eval(pts)[0]
    )

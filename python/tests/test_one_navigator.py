"""Issue 51, item 4: one `Navigator` over either world. `FloorNavigator` is its subclass: the
methods are `Navigator`'s (written once), the options are parsed and checked in one place (the
same defaults, the same errors for both constructors), and a floor navigator pickles as a star
world's does, commanding bit for bit as the original."""

import copy
import inspect
import pickle

import numpy as np
import pytest

import harmonav
from conftest import SCENARIOS

SQUARE = np.array([[0.0, 0.0], [5.0, 0.0], [5.0, 5.0], [0.0, 5.0]])
OFFICE = SCENARIOS / "floorplans" / "maps" / "office.yaml"
# Methods and properties that both worlds share.
SHARED = ["add_obstacle", "command", "observe_scan", "perceived", "obstacles", "theta", "k",
          "obstacle_count", "goal", "speed_bound", "mode", "control_period", "clearance",
          "__reduce__", "__setstate__"]
FLOOR_ONLY = ["wall_distance", "delta", "elements", "escapes"]


def star(**options):
    return harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], **options)


def floor(**options):
    return harmonav.FloorNavigator(SQUARE, [4.0, 4.0], **options)


def test_a_floor_navigator_is_a_navigator_with_its_methods():
    assert issubclass(harmonav.FloorNavigator, harmonav.Navigator)
    made = [floor(), harmonav.FloorNavigator.from_map(OFFICE, [1.5, 1.5], [8.5, 6.5])]
    for nav in made + [copy.copy(made[0]), copy.deepcopy(made[0]), pickle.loads(pickle.dumps(made[0]))]:
        assert isinstance(nav, harmonav.Navigator) and type(nav) is harmonav.FloorNavigator
    # Not overridden: the one implementation.
    for name in SHARED:
        assert name not in vars(harmonav.FloorNavigator), name
    # The floor-only methods exist only on the floor plan's class.
    nav = star()
    for name in FLOOR_ONLY:
        assert hasattr(made[0], name)
        with pytest.raises(AttributeError, match=name):
            getattr(nav, name)


@pytest.mark.parametrize("make,start", [(star, [-3.0, 0.5]), (floor, [1.0, 1.0])])
@pytest.mark.parametrize("law", ["kinematic", "dynamic"])
def test_the_shared_methods_work_on_both_worlds(make, start, law):
    nav = make(law=law, radius=0.1, margin=0.05)
    x, v = np.array(start), np.zeros(2)
    assert nav.mode == "law" and nav.obstacle_count == 0 and nav.obstacles == []
    k = nav.k
    index = nav.add_obstacle(harmonav.circle([2.0, 2.2], 0.3))
    assert index == 0 and nav.obstacle_count == 1 and nav.k > k
    assert nav.obstacles[0].contains([2.0, 2.2]) and nav.perceived == []
    assert 0.0 < nav.theta(x) < 1.0 and nav.clearance(x) > 0.0
    assert (nav.speed_bound is None) == (law == "kinematic")
    np.testing.assert_array_equal(nav.goal, [3.0, 0.0] if make is star else [4.0, 4.0])
    for _ in range(50):
        u = nav.command(x, v)
        assert np.all(np.isfinite(u)) and nav.mode in ("law", "capped")
        if law == "kinematic":
            x = x + nav.control_period * u
        else:
            v = v + nav.control_period * u
            x = x + nav.control_period * v
    assert nav.theta(x) < nav.theta(start)
    # A scan with nothing to see changes nothing.
    update = nav.observe_scan(x, 0.0, np.full(90, np.inf), -np.pi, 2 * np.pi / 90, 0.5)
    assert not update.changed and nav.obstacle_count == 1
    with pytest.raises(ValueError):
        nav.add_obstacle(harmonav.circle(x, 0.2))  # over the robot
    assert nav.obstacle_count == 1


def floor_loop(nav, x, steps):
    """`steps` held kinematic commands from `x`: the positions."""
    path = [x]
    for _ in range(steps):
        x = x + nav.control_period * nav.command(x)
        path.append(x)
    return np.array(path)


def test_a_pickled_floor_navigator_drives_the_same_path_bit_for_bit():
    """After obstacles added and perceived and a stretch of driving, the restored navigator
    commands every later step exactly as the original (no escape under way when pickled)."""
    room = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 3.0], [0.0, 3.0]])
    nav = harmonav.FloorNavigator(room, [5.5, 1.8], radius=0.1, margin=0.1, max_element=0.1,
                                  sensor=(1.5, 90.0), rho_min=0.08)
    a = np.arange(360) * (2 * np.pi / 360)
    r = np.full(360, np.inf)
    facing = np.abs(np.tan(a)) < 0.35 / 1.1
    r[facing & (np.cos(a) > 0)] = 1.1 / np.cos(a[facing & (np.cos(a) > 0)])
    assert nav.observe_scan([1.5, 1.5], 0.0, r, 0.0, 2 * np.pi / 360, 4.0).changed
    nav.add_obstacle(harmonav.circle([4.2, 1.0], 0.2))
    x = floor_loop(nav, np.array([0.5, 0.5]), 40)[-1]
    assert nav.escapes == 0
    for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
        twin = pickle.loads(pickle.dumps(nav, protocol=protocol))
        assert type(twin) is harmonav.FloorNavigator
        assert twin.obstacle_count == nav.obstacle_count == 2
        mine = copy.deepcopy(nav)
        ours, theirs = floor_loop(mine, x, 200), floor_loop(twin, x, 200)
        assert np.array_equal(ours, theirs), protocol
        # Escapes begun after the pickle (behind the box) are the same too.
        assert twin.escapes == mine.escapes
    partial, _, _ = nav.__reduce__()
    assert partial.keywords["sensor"] == (1.5, 90.0) and partial.keywords["rho_min"] == 0.08


def test_a_floor_navigator_pickled_during_an_escape_goes_on_escaping_bit_for_bit():
    """Issue 51: a floor navigator pickled while an escape is under way (the long L room, whose
    corner holds the law at a rest point of its slide) commands every later step exactly as
    the original, its escape memory (the escape, its levels, the count and the point it stays
    near) taken back after every call. The control: the same calls with another memory (none
    under way, and the last escape against the law begun far above, so that none may begin)
    command otherwise."""
    outer = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [2.0, 2.0], [2.0, 6.0], [0.0, 6.0]])
    nav = harmonav.FloorNavigator(outer, [5.4, 1.0], radius=0.1, margin=0.1, max_element=0.1)
    x = np.array([1.0, 5.4])
    for _ in range(20000):
        x = x + nav.control_period * nav.command(x)
        if nav.mode == "escaping":
            break
    assert nav.mode == "escaping" and nav.escapes >= 1, (x, nav.mode)
    call, args, state = nav.__reduce__()
    assert state[0][0] == "escapes" and state[0][1] is not None, state[0]
    twin = pickle.loads(pickle.dumps(nav))
    mine = copy.deepcopy(nav)
    ours, theirs = floor_loop(mine, x, 300), floor_loop(twin, x, 300)
    assert np.array_equal(ours, theirs)
    assert twin.escapes == mine.escapes
    other = call(*args)
    other.__setstate__([("escapes", None, False, -1e300, 0, None, 0)] + state[1:])
    assert not np.array_equal(floor_loop(other, x, 300), ours)
    # A corrupt memory is refused and changes nothing: a slot of the wrong type, two of them.
    before = twin.__reduce__()[2]
    with pytest.raises(TypeError, match="entry 0"):
        twin.__setstate__([("escapes", None, "no", None, 0, None, 0)] + state[1:])
    with pytest.raises(ValueError, match="a second escape memory"):
        twin.__setstate__(state + [state[0]])
    assert twin.__reduce__()[2] == before


BAD = [
    (dict(gian=2.0), TypeError, "unexpected keyword argument 'gian'"),
    (dict(mu=-1.0), ValueError, "`mu` must be finite and positive, got -1"),
    (dict(damping="bogus"), ValueError, "unknown damping policy \"bogus\""),
    (dict(v_max=float("nan")), ValueError, "v_max"),
    (dict(sensor=(1.0, -5.0)), ValueError, "sensor"),
    (dict(free_memory=-1), ValueError, "`free_memory`: must be an integer from 0 to 256"),
    (dict(free_memory=1.5), TypeError, "`free_memory` must be an integer, got float"),
    (dict(gain="fast"), TypeError, "real number"),
]


@pytest.mark.parametrize("options,error,words", BAD, ids=lambda p: str(p))
def test_a_bad_option_is_refused_naming_it_in_every_constructor(options, error, words):
    """One validation path: the same error, with the same message, from each constructor (a
    floor plan's before its map is solved)."""
    messages = []
    for make in (star, floor, lambda **o: harmonav.FloorNavigator.from_map(
            OFFICE, [1.5, 1.5], [8.5, 6.5], **o)):
        with pytest.raises(error, match=words) as caught:
            make(**options)
        messages.append(str(caught.value).split("() got")[-1])
    assert len(set(messages)) == 1, messages


def test_both_worlds_have_the_same_defaults():
    """The signature's defaults are the options a navigator is built with (the Rust defaults),
    and a floor navigator's are a star world's."""
    _, args, _ = star().__reduce__()
    parameters = list(inspect.signature(harmonav.Navigator).parameters.values())[2:]
    assert {p.name: p.default for p in parameters} == dict(
        zip([p.name for p in parameters], args[2:]))
    partial, _, _ = floor().__reduce__()
    floor_only = {"max_element": 0.2, "centre": "solve", "heading": "auto", "funnels": False}
    assert partial.keywords == {**{p.name: p.default for p in parameters}, **floor_only}


def test_options_may_still_be_given_in_order_to_a_star_navigator():
    given = ("dynamic", 1.0, 2.0, 5.0, (1.5, 90.0))
    by_name = star(law="dynamic", mass=2.0, mu=5.0, sensor=(1.5, 90.0))
    in_order = harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], *given)
    assert in_order.__reduce__()[1][2:] == by_name.__reduce__()[1][2:]
    np.testing.assert_array_equal(in_order.command([-2.0, 0.5], [0.3, 0.0]),
                                  by_name.command([-2.0, 0.5], [0.3, 0.0]))
    with pytest.raises(TypeError, match="multiple values for argument 'law'"):
        harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], "dynamic", law="kinematic")
    with pytest.raises(TypeError, match="at most 27 positional arguments"):
        harmonav.Navigator(harmonav.circle([0, 0], 4.0), [3.0, 0.0], *([None] * 26))
    # A floor plan's options are keywords only, as before.
    with pytest.raises(TypeError):
        harmonav.FloorNavigator(SQUARE, [4.0, 4.0], None, 0.2)

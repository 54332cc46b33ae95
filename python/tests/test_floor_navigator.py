"""harmonav.FloorNavigator: the floor-plan navigator embedded in a loop written in Python. The
walls, the robot's clearance and the scans are computed here with NumPy, independently of
harmonav: point-to-segment distances, a parity test for inside, and rays cast against
segments."""

import copy

import numpy as np
import pytest

import harmonav
from conftest import SCENARIOS

# The L room of scenarios/floorplans/l-room.toml: two 6 m arms, 2 m wide, a square pillar.
L_OUTER = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [2.0, 2.0], [2.0, 6.0], [0.0, 6.0]])
L_PILLAR = np.array([[0.8, 3.8], [1.2, 3.8], [1.2, 4.2], [0.8, 4.2]])
RADIUS, MARGIN = 0.1, 0.1


def edges(*rings):
    """The segments (a, b) of closed rings, as two (M, 2) arrays."""
    a = np.concatenate([r for r in rings])
    b = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
    return a, b


def distance(x, segments):
    """The distance from x to the nearest segment."""
    a, b = segments
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", x - a, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
    return np.min(np.linalg.norm(a + t[:, None] * d - x, axis=1))


def inside(x, ring):
    """Whether x lies inside the closed ring (even-odd rule)."""
    a, b = ring, np.roll(ring, -1, axis=0)
    crosses = (a[:, 1] > x[1]) != (b[:, 1] > x[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        at = a[:, 0] + (x[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(crosses & (x[0] < at)) % 2)


def l_room(**kwargs):
    return harmonav.FloorNavigator(
        L_OUTER, [5.4, 1.0], [L_PILLAR], radius=RADIUS, margin=MARGIN, max_element=0.05, **kwargs
    )


def test_a_python_loop_turns_the_l_rooms_corner_clear_of_the_walls():
    nav = l_room()
    assert nav.delta == 0.05 and nav.elements > 100 and nav.k > 0
    walls = edges(L_OUTER, L_PILLAR)
    x, h = np.array([1.0, 5.4]), nav.control_period
    closest, steps = np.inf, 0
    for steps in range(1, 4000):
        x = x + h * nav.command(x)
        assert inside(x, L_OUTER) and not inside(x, L_PILLAR), x
        closest = min(closest, distance(x, walls))
        if np.linalg.norm(x - nav.goal) < 0.05:
            break
    assert np.linalg.norm(x - nav.goal) < 0.05, (steps, x)
    # The robot's disc kept its margin from the true walls (the certified region: at least
    # radius + margin from them, less what a step may cut between two states).
    assert closest >= RADIUS + MARGIN - 1e-6, closest
    # The binding's wall distance is the walls' own.
    for p in ([1.0, 5.4], [3.0, 1.0], [1.9, 2.1], [1.0, 4.0]):
        want = distance(np.array(p), walls) * (-1.0 if inside(np.array(p), L_PILLAR) else 1.0)
        assert nav.wall_distance(p) == pytest.approx(want, abs=1e-9)
    assert nav.theta(nav.goal) < 1e-9 and 0.0 < nav.theta([1.0, 5.4]) < 1.0


def scan(position, heading, segments, beams=360, range_max=4.0):
    """A noise-free 360° scan at `position`: each beam's first hit among the segments, +inf
    beyond range_max."""
    angles = heading + np.arange(beams) * (2 * np.pi / beams)
    u = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    a, b = segments
    d = b - a
    ranges = np.full(beams, np.inf)
    for i, ui in enumerate(u):
        # position + t·ui = a + s·d
        den = ui[0] * (-d[:, 1]) - ui[1] * (-d[:, 0])
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = a - position
            t = (rel[:, 0] * (-d[:, 1]) - rel[:, 1] * (-d[:, 0])) / den
            s = (ui[0] * rel[:, 1] - ui[1] * rel[:, 0]) / den
        ok = (np.abs(den) > 1e-12) & (t > 0) & (s >= 0) & (s <= 1)
        if ok.any():
            ranges[i] = np.min(t[ok])
    ranges[ranges > range_max] = np.inf
    return ranges


def test_a_floor_navigator_perceives_an_unknown_box_from_scans_and_passes_it():
    room = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 3.0], [0.0, 3.0]])
    box = np.array([[2.6, 1.1], [3.4, 1.1], [3.4, 1.9], [2.6, 1.9]])
    nav = harmonav.FloorNavigator(
        room, [5.5, 1.8], radius=RADIUS, margin=MARGIN, max_element=0.1, max_obstacle_depth=1.0
    )
    k0 = nav.k
    world, box_edges = edges(room, box), edges(box)
    x, h = np.array([0.5, 1.2]), nav.control_period
    heading, hits_on_box, events = 0.0, [], 0
    for n in range(4000):
        if n % 10 == 0:  # a 10 Hz lidar in a 100 Hz loop
            r = scan(x, heading, world)
            u = nav.observe_scan(x, heading, r, 0.0, 2 * np.pi / 360, 4.0)
            events += u.changed
            angles = heading + np.arange(360) * (2 * np.pi / 360)
            seen = np.isfinite(r)
            pts = x + r[seen, None] * np.stack([np.cos(angles[seen]), np.sin(angles[seen])], 1)
            hits_on_box += [p for p in pts if distance(p, box_edges) < 1e-9]
        step = h * nav.command(x)
        if np.linalg.norm(step) > 0:
            heading = float(np.arctan2(step[1], step[0]))
        x = x + step
        assert distance(x, box_edges) > RADIUS and not inside(x, box), x
        if np.linalg.norm(x - nav.goal) < 0.05:
            break
    assert np.linalg.norm(x - nav.goal) < 0.05, x
    # The box was perceived (the walls were not: their hits are the map's), as one shape
    # holding every hit that fell on it.
    shapes = nav.obstacles
    assert events >= 1 and len(shapes) == 1 and nav.k > k0
    assert len(hits_on_box) > 50
    assert max(shapes[0].signed_distance(p) for p in hits_on_box) <= 0.0


def test_a_floor_navigator_from_a_ros_map():
    yaml = SCENARIOS / "floorplans" / "maps" / "office.yaml"
    nav = harmonav.FloorNavigator.from_map(
        yaml, [1.5, 1.5], [8.5, 6.5], radius=RADIUS, margin=MARGIN, centre="goal"
    )
    assert nav.elements > 500
    assert nav.theta([8.5, 6.5]) < 1e-9 and 0.0 < nav.theta([1.5, 1.5]) < 1.0
    u = nav.command([1.5, 1.5])
    assert np.all(np.isfinite(u)) and np.linalg.norm(u) > 0 and nav.mode in ("law", "capped")
    # A goal in a wall, and a missing file, name the problem and the file.
    with pytest.raises(ValueError, match="office.yaml.*goal|goal.*office.yaml"):
        harmonav.FloorNavigator.from_map(yaml, [1.5, 1.5], [0.01, 0.01])
    bad_options = [({"simplify": float("nan")}, "simplify"), ({"speck_pixels": -1}, "speck_pixels")]
    for bad, field in bad_options:
        with pytest.raises(ValueError, match=f"`{field}`"):
            harmonav.FloorNavigator.from_map(yaml, [1.5, 1.5], [8.5, 6.5], **bad)
    with pytest.raises(ValueError, match="nowhere.yaml"):
        harmonav.FloorNavigator.from_map(yaml.parent / "nowhere.yaml", [1.5, 1.5], [8.5, 6.5])


def test_bad_arguments_name_the_field_and_a_failed_call_changes_nothing():
    with pytest.raises(ValueError, match="goal"):
        l_room().__class__(L_OUTER, [10.0, 10.0], radius=RADIUS, margin=MARGIN)
    with pytest.raises((TypeError, ValueError), match=r"holes\[0\]"):
        harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], [[1.0, 2.0, 3.0]])
    with pytest.raises(ValueError, match="law"):
        harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], law="hover")
    with pytest.raises(ValueError, match="`radius`"):
        harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], radius=-0.1)
    with pytest.raises(ValueError, match="`free_memory`: must be an integer from 0 to 256"):
        harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], free_memory=-1)
    with pytest.raises(ValueError, match="boundary elements.*max_element"):
        harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], max_element=1e-6)  # refused before the solve
    with pytest.raises(ValueError, match="heading"):
        harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], heading="sideways")
    with pytest.raises(ValueError, match="`mass` must be finite and positive, got NaN"):
        harmonav.FloorNavigator(L_OUTER, [5.4, 1.0], mass=float("nan"))
    # A far goal is named in scientific notation, at its true distance.
    with pytest.raises(ValueError, match=r"the goal is -1\.0000e200 m from the walls"):
        harmonav.FloorNavigator(L_OUTER, [1e200, 1.0])
    nav = l_room()
    # Far points are as far from the walls as from the origin (parry's queries overflowed
    # beyond 1e154 m: a wall distance of -inf and a clearance of -δ).
    for far in (1e20, 1e200, -1e300):
        assert nav.wall_distance([far, 1.0]) == pytest.approx(-abs(far), rel=1e-12)
        assert nav.clearance([far, 1.0]) == pytest.approx(-abs(far), rel=1e-12)
    k = nav.k
    # An obstacle over the goal is refused, and the navigator is as it was.
    with pytest.raises(ValueError):
        nav.add_obstacle(harmonav.circle([5.4, 1.0], 0.3))
    assert nav.k == k
    # A scan from inside a wall is refused, and nothing is perceived.
    with pytest.raises(ValueError):
        nav.observe_scan([3.0, 3.0], 0.0, np.full(360, 1.0), 0.0, 2 * np.pi / 360, 4.0)
    assert nav.obstacles == [] and nav.k == k
    # A copy is independent.
    other = copy.copy(nav)
    other.add_obstacle(harmonav.circle([3.5, 1.0], 0.2))
    assert other.k > k and nav.k == k


def test_obstacles_lists_the_added_shapes_and_perceived_only_the_scanned():
    """Issue 56, D20: `obstacles` listed only the perceived shapes, so two successful
    `add_obstacle` calls left it empty; now it holds every known shape in the navigator's
    order, and `perceived` the scanned ones."""
    f = harmonav.FloorNavigator([[0, 0], [5, 0], [5, 5], [0, 5]], [4, 4])
    f.add_obstacle(harmonav.circle([2, 2], 0.3))
    f.add_obstacle(harmonav.circle([3, 1.2], 0.2))
    assert len(f.obstacles) == 2 and len(f.perceived) == 0
    assert f.obstacles[0].contains([2, 2]) and f.obstacles[1].contains([3, 1.2])
    nav = harmonav.Navigator(harmonav.circle([0, 0], 10.0), goal=[8, 0])
    nav.add_obstacle(harmonav.circle([0, 3], 0.5))
    assert len(nav.obstacles) == 1 and nav.obstacles[0].contains([0, 3])


def test_furniture_against_a_wall_joins_the_walls_and_the_loop_stays_clear():
    """A table 0.1 m from the L room's south wall, on the straight path: the walls' own field
    cannot take it (its band reaches the boundary layer), so it joins the walls (`joined`, the
    harmonic map solved again) instead of being refused, and a Python loop past it arrives with
    the robot's disc clear of the walls and the table (NumPy distances)."""
    nav = l_room()
    table = harmonav.circle([3.5, 0.5], 0.4)
    assert nav.add_obstacle(table) == 0
    assert nav.joined == [0] and nav.obstacle_count == 1
    walls = edges(L_OUTER, L_PILLAR)
    x, h = np.array([1.0, 5.4]), nav.control_period
    closest = np.inf
    for _ in range(6000):
        x = x + h * nav.command(x)
        closest = min(closest, distance(x, walls), np.linalg.norm(x - [3.5, 0.5]) - 0.4)
        if np.linalg.norm(x - nav.goal) < 0.05:
            break
    assert np.linalg.norm(x - nav.goal) < 0.05, x
    assert closest > RADIUS, closest
    # The same table in the open joins nothing.
    other = l_room()
    other.add_obstacle(harmonav.circle([3.5, 1.0], 0.2))
    assert other.joined == []


# The bar room of scenarios/floorplans/funnels/bar.toml: a 4 m bar across a 6 × 4 m room, the
# goal just behind it; below the bar the flow of Θ alone rests against it.
BAR_OUTER = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 4.0], [0.0, 4.0]])
BAR = np.array([[1.0, 1.8], [5.0, 1.8], [5.0, 2.2], [1.0, 2.2]])
BAR_GOAL, BAR_START = [3.0, 2.6], np.array([2.0, 1.0])


def bar_room(**kwargs):
    return harmonav.FloorNavigator(
        BAR_OUTER, BAR_GOAL, [BAR], radius=0.1, margin=0.1, max_element=0.1, heading="paper",
        **kwargs,
    )


def fly_bar(nav, seconds):
    """The held loop from BAR_START: (arrived, end, the funnels it was in, in order, modes)."""
    x, h = BAR_START.copy(), nav.control_period
    walls = edges(BAR_OUTER, BAR)
    funnels, modes = [], set()
    for _ in range(int(seconds / h)):
        if np.linalg.norm(x - BAR_GOAL) < 0.05:
            return True, x, funnels, modes
        x = x + h * nav.command(x)
        modes.add(nav.mode)
        assert distance(x, walls) >= 0.2 - 1e-6 and not inside(x, BAR), x
        now = nav.funnels["current"] if nav.funnels else None
        if not funnels or funnels[-1] != now:
            funnels.append(now)
    return False, x, funnels, modes


def test_funnels_certify_the_room_and_lead_around_the_bar_where_theta_alone_rests():
    import pickle

    # Without the chain (the negative control): pressed under the bar, not arrived in 20 s.
    arrived, end, _, _ = fly_bar(bar_room(), 20.0)
    assert not arrived and end[1] < 1.8, end
    nav = bar_room(funnels=True)
    chain = nav.funnels
    assert chain["count"] >= 2 and chain["certified_fraction"] >= 0.9, chain
    assert chain["goals"][0] == (tuple(BAR_GOAL), None) and chain["current"] is None
    assert all(p is not None and p < i for i, (_, p) in enumerate(chain["goals"]) if i > 0)
    # The start lies in a funnel other than the goal's; a point in the bar in none.
    assert nav.funnel_at(BAR_START) > 0 and nav.funnel_at([3.0, 2.0]) is None
    # A pickled navigator rebuilds the same chain (built from the goal, not from a start).
    twin = pickle.loads(pickle.dumps(nav))
    assert twin.funnels == chain
    arrived, end, funnels, modes = fly_bar(nav, 40.0)
    assert arrived and "escaping" not in modes, (end, funnels, modes)
    # Every switch goes to an ancestor of the funnel it leaves, and the last is the goal's.
    parents = [p for _, p in chain["goals"]]
    assert funnels[-1] == 0 and None not in funnels, funnels
    for a, b in zip(funnels, funnels[1:]):
        up = parents[a]
        while up is not None and up != b:
            up = parents[up]
        assert up == b, (a, b, funnels)
    # The twin commands as the original did.
    assert np.array_equal(twin.command(BAR_START), bar_room(funnels=True).command(BAR_START))


def test_funnels_need_the_kinematic_law():
    with pytest.raises(ValueError, match="funnels=True.*kinematic"):
        bar_room(funnels=True, law="dynamic")
    assert bar_room().funnels is None and bar_room().funnel_at(BAR_START) is None


def test_a_ros_maps_navigator_builds_funnels_and_its_pickle_rebuilds_them():
    import pickle

    # The public LSE arena (scenarios/floorplans/public/lse-arena.toml): the goal's own level
    # certifies 39.9 % of the room, the chain all of it.
    yaml = SCENARIOS / "floorplans" / "public" / "maps" / "lse-arena.yaml"
    start, goal = [0.48, 2.53], [3.53, 0.48]
    nav = harmonav.FloorNavigator.from_map(yaml, start, goal, radius=0.2, margin=0.05, funnels=True)
    chain = nav.funnels
    assert chain["count"] >= 2 and chain["certified_fraction"] > 0.99, chain
    assert nav.funnel_at(start) is not None
    # Pickle rebuilds the navigator from the walls' rings, and the chain from the goal.
    twin = pickle.loads(pickle.dumps(nav))
    assert twin.funnels == chain
    assert np.array_equal(twin.command(start), nav.command(start))

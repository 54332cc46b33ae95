"""Navigator.observe_scan: a lidar loop that never touches the truth, perceived shapes that
contain it, typed results, refusals that change nothing, and pickling of scanned state."""

import copy
import math
import pickle

import numpy as np
import pytest

import harmonav

TRUTH = [([-1.0, 0.2], 0.4), ([1.5, -1.2], 0.3)]
BOUNDARY_R = 5.0
BEAMS = 360
RANGE_MAX = 3.0
NOISE = 0.01


def ranges_at(x, heading, rng, truth=TRUTH):
    """A 360° scan of the true discs and the boundary (ray-circle intersections), uniform noise
    within NOISE, 1 % NaN dropouts, +inf beyond RANGE_MAX."""
    a = heading - math.pi + np.arange(BEAMS) * (2 * math.pi / BEAMS)
    u = np.stack([np.cos(a), np.sin(a)], axis=1)
    best = np.full(BEAMS, np.inf)
    for c, r in truth:
        d = x - np.asarray(c)
        b = u @ d
        disc = b * b - (d @ d - r * r)
        t = -b - np.sqrt(np.maximum(disc, 0.0))
        best = np.where((disc > 0) & (t > 0), np.minimum(best, t), best)
    # The boundary: the ray leaves the disc of radius BOUNDARY_R.
    b = u @ x
    t = -b + np.sqrt(b * b - (x @ x - BOUNDARY_R**2))
    best = np.minimum(best, t)
    out = best + rng.uniform(-NOISE, NOISE, BEAMS)
    out[out >= RANGE_MAX] = np.inf
    out[rng.uniform(size=BEAMS) < 0.01] = np.nan
    return out, -math.pi, 2 * math.pi / BEAMS


def navigator(goal=(3.0, 0.5), **kw):
    args = dict(sensor=(RANGE_MAX, 360.0), range_noise=NOISE, max_obstacle_depth=1.0)
    args.update(kw)
    return harmonav.Navigator(harmonav.circle([0.0, 0.0], BOUNDARY_R), np.array(goal), **args)


def observe(nav, x, rng, heading=0.0):
    ranges, amin, inc = ranges_at(np.asarray(x, float), heading, rng)
    return nav.observe_scan(
        position=x, heading=heading, ranges=ranges, angle_min=amin, angle_increment=inc, range_max=RANGE_MAX
    )


def truth_boundary(n=128):
    th = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return [np.asarray(c) + r * np.stack([np.cos(th), np.sin(th)], axis=1) for c, r in TRUTH]


def test_a_scan_adds_shapes_that_contain_the_seen_truth():
    nav = navigator()
    k0 = nav.k
    u = observe(nav, [-3.0, 0.0], np.random.default_rng(1))
    assert isinstance(u, harmonav.ScanUpdate)
    assert u.changed and u.added and not u.grown and not u.absorbed
    assert u.hits > 0 and u.explained > 0 and u.event_clearance > 0.5
    assert nav.obstacle_count == len(u.added) and nav.k != k0
    shapes = nav.obstacles
    assert [s.center.tolist() for s in shapes] == [s.center.tolist() for _, s in nav.perceived]
    seen = [pts for pts in truth_boundary() if any(s.contains(pts.mean(axis=0)) for s in shapes)]
    assert seen, "the near disc is seen"
    for pts in seen:
        inside = np.min([s.signed_distance(pts) for s in shapes], axis=0)
        assert np.all(inside < 0), inside.max()
    # The same view again: explained, no event.
    again = observe(nav, [-3.0, 0.0], np.random.default_rng(2))
    assert not again.changed and again.explained == again.hits


def test_the_lidar_loop_arrives_without_touching_the_truth():
    nav = navigator()
    rng = np.random.default_rng(7)
    x, h, t, closest, events = np.array([-3.2, -0.3]), 0.01, 0.0, np.inf, 0
    goal = nav.goal
    while np.linalg.norm(x - goal) > 0.01:
        if round(t / h) % 10 == 0:
            events += observe(nav, x, rng).changed
        x = x + h * nav.command(x)
        t += h
        closest = min(closest, min(np.linalg.norm(x - np.asarray(c)) - r for c, r in TRUTH))
        assert t < 60.0, f"no arrival: x = {x}"
    assert closest > 0.0 and events >= 1 and nav.obstacle_count == len(TRUTH)


def state(nav):
    pts = [[-3.0, 2.0], [2.0, 2.0], [0.0, -3.0]]
    return (
        nav.obstacle_count,
        nav.k,
        [(i, s.center.tolist(), s.signed_distance([0.0, 0.0])) for i, s in nav.perceived],
        [nav.theta(p) for p in pts],
    )


@pytest.mark.parametrize(
    "change, message",
    [
        (dict(ranges=[]), "no ranges"),
        (dict(angle_increment=-0.01), "angle_increment"),
        (dict(angle_min=float("nan")), "angle_min"),
        (dict(range_max=-1.0), "range_min"),
        (dict(position=[float("inf"), 0.0]), "finite"),
        (dict(heading=float("nan")), "pose.yaw"),
        (dict(heading=1e7), "`pose.yaw` must be finite and at most 1e6 rad"),
        (dict(position=[-1.0, 0.2]), "inside known shape"),
        (dict(position=[9.0, 0.0]), "outside the known boundary"),
    ],
)
def test_bad_scans_raise_and_change_nothing(change, message):
    nav = navigator()
    observe(nav, [-3.0, 0.0], np.random.default_rng(1))
    before = state(nav)
    ranges, amin, inc = ranges_at(np.array([-2.5, 1.0]), 0.0, np.random.default_rng(3))
    args = dict(
        position=[-2.5, 1.0], heading=0.0, ranges=ranges, angle_min=amin, angle_increment=inc, range_max=RANGE_MAX
    )
    args.update(change)
    with pytest.raises(ValueError, match=message):
        nav.observe_scan(**args)
    assert state(nav) == before


def test_all_nan_ranges_are_no_information():
    nav = navigator()
    u = nav.observe_scan([-3.0, 0.0], 0.0, np.full(BEAMS, np.nan), -math.pi, 2 * math.pi / BEAMS, RANGE_MAX)
    assert (u.hits, u.changed, nav.obstacle_count) == (0, False, 0)


def test_a_shape_over_the_goal_is_refused():
    nav = navigator(goal=(-0.4, 0.2))  # just behind the first disc, within the depth prior
    with pytest.raises(ValueError, match="contains the goal"):
        observe(nav, [-3.0, 0.0], np.random.default_rng(1))
    assert nav.obstacle_count == 0 and nav.perceived == []


@pytest.mark.parametrize(
    "kw, field",
    [
        (dict(range_noise=-1.0), "range_noise"),
        (dict(max_obstacle_depth=0.0), "max_obstacle_depth"),
        (dict(growth_threshold=0.0), "growth_threshold"),
        # At or below the depth prior the sector of d_min of the dynamic law under the paper's
        # damping would be empty (the other policies brake within each event's room).
        (dict(fit_range=1.0, law="dynamic", damping="paper"), "above max_obstacle_depth"),
        (dict(fit_range=0.0), "fit_range"),
        (dict(free_memory=10**6), "free_memory"),
    ],
)
def test_scan_options_are_checked(kw, field):
    with pytest.raises(ValueError, match=field):
        navigator(**kw)


def test_the_kinematic_law_may_fit_from_nearer_than_the_depth_prior():
    """The kinematic law takes no d_min from the fit range (docs/maths.md §12.16), nor does the
    dynamic law but under the paper's damping (§12.18), so one below ``max_obstacle_depth`` is
    accepted, and defers the disc 1.6 m away."""
    for kw in (dict(), dict(law="dynamic")):
        nav = navigator(fit_range=0.5, **kw)
        u = observe(nav, [-3.0, 0.0], np.random.default_rng(1))
        assert u.hits > 0 and not u.changed


def test_far_segments_wait_for_a_nearer_scan():
    """With `fit_range`, discs whose every hit lies farther are not fitted yet (the scan changes
    nothing), and are fitted once the robot is near; without it the first scan adds them."""
    x = np.array([-3.0, 0.0])
    # The nearer disc's face is 1.6 m away; fit_range 1.5 m defers it.
    near = navigator(fit_range=1.5)
    u = observe(near, x, np.random.default_rng(1))
    assert u.hits > 0 and not u.changed and near.obstacle_count == 0
    u = observe(near, [-2.0, 0.0], np.random.default_rng(2))
    assert u.changed and near.obstacle_count >= 1
    every = navigator()
    assert observe(every, x, np.random.default_rng(1)).changed


def test_copy_and_pickle_keep_the_scanned_obstacles():
    nav = navigator()
    rng = np.random.default_rng(5)
    observe(nav, [-3.0, 0.0], rng)
    nav.command([-3.0, 0.0])
    observe(nav, [0.0, -2.5], rng)
    for other in (copy.copy(nav), copy.deepcopy(nav), pickle.loads(pickle.dumps(nav))):
        assert state(other) == state(nav)
        assert np.array_equal(other.command([-2.9, 0.0]), copy.copy(nav).command([-2.9, 0.0]))


def test_the_study_table_counts_refused_scans_apart_and_shows_the_perceived_area():
    """A lidar run's summary as a record of ``harmonav.study_table``: its outcome and its
    perception's conservatism get their columns; a refused scan is counted as such, never as a
    collision."""
    from conftest import SCENARIOS

    s = harmonav.Scenario.load(SCENARIOS / "lidar" / "paper-world.toml").run().summary
    area = s["perception"]["conservatism"]
    assert s["reached"] and area > 1.0

    def row(world, reached, outcome, conservatism):
        return {"world": world, "generator": "test", "obstacles": 6, "law": "kinematic",
                "speed": "auto", "k": "auto", "sensing": "lidar", "margin": 0.0,
                "reached": reached, "outcome": outcome, "time_s": s["time_s"],
                "path_over_shortest": 1.1, "min_clearance": s["min_clearance"], "collisions": 0,
                "guarantees_held": True, "conservatism": conservatism}

    rows = [row("a", True, s["outcome"]["kind"], area), row("b", False, "scan-refused", None)]
    lines = harmonav.study_table(rows).splitlines()
    assert lines[0].endswith("| not arrived | perceived/true area median / p90 / max |"), lines[0]
    assert "| 1/2 | 2/2 | 0 |" in lines[2] and "| scan-refused 1 |" in lines[2], lines[2]
    assert lines[2].endswith(f"| {area:.2f} / {area:.2f} / {area:.2f} |"), lines[2]
    (cell,) = harmonav.study_cells(rows)
    assert cell["not_arrived"] == {"scan-refused": 1}
    assert list(cell["conservatism"]) == [area] * 3


def test_after_a_refused_scan_the_robot_halts_until_a_scan_is_accepted():
    """Issue 56: a refused scan used to leave the robot commanded as before it, as if the space
    it saw were free; now every command halts it until a scan is accepted."""
    nav = harmonav.Navigator(harmonav.circle([0, 0], 10.0), goal=[8, 0], radius=0.1)
    before = nav.command([-3, 0])
    assert np.linalg.norm(before) > 0
    ranges = np.random.default_rng(0).uniform(0.05, 3.0, 360)
    with pytest.raises(ValueError):
        nav.observe_scan([-3, 0], 0.0, ranges, -math.pi, 2 * math.pi / 360, 3.0, 0.0)
    assert np.array_equal(nav.command([-3, 0]), [0.0, 0.0])
    assert nav.mode == "halted"
    # A copy halts too (pickle replays the refusal), and an accepted scan ends its halt.
    twin = pickle.loads(pickle.dumps(nav))
    assert np.array_equal(twin.command([-3, 0]), [0.0, 0.0])
    twin.observe_scan([-3, 0], 0.0, np.full(360, np.inf), -math.pi, 2 * math.pi / 360, 3.0, 0.0)
    assert np.allclose(pickle.loads(pickle.dumps(twin)).command([-3, 0]), before)
    nav.observe_scan([-3, 0], 0.0, np.full(360, np.inf), -math.pi, 2 * math.pi / 360, 3.0, 0.0)
    assert np.allclose(nav.command([-3, 0]), before)
    assert nav.mode != "halted"

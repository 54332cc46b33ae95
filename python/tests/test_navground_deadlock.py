"""The deadlock rule of the navground adapter's direction task (the Corridor's nominal,
``harmonav.navground.KeepRight``; docs/movers.md §7 and §9) in a three-neighbour pinch: an agent
heading +x, pressed by a peer ahead, one below and one behind and below (every clearance 1 mm),
a wall above. The filter lets only velocities up and up-left through. The old rule (``right``:
the stuck rule always turns the nominal 60° clockwise) stays held for the whole run (the
**negative control**); the default rule (``gap``: the freest direction) gets out. Both only
change the nominal: the filter certifies every command. Skipped without navground."""

import math
import os

import numpy as np
import pytest

if not os.environ.get("HARMONAV_REQUIRE_NAVGROUND"):
    pytest.importorskip("navground")

import harmonav  # noqa: E402
from harmonav import navground as hn  # noqa: E402

# navground's Corridor agents: radius 0.08 m, safety margin 0.02 m, 0.12 m/s, 0.1 s steps.
RADIUS, MARGIN, SPEED, H = 0.08, 0.02, 0.12, 0.1
GAP = 1e-3
#: A straight wall 0.3 m above the agent (the Corridor's walls are 0.6 m apart).
WALL = [(np.array([-10.0, 0.3]), np.array([10.0, 0.3]))]


def pinch():
    """Centres, radii and velocities of the three peers (at rest, the jam's)."""
    d = 2 * RADIUS + MARGIN + GAP
    p = np.array([[d * math.cos(math.radians(a)), d * math.sin(math.radians(a))]
                  for a in (0.0, -90.0, -135.0)])
    return p, np.full(3, RADIUS), np.zeros((3, 2))


def drive(rule: str, periods: int = 150):
    """The direction task's loop of ``HarmonavBehavior`` around one agent: the nominal +x at
    ``SPEED`` turned by ``KeepRight(rule)``, certified by ``MoverFilter`` against the peers
    (reciprocal) and the wall; the peers stay put. Returns the positions and the modes."""
    arrays = pinch()
    movers = [harmonav.Mover(c, RADIUS, SPEED, hn.FLOAT_ERROR, "reciprocal", 0.5)
              for c in arrays[0].tolist()]
    rule_ = hn.KeepRight(rule)
    filt = harmonav.MoverFilter(RADIUS, MARGIN, 0.166, H)
    x = np.zeros(2)
    nominal = np.array([SPEED, 0.0])
    path, modes = [x.copy()], []
    for _ in range(periods):
        turn = rule_.turn(x, nominal, arrays, RADIUS + MARGIN, WALL)
        turned = hn.clockwise(nominal, turn) if turn != 0.0 else nominal
        u, mode = filt.filter(x, turned, movers + hn.wall_movers(x, WALL, RADIUS))
        rule_.after(float(np.hypot(*u)), SPEED, mode != "law", True, H)
        x = x + H * np.asarray(u)
        path.append(x.copy())
        modes.append(mode)
    return np.array(path), modes


def clearance(path):
    p, r, _ = pinch()
    d = np.hypot(path[:, None, 0] - p[None, :, 0], path[:, None, 1] - p[None, :, 1])
    return (d - RADIUS - MARGIN - r[None, :]).min(axis=1)


def test_the_old_right_turn_stays_held_in_the_pinch():
    path, modes = drive("right")
    # Held for the whole 15 s, pressed until the clearances are within the report error (then
    # the filter says Overwhelmed: no certified velocity but rest is left, and rest is taken).
    assert np.abs(path - path[0]).max() < 2 * GAP, path[-1]
    assert clearance(path).min() > 0.0


def test_the_freest_direction_gets_out():
    path, modes = drive("gap")
    gaps = clearance(path)
    assert gaps.min() > 0.0
    assert path[:, 1].max() < 0.3 - RADIUS - MARGIN + 1e-9  # under the wall, margin kept
    out = np.flatnonzero(gaps > 0.05)
    assert out.size, f"held: ended at {path[-1]}"
    # It is held for 1 s, then goes up and passes over the peer ahead (measured: out at 6 s).
    assert out[0] < 80, out[0]
    assert path[-1, 0] > 0.5, path[-1]  # past the peer ahead, on its way
    assert "overwhelmed" not in modes


def test_the_default_rule_is_gap_and_rules_are_checked():
    assert hn.KeepRight().rule == "gap"
    with pytest.raises(ValueError):
        hn.KeepRight("left")
    assert hn.escape_turn(np.zeros(2), np.zeros(2), pinch(), WALL, RADIUS + MARGIN) == 0.0


def test_the_free_run_stops_at_a_body_and_a_wall():
    nb, grown = pinch(), RADIUS + MARGIN
    up = hn.free_run(np.zeros(2), np.array([0.0, 1.0]), nb, WALL, grown, 1.0)
    assert up == pytest.approx(0.3 - grown)
    ahead = hn.free_run(np.zeros(2), np.array([1.0, 0.0]), nb, [], grown, 1.0)
    assert ahead == pytest.approx(GAP)
    away = np.array([-1.0, 1.0]) / math.sqrt(2)
    assert hn.free_run(np.zeros(2), away, nb, [], grown, 1.0) == 1.0

"""``harmonav.navground``: harmonav inside navground (issue 54, item 5; docs/movers.md §9).

Imported only when navground is installed: ``import harmonav`` never imports this module, and
importing it without navground raises an ``ImportError`` that says so. Three navground
components, registered by name when this module is imported (navground's Python register:
``class C(core.Behavior, name=...)``), so that navground's YAML experiments can name them; the
``harmonav`` package also declares them as navground plugins (entry points, python/pyproject.toml)
for ``navground_py`` and ``core.load_plugins()``:

- ``Harmonav`` (:class:`HarmonavBehavior`): a navground ``Behavior`` that runs harmonav. Towards
  a point target it keeps one ``harmonav.Navigator`` per target point (kinematic law, an empty
  disc world around the target, the agent's radius and ``safety_margin``, ``control_period`` =
  navground's time step, ``v_max`` = the target's speed); every period the agent's neighbours
  become ``harmonav.Mover``s with their radius, a position error and a speed bound, and the
  navigator's command is filtered against them (the Rust KeepRight turns its nominal,
  docs/movers.md §7). With a direction target (navground's Corridor) or no target, the nominal
  is navground's target velocity (or rest), turned by the same KeepRight rule written here
  (with the neighbours' velocities, and the walls in the stuck rule's free runs), and
  certified by ``harmonav.MoverFilter``. Every command passes through
  ``compute_cmd_internal``: stops included, nothing bypasses the filter.
- ``HarmonavFilter`` (:class:`MoverFilterModulation`): a navground ``BehaviorModulation`` that
  puts ``harmonav.MoverFilter`` behind any behaviour's command (``post``): "ORCA + filter".
- ``HarmonavSensing`` (:class:`HarmonavSensing`): a ``StateEstimation`` with the information of
  navground's ``Bounded`` (exact centres, radii and velocities within a range), read once per
  step for the whole world and lattice-aware, and the world's straight walls. Without it the
  two components above read the behaviour's ``GeometricState`` (``Bounded``), more slowly.

Straight walls (navground's ``Wall``s, the Corridor's) enter both as hard rows: a wall is given
as a reciprocal mover of share 1 and speed 0, a disc of radius ``WALL_RADIUS`` tangent to the
wall at the robot's foot point, whose row is then exactly the half-plane row of the wall
(``n·u ≥ −β·d/h`` with ``n`` the wall's normal and ``d`` the grown distance to the line). Walls
of finite length are treated as infinite lines (conservative, and exact for the Corridor).

The theorem's assumptions in navground (docs/movers.md §3): (A1) Omni kinematics with
``heading: idle``, so a held velocity is a straight step (an angular speed would make navground
integrate an arc), up to navground's single-precision rounding, which ``position_error``
(``FLOAT_ERROR``) covers and :func:`recovered` keeps from accumulating; (A2) a neighbour never
moves faster than ``mover_speed_bound`` (navground's collision resolution can break it for
agents that collide with each other); (A3) a sensing range far above the reach (navground 0.7's
``Bounded`` can miss a neighbour for the step after it wraps on a lattice: ``HarmonavSensing``
does not); (A4) ``peers: reciprocal`` only when every neighbour runs the same filter at the same
period: navground senses every agent, then computes every command, then moves them all.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

try:
    from navground import core, sim
except ImportError as e:  # pragma: no cover - the message is the point
    raise ImportError(
        "harmonav.navground needs navground (pip install navground); harmonav itself does not"
    ) from e

import harmonav

#: β, the hold's fraction (``harmonav::KINEMATIC_FRACTION``): a clearance keeps ≥ 1 − β of
#: itself over a period.
BETA = 0.5
#: KeepRight (docs/movers.md §7), the Rust constants: anticipation horizon (s) and largest turn.
ANTICIPATION = 3.0
ANTICIPATION_TURN = math.radians(50.0)
#: KeepRight's stuck rule: slower than this fraction of the nominal for STUCK_TIME s, away from
#: the goal, fires: for STUCK_TURN_TIME s the nominal takes the escape of its rule (RULES;
#: STUCK_TURN is the turn of the rules other than ``gap`` and ``gap-held``).
STUCK_RATIO, STUCK_TIME = 0.2, 1.0
STUCK_TURN, STUCK_TURN_TIME = math.radians(60.0), 2.0
#: A straight wall as a disc tangent to it at the robot's foot point (m): its row is the wall's.
WALL_RADIUS = 1.0e3

#: The default bound on a neighbour's position error, m. navground stores positions in single
#: precision (``core.uses_doubles()`` is False by default): each step rounds every position by
#: up to half an ulp (2.4e-7 m per coordinate at 4–8 m), a report error (A2) and a tracking
#: error of the hold (A1) at once, and while two agents press against each other for hundreds
#: of periods these roundings add up (measured: with 1e-6 m, ORCA + filter in the Corridor went
#: 6e-6 m below the margin; with 1e-5 m, never in the benchmark's runs).
FLOAT_ERROR = 1.0e-5

#: Mode codes of the per-period log (``HarmonavBehavior.modes``).
MODES = ("law", "capped", "yielding", "overwhelmed", "refused", "other")
_CODE = {name: i for i, name in enumerate(MODES)}


def mode_code(mode: str) -> int:
    return _CODE.get(mode, _CODE["other"])


def clockwise(u: np.ndarray, angle: float) -> np.ndarray:
    """``u`` turned clockwise by ``angle`` rad."""
    s, c = math.sin(angle), math.cos(angle)
    return np.array([c * u[0] + s * u[1], -s * u[0] + c * u[1]])


def _rule(value: str) -> str:
    if value not in RULES:
        raise ValueError(f"deadlock_rule: expected one of {RULES}, got {value!r}")
    return value


def _peers(value: str) -> str:
    if value not in ("reciprocal", "noncooperative"):
        raise ValueError(f"peers: expected 'reciprocal' or 'noncooperative', got {value!r}")
    return value


def registered(name: str, default, doc: str, check=None) -> property:
    """A navground property (YAML-settable, ``get``/``set`` by name) kept in ``self._<name>``,
    of ``default``'s type, each value passed through ``check`` (default: the type)."""
    kind = type(default)
    check = check or kind
    attr = "_" + name

    def getter(self):
        return getattr(self, attr, default)

    getter.__name__ = name
    getter.__annotations__ = {"return": kind}

    def setter(self, value) -> None:
        setattr(self, attr, check(value))

    return property(core.register(default, doc)(getter), setter)


#: The properties the behaviour and the modulation share.
PEERS_DOC = ("how the neighbours are given: 'reciprocal' (every neighbour runs this filter at "
             "the same period) or 'noncooperative'")
BOUND_DOC = "speed bound V of a non-cooperative neighbour, m/s (negative: the agent's max_speed)"
ERROR_DOC = ("bound on a neighbour's position error, m (default: navground's single-precision "
             "rounding)")


#: The stuck rule's escapes (docs/movers.md §7, each measured in the Corridor, §9), for the
#: STUCK_TURN_TIME s after it fires: ``gap`` (the default, and the Rust navigator's rule) heads
#: for the freest direction (:func:`escape_turn`) chosen afresh every period; ``gap-held``
#: chooses it once when the rule fires and keeps it; ``right`` turns clockwise by STUCK_TURN
#: (KeepRight before issue 54's Corridor fix); ``side`` turns by STUCK_TURN to the side with
#: the longer free run; ``alternate`` turns right, then left, then back on successive firings;
#: ``backoff`` turns right, then backs off.
RULES = ("gap", "gap-held", "right", "side", "alternate", "backoff")
#: How far ahead a free run is measured, in grown radii ``ρ + r`` of the robot (Rust's
#: ``movers::ESCAPE_REACH``): a direction is wholly free once the robot's grown disc can move
#: its own diameter along it.
ESCAPE_REACH = 2.0
#: The candidate escapes: the nominal turned by every multiple of this (Rust's
#: ``ESCAPE_STEP_DEG``).
ESCAPE_STEP = math.radians(15.0)


def free_run(x, direction, neighbours, lines, inflation: float, cap: float) -> float:
    """(eq. free run of docs/movers.md §7, Rust's ``movers::free_run`` with the walls added)
    How far the robot's grown disc (radius ``inflation``) at ``x`` moves along the unit
    ``direction`` before it touches a neighbour's body or a wall's line, at most ``cap``: the
    least root ``t ≥ 0`` of ``|x + t·d − p_j| = inflation + r_j`` over the neighbours
    approached (``(x − p_j)·d < 0``), and of ``(x − p₀)·n + t·d·n = inflation`` over the walls
    approached; 0 for a neighbour already within reach that the direction closes on."""
    t = cap
    p, r, _ = neighbours
    if len(r):
        e = x - p
        b = e @ direction
        c = np.einsum("ij,ij->i", e, e) - (inflation + r) ** 2
        closing = b < 0.0
        disc = b * b - c
        hit = closing & (disc > 0.0)
        if hit.any():
            roots = -b[hit] - np.sqrt(disc[hit])
            t = min(t, max(float(roots.min()), 0.0))
    for p0, p1 in lines:
        tangent = p1 - p0
        length = float(np.hypot(*tangent))
        if length <= 0.0:
            continue
        n = np.array([-tangent[1], tangent[0]]) / length
        side = float((x - p0) @ n)
        if side < 0.0:
            n, side = -n, -side
        dn = float(direction @ n)
        if dn < 0.0:
            t = min(t, max((side - inflation) / -dn, 0.0))
    return t


def escape_turn(x, u, neighbours, lines, inflation: float) -> float:
    """The ``gap`` rule's escape (eq. escape of docs/movers.md §7, Rust's ``movers::escape``
    with the walls added), a clockwise turn of ``u`` (rad, in (−π, π]): over the turns
    ``θ_k = k·ESCAPE_STEP``, the one with the largest ``min(ℓ(θ), L)·(2 + cos θ)/3``
    (``L = ESCAPE_REACH·inflation``),
    ``ℓ(θ)`` the free run (:func:`free_run`) along ``u`` turned by ``θ``: the freest direction,
    forward preferred over sideways over back; ties go to the smaller turn, then to the right.
    0 when ``u = 0`` or no direction is free (the nominal as it is: wait)."""
    speed = float(np.hypot(*u))
    if speed <= 0.0:
        return 0.0
    d = u / speed
    cap = ESCAPE_REACH * inflation
    steps = int(round(math.pi / ESCAPE_STEP))
    best, best_score = 0.0, 0.0
    # Order: 0, +1, −1, +2, −2, …: a strictly better score is needed to move away from 0 and
    # from the right (clockwise, positive) side.
    for k in [0] + [s * j for j in range(1, steps + 1) for s in (1, -1)]:
        if k == -steps:
            continue
        theta = k * ESCAPE_STEP
        score = free_run(x, clockwise(d, theta), neighbours, lines, inflation, cap) * \
            (2.0 + math.cos(theta)) / 3.0
        if score > best_score * (1.0 + 1e-9) + 1e-12:
            best, best_score = theta, score
    return best


class KeepRight:
    """The deadlock rule of docs/movers.md §7 on a nominal velocity (it never touches safety:
    the filter certifies whatever it is given): the anticipation, and the stuck rule with the
    escape ``rule`` (one of :data:`RULES`). For the direction-task and modulation paths; the
    ``Navigator`` path uses the Rust rule."""

    def __init__(self, rule: str = "gap") -> None:
        if rule not in RULES:
            raise ValueError(f"deadlock rule: expected one of {RULES}, got {rule!r}")
        self.rule = rule
        self.slow = 0.0
        self.turning = 0.0
        #: The stuck rule's turn for the current window (None: choose at the next ``turn``).
        self.escape: Optional[float] = None
        #: Triggers since the robot last moved freely for STUCK_TIME, and how long it has.
        self.triggers = 0
        self.moving = 0.0

    def stuck_turn(self, x, u, neighbours, lines, inflation: float) -> float:
        """The stuck rule's clockwise turn now: ``gap``'s afresh, the others' chosen at the
        first period after the rule fired and kept."""
        if self.rule == "gap":
            return escape_turn(x, u, neighbours, lines, inflation)
        if self.escape is None:
            rule = self.rule
            if rule == "right":
                self.escape = STUCK_TURN
            elif rule == "side":
                speed = float(np.hypot(*u))
                if speed <= 0.0:
                    self.escape = STUCK_TURN
                else:
                    d = u / speed
                    cap = ESCAPE_REACH * inflation
                    right = free_run(x, clockwise(d, STUCK_TURN), neighbours, lines, inflation,
                                     cap)
                    left = free_run(x, clockwise(d, -STUCK_TURN), neighbours, lines,
                                    inflation, cap)
                    self.escape = -STUCK_TURN if left > right + 1e-9 else STUCK_TURN
            elif rule == "gap-held":
                self.escape = escape_turn(x, u, neighbours, lines, inflation)
            elif rule == "alternate":
                self.escape = (STUCK_TURN, -STUCK_TURN, math.pi)[(self.triggers - 1) % 3]
            else:  # backoff
                self.escape = STUCK_TURN if self.triggers <= 1 else math.pi
        return self.escape

    def turn(self, x, u, neighbours, inflation: float, lines=()) -> float:
        """The clockwise turn of ``u`` at ``x``, rad (negative: anticlockwise): the stuck
        rule's while it turns, else the anticipation's largest over ``neighbours`` (arrays:
        centres, radii, velocities); ``lines``: the straight walls, for the free runs."""
        if self.turning > 0.0:
            return self.stuck_turn(x, u, neighbours, lines, inflation)
        turn = 0.0
        p, r, v = neighbours
        if len(r) == 0:
            return turn
        e = x - p
        w = u - v
        ww = np.einsum("ij,ij->i", w, w)
        moving = ww > 0.0
        if not moving.any():
            return turn
        e, w, ww, r = e[moving], w[moving], ww[moving], r[moving]
        t = -np.einsum("ij,ij->i", e, w) / ww
        miss = e + t[:, None] * w
        close = (t > 0.0) & (t < ANTICIPATION) & \
            (np.hypot(miss[:, 0], miss[:, 1]) < 2.0 * (inflation + r))
        if close.any():
            turn = max(turn, ANTICIPATION_TURN * (1.0 - float(t[close].min()) / ANTICIPATION))
        return turn

    def after(self, kept: float, wanted: float, yielded: bool, far: bool, h: float) -> None:
        """Updates the memory after a period whose filtered speed was ``kept`` of ``wanted``."""
        self.turning = max(self.turning - h, 0.0)
        slow = yielded and far and kept < STUCK_RATIO * wanted
        self.slow = self.slow + h if slow else 0.0
        self.moving = 0.0 if slow else self.moving + h
        if self.moving >= STUCK_TIME:
            self.triggers = 0
        if self.slow >= STUCK_TIME:
            self.slow, self.turning = 0.0, STUCK_TURN_TIME
            self.triggers += 1
            self.escape = None


def neighbour_reach(radius: float, margin: float, v_max: float, speed_bound: float,
                    error: float, h: float, other_radius, other_speed):
    """Centre distance beyond which a neighbour changes nothing: its row cannot bind any
    ``|u| ≤ v_max`` (``a_j ≤ −v_max``) and KeepRight's anticipation cannot see it
    (``|e| ≥ 2R + T_a(v_max + |v̂|)``). Dropping such neighbours leaves every command bit for
    bit the same, and keeps the Python loop short in large crowds. Works on arrays."""
    grown = radius + margin + other_radius
    row = grown + error + (speed_bound + v_max) * h / BETA
    anticipation = 2.0 * grown + ANTICIPATION * (v_max + other_speed)
    return np.maximum(row, anticipation) + 1e-6


def neighbour_arrays(state) -> tuple:
    """The neighbours of a navground ``GeometricState`` as arrays: centres (n, 2), radii (n,),
    velocities (n, 2)."""
    nbs = getattr(state, "neighbors", None) or []
    if not nbs:
        return np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2))
    p = np.array([nb.position for nb in nbs], dtype=float)
    r = np.array([nb.radius for nb in nbs], dtype=float)
    v = np.array([nb.velocity for nb in nbs], dtype=float)
    return p, r, v


def near_movers(x, arrays, body: tuple, v_max: float, bound: float, error: float, h: float,
                kind: str, tracked: bool = False) -> tuple:
    """The neighbours that can matter (:func:`neighbour_reach`) as ``harmonav.Mover``s (with
    their velocity as the tracked one if ``tracked``), and as arrays ``(centres, radii,
    velocities)`` for the Python KeepRight."""
    p, r, v = arrays
    if len(r) == 0:
        return [], arrays
    radius, margin = body
    dist = np.hypot(p[:, 0] - x[0], p[:, 1] - x[1])
    reach = neighbour_reach(radius, margin, v_max, bound, error, h, r,
                            np.hypot(v[:, 0], v[:, 1]))
    near = dist <= reach
    p, r, v = p[near], r[near], v[near]
    # The tracked velocity feeds KeepRight's anticipation only, never a row.
    vs = v.tolist() if tracked else [None] * len(r)
    movers = [harmonav.Mover(c, s, bound, error, kind, 0.5, w)
              for c, s, w in zip(p.tolist(), r.tolist(), vs)]
    return movers, (p, r, v)


#: The sensing of each agent whose state estimation is a ``HarmonavSensing``, by the identity
#: of its behaviour object (navground hands the modulation the behaviour, not the agent).
_SENSING: dict = {}


class _WorldCache:
    """Every agent's centre, radius and velocity at one world step, read once per step."""

    def __init__(self) -> None:
        self.key = None
        self.p = self.r = self.v = None
        self.periods = (None, None)
        self.lines: list = []

    def refresh(self, world) -> None:
        key = (id(world), world.step, world.time)
        if key == self.key:
            return
        agents = world.agents
        self.key = key
        self.p = np.array([a.position for a in agents], dtype=float).reshape(-1, 2)
        self.r = np.array([a.radius for a in agents], dtype=float)
        self.v = np.array([a.velocity for a in agents], dtype=float).reshape(-1, 2)
        periods = []
        for axis in (0, 1):
            lattice = world.get_lattice(axis)
            periods.append(None if lattice is None else float(lattice[1] - lattice[0]))
        self.periods = tuple(periods)
        self.lines = [(np.asarray(w.line.p1, dtype=float), np.asarray(w.line.p2, dtype=float))
                      for w in world.walls]


_WORLD = _WorldCache()


class HarmonavSensing(sim.StateEstimation, name="HarmonavSensing"):
    """Every other agent whose centre is within ``range`` of this one, with its exact centre,
    radius and velocity: the information of navground's ``Bounded`` estimation, read from the
    world once per step as arrays, and lattice-aware (on a wrapped world, navground 0.7's
    ``Bounded`` can miss a neighbour for the step after it wraps, which breaks (A3)). It fills
    nothing of the behaviour's ``GeometricState``: the harmonav behaviour and the
    ``HarmonavFilter`` modulation read it; give a wrapped behaviour (ORCA) ``Bounded`` as well."""

    def __init__(self, range: float = 5.0) -> None:
        super().__init__()
        self._range = float(range)
        self.arrays = (np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2)))
        self.lines: list = []
        self._behavior = None
        self._index = 0

    @property
    @core.register(5.0, "sensing range (centre to centre), m")
    def range(self) -> float:
        return self._range

    @range.setter
    def range(self, value: float) -> None:
        self._range = float(value)

    def prepare(self, agent, world) -> None:
        self._index = [a._uid for a in world.agents].index(agent._uid)
        self._behavior = agent.behavior
        if self._behavior is not None:
            _SENSING[id(self._behavior)] = self

    def close(self) -> None:
        if self._behavior is not None:
            _SENSING.pop(id(self._behavior), None)
            self._behavior = None

    def update(self, agent, world, state) -> None:
        _WORLD.refresh(world)
        i = self._index
        x = _WORLD.p[i]
        d = _WORLD.p - x
        for axis, period in enumerate(_WORLD.periods):
            if period:
                d[:, axis] -= period * np.round(d[:, axis] / period)
        near = np.hypot(d[:, 0], d[:, 1]) <= self._range
        near[i] = False
        self.arrays = (x + d[near], _WORLD.r[near], _WORLD.v[near])
        self.lines = _WORLD.lines


def sensed_lines(behavior, state) -> list:
    """The straight walls of ``behavior`` (``(p0, p1)``): the world's, from its
    ``HarmonavSensing``, else its ``GeometricState``'s line obstacles."""
    sensing = _SENSING.get(id(behavior))
    if sensing is not None:
        return sensing.lines
    return [(np.asarray(s.p1, dtype=float), np.asarray(s.p2, dtype=float))
            for s in getattr(state, "line_obstacles", [])]


def sensed_arrays(behavior, state) -> tuple:
    """The neighbours of ``behavior``: from its ``HarmonavSensing`` if it has one, else from its
    navground ``GeometricState``."""
    sensing = _SENSING.get(id(behavior))
    if sensing is not None:
        return sensing.arrays
    return neighbour_arrays(state)


def wall_movers(x, lines, radius: float):
    """Each straight wall (``(p0, p1)``) as a hard row: a reciprocal mover of share 1 and speed
    0, a disc of radius ``WALL_RADIUS`` tangent to the wall's line at the robot's foot point on
    the robot's side. ``[]`` for a wall the robot is not in front of (its foot point outside
    the segment by more than the robot's radius would not matter here: walls are long)."""
    out = []
    for p0, p1 in lines:
        t = p1 - p0
        length = float(np.hypot(*t))
        if length <= 0.0:
            continue
        t = t / length
        n = np.array([-t[1], t[0]])
        side = float((x - p0) @ n)
        if side < 0.0:
            n, side = -n, -side
        foot = x - side * n
        out.append(harmonav.Mover(foot - WALL_RADIUS * n, WALL_RADIUS, 0.0,
                                  kind="reciprocal", share=1.0))
    return out


class _Log:
    """Per-period counters and a compact log of modes (one byte a period). ``outside`` counts
    the uncertified commands issued while every reported body was still farther than the
    margin (a clearance within the position error ``ε``: navground's single-precision rounding
    of clearances that decayed towards the margin), ``least`` is the least such clearance."""

    def __init__(self) -> None:
        self.modes = bytearray()
        self.counts = [0] * len(MODES)
        self.outside = 0

    def add(self, mode: str, clearance: float = -1.0) -> None:
        code = mode_code(mode)
        self.modes.append(code)
        self.counts[code] += 1
        if mode == "overwhelmed" and clearance >= 0.0:
            self.outside += 1

    def summary(self) -> dict:
        out = {name: self.counts[i] for i, name in enumerate(MODES)}
        out["overwhelmed_outside_margin"] = self.outside
        return out


def least_clearance(x, movers: list, grown: float) -> float:
    """The least ``|x − p̂_j| − (radius + margin + r_j)`` over ``movers`` (walls included)."""
    return min((float(np.hypot(*(x - m.centre))) - grown - m.radius for m in movers),
               default=float("inf"))


def recovered(mover_filter, x, u, movers: list, grown: float):
    """After an ``Overwhelmed`` command: the velocity that leads out of every reciprocal mover
    (and wall) whose reported clearance has fallen to 0 or below, instead of only not closing in.

    The filter's hard rows keep ``u = 0`` feasible with ``max(d, 0)``, so once a clearance
    rounds below 0 they only forbid closing in (``n·u ≥ 0``), and nothing brings it back:
    navground's single-precision integration then drifts it further (a velocity component
    smaller than half an ulp of the position, 2.4e-7 m at 4–8 m, is dropped every step, so
    sliding along a neighbour closes in by up to that much per step, systematically). Such a
    mover is given here as non-cooperative with speed bound 0, whose row
    ``n·u ≥ −β·d/h > 0`` leads out. The command stays uncertified (Theorem 1 starts from
    ``d > 0``): only what it does changes."""
    changed = []
    for m in movers:
        d = float(np.hypot(*(x - m.centre))) - grown - m.radius - m.error
        if m.kind == "reciprocal" and d <= 0.0:
            changed.append(harmonav.Mover(m.centre, m.radius, 0.0, m.error))
        else:
            changed.append(m)
    try:
        v, _ = mover_filter.filter(x, u, changed)
    except ValueError:
        return u
    return v


class HarmonavBehavior(core.Behavior, name="Harmonav"):
    """harmonav's kinematic law and certified mover filter as a navground behaviour."""

    def __init__(self, kinematics: Optional[core.Kinematics] = None, radius: float = 0.0):
        super().__init__(kinematics, radius)
        self._state = core.GeometricState()
        self._navigators: dict = {}
        self._filters: dict = {}
        self._keep_right = KeepRight()
        self.log = _Log()

    # --- YAML-settable properties ---------------------------------------------------------

    peers = registered("peers", "reciprocal", PEERS_DOC, _peers)
    mover_speed_bound = registered("mover_speed_bound", -1.0, BOUND_DOC)
    position_error = registered("position_error", FLOAT_ERROR, ERROR_DOC)
    world_radius = registered("world_radius", 10.0,
                              "radius of the empty disc world around each target, m")
    use_filter = registered("use_filter", True, "filter the commands against the neighbours "
                            "(False: a negative control, harmonav's law alone)")
    tracked_velocity = registered(
        "tracked_velocity", False, "give the navigator's movers the neighbours' velocities "
        "(KeepRight's anticipation only; off: a neighbour is anticipated at rest, which "
        "measured better in Cross, Antipodal and the mixed crowd)")
    comfort = registered(
        "comfort", 0.0, "distance kept beyond the safety margin from non-cooperative "
        "neighbours where possible, m (harmonav.Navigator's comfort=: the nominal command only, "
        "the filter still certifies every command; docs/movers.md §7)")
    deadlock_rule = registered(
        "deadlock_rule", "gap", "the stuck rule's escape on a direction task (the Corridor): "
        "'gap' (the freest direction, as the Rust navigator), 'gap-held', 'right' (KeepRight "
        "before the Corridor fix), 'side', 'alternate', 'backoff' (docs/movers.md §7)", _rule)

    # --- navground hooks ------------------------------------------------------------------

    def get_environment_state(self) -> core.EnvironmentState:
        return self._state

    def speed_bound(self) -> float:
        bound = self.mover_speed_bound
        return bound if bound >= 0.0 else float(self.max_speed)

    def movers(self, x: np.ndarray, v_max: float, h: float) -> tuple:
        """The neighbours as harmonav movers (those that can matter, see
        :func:`neighbour_reach`), and as ``(centre, radius, velocity)`` for KeepRight."""
        return near_movers(x, sensed_arrays(self, self._state),
                           (float(self.radius), float(self.safety_margin)), v_max,
                           self.speed_bound(), self.position_error, h, self.peers,
                           self.tracked_velocity)

    def navigator(self, goal: np.ndarray, x: np.ndarray, speed: float, h: float):
        comfort = float(self.comfort)
        key = (round(float(goal[0]), 6), round(float(goal[1]), 6), round(speed, 9), h, comfort)
        nav = self._navigators.get(key)
        if nav is None:
            reach = max(self.world_radius, 3.0 * float(np.hypot(*(x - goal))))
            nav = harmonav.Navigator(harmonav.circle(goal, reach), goal, law="kinematic",
                                     radius=float(self.radius),
                                     margin=float(self.safety_margin), control_period=h,
                                     v_max=speed, comfort=comfort)
            self._navigators[key] = nav
        return nav

    def mover_filter(self, v_max: float, h: float):
        key = (v_max, h)
        f = self._filters.get(key)
        if f is None:
            f = harmonav.MoverFilter(float(self.radius), float(self.safety_margin), v_max, h)
            self._filters[key] = f
        return f

    def compute_cmd_internal(self, time_step: float) -> core.Twist2:
        h = float(time_step)
        x = np.asarray(self.position, dtype=float)
        grown = float(self.radius) + float(self.safety_margin)
        speed = float(self.get_target_speed()) or float(self.optimal_speed)
        speed = min(speed, float(self.max_speed))
        movers, plain = self.movers(x, max(speed, float(self.max_speed)), h) if self.use_filter \
            else ([], (np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2))))
        movers += wall_movers(x, sensed_lines(self, self._state), float(self.radius))
        point = self.get_target_position(core.Frame.absolute)
        if point is not None and not self.check_if_target_satisfied() and speed > 0.0:
            nav = self.navigator(np.asarray(point, dtype=float), x, speed, h)
            try:
                nav.set_movers(movers)
                u = nav.command(x)
                mode = nav.mode
                least = -1.0
                if mode == "overwhelmed":
                    least = least_clearance(x, movers, grown)
                    u = recovered(self.mover_filter(speed, h), x, u, movers, grown)
                self.log.add(mode, least)
            except ValueError:
                # The robot's disc overlaps a reported body (InMover: A3 or A2 broken): no
                # certified command exists; it rests.
                u = np.zeros(2)
                self.log.add("refused")
            return self.twist_towards_velocity(u)
        # A direction task (navground's Corridor), a reached target or none: the nominal is
        # navground's target velocity (or rest), turned by KeepRight, certified by MoverFilter.
        nominal = np.asarray(self.get_target_velocity(core.Frame.absolute), dtype=float)
        if point is not None or not np.all(np.isfinite(nominal)):
            nominal = np.zeros(2)
        v_max = float(self.max_speed)
        wanted = float(np.hypot(*nominal))
        if self._keep_right.rule != self.deadlock_rule:
            self._keep_right = KeepRight(self.deadlock_rule)
        turn = self._keep_right.turn(x, nominal, plain,
                                     float(self.radius) + float(self.safety_margin),
                                     sensed_lines(self, self._state))
        turned = clockwise(nominal, turn) if turn != 0.0 else nominal
        try:
            u, mode = self.mover_filter(v_max, h).filter(x, turned, movers)
        except ValueError:
            u, mode = np.zeros(2), "refused"
        least = -1.0
        if mode == "overwhelmed":
            least = least_clearance(x, movers, grown)
            u = recovered(self.mover_filter(v_max, h), x, u, movers, grown)
        self.log.add(mode, least)
        self._keep_right.after(float(np.hypot(*u)), wanted, mode != "law", wanted > 0.0, h)
        return self.twist_towards_velocity(u)


class MoverFilterModulation(core.BehaviorModulation, name="HarmonavFilter"):
    """``harmonav.MoverFilter`` behind any navground behaviour: the behaviour's command (a
    twist, its velocity in the world frame) is certified against the neighbours of the
    behaviour's ``GeometricState`` (and its straight walls) for the agent's radius,
    ``safety_margin``, ``max_speed`` and the time step. ``keep_right`` (default off) turns the
    behaviour's command by KeepRight first (docs/movers.md §7)."""

    def __init__(self) -> None:
        super().__init__()
        self._rule = KeepRight()
        self._filter = None
        self.log = _Log()

    peers = registered("peers", "reciprocal", PEERS_DOC, _peers)
    mover_speed_bound = registered("mover_speed_bound", -1.0, BOUND_DOC)
    position_error = registered("position_error", FLOAT_ERROR, ERROR_DOC)
    keep_right = registered("keep_right", False,
                            "turn the behaviour's command by KeepRight before the filter")

    def post(self, behavior: core.Behavior, time_step: float, cmd: core.Twist2) -> core.Twist2:
        h = float(time_step)
        state = behavior.environment_state
        x = np.asarray(behavior.position, dtype=float)
        radius, margin = float(behavior.radius), float(behavior.safety_margin)
        v_max = float(behavior.max_speed)
        if self._filter is None or self._filter.control_period != h:
            self._filter = harmonav.MoverFilter(radius, margin, v_max, h)
        bound = self.mover_speed_bound if self.mover_speed_bound >= 0.0 else v_max
        nominal = np.asarray(behavior.to_frame(cmd, core.Frame.absolute).velocity, dtype=float)
        movers, plain = near_movers(x, sensed_arrays(behavior, state), (radius, margin), v_max,
                                    bound, self.position_error, h, self.peers)
        lines = sensed_lines(behavior, state)
        movers += wall_movers(x, lines, radius)
        turned = nominal
        if self.keep_right:
            turn = self._rule.turn(x, nominal, plain, radius + margin, lines)
            if turn != 0.0:
                turned = clockwise(nominal, turn)
        try:
            u, mode = self._filter.filter(x, turned, movers)
        except ValueError:
            u, mode = np.zeros(2), "refused"
        least = -1.0
        if mode == "overwhelmed":
            least = least_clearance(x, movers, radius + margin)
            u = recovered(self._filter, x, u, movers, radius + margin)
        self.log.add(mode, least)
        if self.keep_right:
            wanted = float(np.hypot(*nominal))
            self._rule.after(float(np.hypot(*u)), wanted, mode != "law", wanted > 0.0, h)
        if mode == "law":
            return cmd
        return behavior.twist_towards_velocity(u)


__all__ = ["HarmonavBehavior", "MoverFilterModulation", "HarmonavSensing", "KeepRight", "MODES"]

#!/usr/bin/env python3
"""Issue 53, item 5: harmonav's differential-drive law against navground's HL (docs/unicycle.md
§9; bench/diff/README.md has the command).

Seeded disc worlds: a disc arena of radius 5 m, 6–12 circular obstacles (radius 0.25–0.6 m, half
of them within 1 m of the start–goal line, grown shapes 4 cm apart at least), start and goal
about 8 m apart on opposite sides. A disc robot of radius 0.18 m, safety margin 0.05 m,
``v_max`` = 0.5 m/s, ``ω_max`` = 2 rad/s, control at 10 Hz, every obstacle known. Start
headings: ``random`` (seeded, uniform) and ``away`` (facing straight away from the goal).

Entries:

- ``harmonav``: ``harmonav.Navigator(..., base="diff", v_max, omega_max)``, every obstacle
  given with ``add_obstacle``, driven by ``nav.command_pose(x, yaw)`` → ``(v, ω)``, each held on
  the exact unicycle arc for the period.
- ``holonomic``: the same navigator with the default base, ``command(x)`` held as a straight
  step (the heading plays no part).
- ``HL`` (navground 0.7's HL, ``2WDiff`` kinematics: wheel axis 0.5 m, wheel speed 0.5 m/s,
  ``max_angular_speed`` 2 rad/s, forward only) and ``HL-Ahead`` (the ``Ahead`` kinematics: a
  forward-only unicycle with the box limits ``v ≤ 0.5``, ``|ω| ≤ 2`` that harmonav's base has;
  2WDiff's wheel limit is the diamond ``|v| + 0.25|ω| ≤ 0.5``), in navground's own loop
  (``World.update(0.1)``, control period 0.1 s), the obstacles as navground discs, the arena as
  64 walls circumscribing its circle, ``Bounded`` sensing over 20 m (everything known), a
  ``Waypoints`` task with tolerance 1 cm, HL's defaults otherwise (horizon 5 m).
- ``naive`` (negative control, the design note's "naive-uniform"): turn towards the holonomic
  navigator's held command ``u`` (``ω = 4φ``) and drive at its speed ``|u|`` whatever the
  heading, ``(v, ω)`` scaled together into the limits, no arc certificate.

Judged the same way for every entry: each period's motion is the exact unicycle arc (navground
integrates the same arc: measured, the chord of a step lies along the mid-period heading), the
body clearance to the true discs and arena circle (navground's robots: to its walls) sampled at
``ARC_POINTS`` points of the arc (≤ 0.25 mm apart at 0.5 m/s); a contact is a clearance ≤ 0.
navground's own collision events are counted too. Arrival: the centre within 1 cm of the goal
within 120 s; time is the first such time, path the arc length driven until then. The shortest
path is the tangent graph's among the discs grown by radius + margin.
"""

from __future__ import annotations

import argparse
import heapq
import json
import math
import multiprocessing as mp
import os
import statistics
import sys
import time

import numpy as np

import harmonav

ARENA = 5.0
RADIUS = 0.18
MARGIN = 0.05
V_MAX = 0.5
OMEGA_MAX = 2.0
PERIOD = 0.1
T_MAX = 120.0
GOAL_TOL = 0.01
#: The design note's arrival tolerance (time to it is reported too: the approach's last 14 cm
#: are each law's braking).
NEAR_TOL = 0.15
ARC_POINTS = 201
#: A clearance below the margin by more than this is an entry into the grown shapes (navground
#: stores positions in single precision: 2.4e-7 m at 4 m).
MARGIN_TOL = 1e-6
WHEEL_AXIS = 2.0 * V_MAX / OMEGA_MAX  # 2WDiff: ω_max = 2·(wheel speed)/axis
HL_RANGE = 20.0
ARENA_WALLS = 64
#: The naive law's turn gain (harmonav's TURN_GAIN until 2026-12-06; 10 since, docs/unicycle.md section 11).
NAIVE_GAIN = 4.0

ENTRIES = ("harmonav", "holonomic", "HL", "HL-Ahead", "naive")
HEADINGS = ("random", "away")


# --- worlds ---------------------------------------------------------------------------------


def make_world(seed: int, family: str = "uniform") -> dict:
    """One seeded world: obstacles ``(cx, cy, r)``, start, goal and a random start yaw.
    ``uniform``: every disc uniform over the inner disc of radius 3.6 m; ``line``: half of them
    centred within 1 m of the start–goal segment (head-on encounters)."""
    rng = np.random.default_rng((1000 if family == "uniform" else 2000) + seed)
    a = rng.uniform(0.0, 2.0 * math.pi)
    b = a + math.pi + rng.uniform(-0.3, 0.3)
    start = 4.0 * np.array([math.cos(a), math.sin(a)])
    goal = 4.0 * np.array([math.cos(b), math.sin(b)])
    n = int(rng.integers(6, 13))
    grown = RADIUS + 0.05  # the default margin: the worlds do not depend on --margin
    discs: list = []
    tries = 0
    while len(discs) < n and tries < 20000:
        tries += 1
        r = rng.uniform(0.25, 0.6)
        if family == "line" and len(discs) < n // 2:  # near the start–goal line
            t = rng.uniform(0.2, 0.8)
            normal = np.array([-(goal - start)[1], (goal - start)[0]])
            normal /= np.linalg.norm(normal)
            c = start + t * (goal - start) + rng.uniform(-1.0, 1.0) * normal
        else:
            rho, phi = 3.6 * math.sqrt(rng.uniform()), rng.uniform(0.0, 2.0 * math.pi)
            c = rho * np.array([math.cos(phi), math.sin(phi)])
        if np.linalg.norm(c) + r > ARENA - 2.0 * grown - 0.3:
            continue
        if min(np.linalg.norm(c - start), np.linalg.norm(c - goal)) < r + grown + 0.4:
            continue
        if any(np.linalg.norm(c - np.array(d[:2])) < r + d[2] + 2.0 * grown + 0.04
               for d in discs):
            continue
        discs.append((float(c[0]), float(c[1]), float(r)))
    yaw = float(rng.uniform(-math.pi, math.pi))
    return dict(seed=seed, family=family, discs=discs, start=start.tolist(),
                goal=goal.tolist(), yaw=yaw)


def start_yaw(world: dict, heading: str) -> float:
    if heading == "random":
        return world["yaw"]
    d = np.asarray(world["start"]) - np.asarray(world["goal"])
    return math.atan2(d[1], d[0])


def wall_lines() -> list:
    """The arena as ``ARENA_WALLS`` walls circumscribing its circle."""
    rv = ARENA / math.cos(math.pi / ARENA_WALLS)
    pts = [(rv * math.cos(2 * math.pi * (k + 0.5) / ARENA_WALLS),
            rv * math.sin(2 * math.pi * (k + 0.5) / ARENA_WALLS)) for k in range(ARENA_WALLS)]
    return [(pts[k], pts[(k + 1) % ARENA_WALLS]) for k in range(ARENA_WALLS)]


# --- geometry -------------------------------------------------------------------------------


def arc_points(x, yaw: float, v: float, omega: float, h: float, n: int = ARC_POINTS):
    """Points (n, 2) of the exact unicycle arc held for ``h`` and the end pose."""
    t = np.linspace(0.0, h, n)
    a = omega * t
    with np.errstate(invalid="ignore", divide="ignore"):
        sinc = np.where(np.abs(a) > 1e-9, np.sin(a / 2) / np.where(a == 0, 1, a / 2), 1.0)
    ell = v * t * sinc
    pts = np.stack([x[0] + ell * np.cos(yaw + a / 2), x[1] + ell * np.sin(yaw + a / 2)], axis=1)
    return pts, pts[-1].copy(), yaw + omega * h


def clearance_to_discs_and_circle(pts: np.ndarray, discs: np.ndarray) -> float:
    """Least body clearance (the disc of ``RADIUS``) of ``pts`` to the discs and arena circle."""
    c = ARENA - np.hypot(pts[:, 0], pts[:, 1]) - RADIUS
    least = float(c.min())
    if len(discs):
        d = np.hypot(pts[:, None, 0] - discs[None, :, 0], pts[:, None, 1] - discs[None, :, 1])
        least = min(least, float((d - discs[None, :, 2] - RADIUS).min()))
    return least


def clearance_to_walls(pts: np.ndarray, discs: np.ndarray, walls: np.ndarray) -> float:
    """Least body clearance of ``pts`` to the discs and the wall segments (navground's arena)."""
    least = float("inf")
    if len(discs):
        d = np.hypot(pts[:, None, 0] - discs[None, :, 0], pts[:, None, 1] - discs[None, :, 1])
        least = float((d - discs[None, :, 2] - RADIUS).min())
    a, b = walls[:, 0], walls[:, 1]
    ab = b - a
    ap = pts[:, None, :] - a[None]
    s = np.clip(np.einsum("pwk,wk->pw", ap, ab) / np.einsum("wk,wk->w", ab, ab), 0.0, 1.0)
    q = a[None] + s[..., None] * ab[None]
    dist = np.hypot(pts[:, None, 0] - q[..., 0], pts[:, None, 1] - q[..., 1])
    return min(least, float((dist - RADIUS).min()))


def segment_blocked(p, q, circles, skip=()) -> bool:
    for i, (c, r) in enumerate(circles):
        if i in skip:
            continue
        d = q - p
        dd = float(d @ d)
        s = 0.0 if dd == 0.0 else min(1.0, max(0.0, float((c - p) @ d) / dd))
        if np.linalg.norm(p + s * d - c) < r - 1e-7:
            return True
    return False


def shortest_path(world: dict, grow: float) -> float:
    """Length of the shortest path from start to goal for a point among the discs grown by
    ``grow`` (tangent graph: bitangents and point tangents, arcs along each circle)."""
    circles = [(np.array(d[:2]), d[2] + grow) for d in world["discs"]]
    s, g = np.asarray(world["start"], float), np.asarray(world["goal"], float)
    nodes = [s, g]
    on = [None, None]  # circle index of each node, or None
    edges: dict = {0: [], 1: []}

    def add(p, circle):
        nodes.append(p)
        on.append(circle)
        edges[len(nodes) - 1] = []
        return len(nodes) - 1

    def link(i, j, skip):
        if not segment_blocked(nodes[i], nodes[j], circles, skip):
            w = float(np.linalg.norm(nodes[i] - nodes[j]))
            edges[i].append((j, w))
            edges[j].append((i, w))

    if not segment_blocked(s, g, circles):
        return float(np.linalg.norm(g - s))
    for pi in (0, 1):
        p = nodes[pi]
        for ci, (c, r) in enumerate(circles):
            d = float(np.linalg.norm(p - c))
            if d <= r:
                continue
            base = math.atan2(*(p - c)[::-1])
            for sgn in (1, -1):
                ang = base + sgn * math.acos(r / d)
                k = add(c + r * np.array([math.cos(ang), math.sin(ang)]), ci)
                link(pi, k, (ci,))
    for i in range(len(circles)):
        for j in range(i + 1, len(circles)):
            (c1, r1), (c2, r2) = circles[i], circles[j]
            d = float(np.linalg.norm(c2 - c1))
            phi = math.atan2(*(c2 - c1)[::-1])
            for inner in (False, True):
                ratio = ((r1 + r2) if inner else (r1 - r2)) / d
                if abs(ratio) >= 1.0:
                    continue
                for sgn in (1, -1):
                    ang = phi + sgn * math.acos(ratio)
                    n = np.array([math.cos(ang), math.sin(ang)])
                    a = add(c1 + r1 * n, i)
                    b = add(c2 - r2 * n if inner else c2 + r2 * n, j)
                    link(a, b, (i, j))
    for ci, (c, r) in enumerate(circles):
        idx = [k for k in range(len(nodes)) if on[k] == ci]
        idx.sort(key=lambda k: math.atan2(*(nodes[k] - c)[::-1]))
        angs = [math.atan2(*(nodes[k] - c)[::-1]) for k in idx]
        for m in range(len(idx)):
            k0, k1 = idx[m], idx[(m + 1) % len(idx)]
            da = (angs[(m + 1) % len(idx)] - angs[m]) % (2 * math.pi)
            if k0 != k1:
                edges[k0].append((k1, r * da))
                edges[k1].append((k0, r * da))
    dist = {0: 0.0}
    heap = [(0.0, 0)]
    while heap:
        d, k = heapq.heappop(heap)
        if k == 1:
            return d
        if d > dist.get(k, float("inf")):
            continue
        for j, w in edges[k]:
            nd = d + w
            if nd < dist.get(j, float("inf")):
                dist[j] = nd
                heapq.heappush(heap, (nd, j))
    return float("nan")


def wrap_angle(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


# --- the harmonav entries -------------------------------------------------------------------


def navigator(world: dict, base: str):
    kw = dict(base="diff", v_max=V_MAX, omega_max=OMEGA_MAX) if base == "diff" else \
        dict(v_max=V_MAX)
    nav = harmonav.Navigator(harmonav.circle([0.0, 0.0], ARENA), goal=world["goal"],
                             law="kinematic", radius=RADIUS, margin=MARGIN,
                             control_period=PERIOD, **kw)
    for cx, cy, r in world["discs"]:
        nav.add_obstacle(harmonav.circle([cx, cy], r))
    return nav


def run_harmonav(world: dict, entry: str, heading: str) -> dict:
    """``harmonav`` (command_pose on the arc), ``holonomic`` (command, straight steps) or
    ``naive`` (turn towards the holonomic command and drive)."""
    discs = np.asarray(world["discs"], float).reshape(-1, 3)
    goal = np.asarray(world["goal"], float)
    x = np.asarray(world["start"], float)
    yaw = start_yaw(world, heading)
    nav = navigator(world, "diff" if entry == "harmonav" else "holonomic")
    cost, least, contacts, below, path = [], float("inf"), 0, 0, 0.0
    max_v = max_w = 0.0
    steers: dict = {}
    arrived, t, error = None, 0.0, None
    steps = int(round(T_MAX / PERIOD))
    near = None
    for _ in range(steps + 1):
        if near is None and np.linalg.norm(x - goal) <= NEAR_TOL:
            near = t
        if np.linalg.norm(x - goal) <= GOAL_TOL:
            arrived = t
            break
        if t >= T_MAX - 1e-9:
            break
        try:
            if entry == "harmonav":
                t0 = time.perf_counter_ns()
                v, w = nav.command_pose(x, yaw)
                cost.append(time.perf_counter_ns() - t0)
                steers[nav.steer] = steers.get(nav.steer, 0) + 1
            else:
                t0 = time.perf_counter_ns()
                u = nav.command(x)
                cost.append(time.perf_counter_ns() - t0)
                if entry == "holonomic":
                    speed = float(np.hypot(*u))
                    v, w = speed, 0.0
                    if speed > 0.0:
                        yaw = math.atan2(u[1], u[0])
                else:
                    phi = wrap_angle(math.atan2(u[1], u[0]) - yaw) if np.any(u) else 0.0
                    v, w = float(np.hypot(*u)), NAIVE_GAIN * phi
                    scale = min(1.0, OMEGA_MAX / abs(w)) if w else 1.0
                    v, w = min(v * scale, V_MAX), w * scale
        except ValueError as e:  # the disc overlaps a known obstacle (the naive law)
            error = str(e)
            break
        max_v, max_w = max(max_v, v), max(max_w, abs(w))
        pts, x, yaw = arc_points(x, yaw, v, w, PERIOD)
        c = clearance_to_discs_and_circle(pts, discs)
        least = min(least, c)
        contacts += c <= 0.0
        below += c < MARGIN - MARGIN_TOL
        path += abs(v) * PERIOD
        t += PERIOD
    out = dict(arrived=arrived is not None, time=arrived, time_to_15cm=near, path=path, least_clearance=least,
               contact_periods=int(contacts), below_margin_periods=int(below),
               commands=len(cost), max_v=max_v,
               max_omega=max_w, error=error)
    if cost:
        us = np.asarray(cost) / 1000.0
        out.update(cost_mean_us=float(us.mean()), cost_median_us=float(np.median(us)),
                   cost_p99_us=float(np.percentile(us, 99)))
    if steers:
        out["steer"] = steers
    return out


# --- navground -------------------------------------------------------------------------------


def navground_yaml(world: dict, entry: str, heading: str) -> str:
    if entry == "HL":
        kin = (f"{{type: 2WDiff, wheel_axis: {WHEEL_AXIS}, max_speed: {V_MAX}, "
               f"max_angular_speed: {OMEGA_MAX}}}")
    else:
        kin = f"{{type: Ahead, max_speed: {V_MAX}, max_angular_speed: {OMEGA_MAX}}}"
    lines = ["obstacles:"]
    for cx, cy, r in world["discs"]:
        lines.append(f"  - {{position: [{cx!r}, {cy!r}], radius: {r!r}}}")
    lines.append("walls:")
    for p, q in wall_lines():
        lines.append(f"  - {{line: [[{p[0]!r}, {p[1]!r}], [{q[0]!r}, {q[1]!r}]]}}")
    sx, sy = world["start"]
    gx, gy = world["goal"]
    lines += [
        "agents:",
        f"  - position: [{sx!r}, {sy!r}]",
        f"    orientation: {start_yaw(world, heading)!r}",
        f"    radius: {RADIUS}",
        f"    control_period: {PERIOD}",
        f"    kinematics: {kin}",
        f"    behavior: {{type: HL, optimal_speed: {V_MAX}, safety_margin: {MARGIN}}}",
        f"    state_estimation: {{type: Bounded, range: {HL_RANGE}}}",
        f"    task: {{type: Waypoints, waypoints: [[{gx!r}, {gy!r}]], tolerance: {GOAL_TOL}}}",
    ]
    return "\n".join(lines) + "\n"


def run_navground(world: dict, entry: str, heading: str) -> dict:
    from navground import sim

    w = sim.load_world(navground_yaml(world, entry, heading))
    agent = w.agents[0]
    discs = np.asarray(world["discs"], float).reshape(-1, 3)
    walls = np.asarray(wall_lines(), float)
    goal = np.asarray(world["goal"], float)
    x = np.asarray(agent.position, float)
    yaw = float(agent.orientation)
    least, contacts, below, events, path = float("inf"), 0, 0, 0, 0.0
    max_v = max_w = 0.0
    arrived, t = None, 0.0
    steps = int(round(T_MAX / PERIOD))
    wall_s = 0.0
    near = None
    for _ in range(steps + 1):
        if near is None and np.linalg.norm(x - goal) <= NEAR_TOL:
            near = t
        if np.linalg.norm(x - goal) <= GOAL_TOL + 1e-6:
            arrived = t
            break
        if t >= T_MAX - 1e-9:
            break
        t0 = time.perf_counter()
        w.update(PERIOD)
        wall_s += time.perf_counter() - t0
        x1 = np.asarray(agent.position, float)
        yaw1 = float(agent.orientation)
        turn = wrap_angle(yaw1 - yaw)
        chord = float(np.linalg.norm(x1 - x))
        length = chord / (math.sin(turn / 2) / (turn / 2)) if abs(turn) > 1e-9 else chord
        v, om = length / PERIOD, turn / PERIOD
        max_v, max_w = max(max_v, v), max(max_w, abs(om))
        pts, _, _ = arc_points(x, yaw, v, om, PERIOD)
        # The arc from the recorded poses; its end should be the recorded end (navground's own
        # collision resolution would break this: then the end point is judged as well).
        pts = np.vstack([pts, x1])
        c = clearance_to_walls(pts, discs, walls)
        least = min(least, c)
        contacts += c <= 0.0
        below += c < MARGIN - MARGIN_TOL
        events += bool(w.collisions)
        path += length
        x, yaw = x1, yaw1
        t += PERIOD
    return dict(arrived=arrived is not None, time=arrived, time_to_15cm=near, path=path, least_clearance=least,
                contact_periods=int(contacts), below_margin_periods=int(below),
                collision_steps=int(events),
                commands=int(round(t / PERIOD)), max_v=max_v, max_omega=max_w,
                sim_us_per_step=1e6 * wall_s / max(1, round(t / PERIOD)))


# --- the benchmark ---------------------------------------------------------------------------


def run_one(task: tuple) -> tuple:
    seed, entry, heading, family = task
    world = make_world(seed, family)
    if entry.startswith("HL"):
        out = run_navground(world, entry, heading)
    else:
        out = run_harmonav(world, entry, heading)
    out["seed"] = seed
    return entry, heading, out


def ratios(runs: dict, a: str, b: str, key: str) -> list:
    """Per world ``a[key]/b[key]`` where both arrived."""
    out = []
    for seed, ra in runs[a].items():
        rb = runs[b].get(seed)
        if rb and ra["arrived"] and rb["arrived"] and rb[key]:
            out.append(ra[key] / rb[key])
    return out


def q(values: list, p: float):
    return float(np.percentile(values, p)) if values else None


def summarise(results: dict, shortest: dict) -> dict:
    summary = {}
    for cell, runs in results.items():
        entry, heading = cell.split("/")
        rs = list(runs.values())
        n = len(rs)
        times = [r["time"] for r in rs if r["arrived"]]
        s = dict(runs=n, arrived=sum(r["arrived"] for r in rs),
                 runs_with_contact=sum(r["contact_periods"] > 0 for r in rs),
                 runs_below_margin=sum(r["below_margin_periods"] > 0 for r in rs),
                 least_clearance=min(r["least_clearance"] for r in rs),
                 time_median=q(times, 50), time_p90=q(times, 90),
                 max_v=max(r["max_v"] for r in rs), max_omega=max(r["max_omega"] for r in rs))
        if entry.startswith("HL"):
            s["runs_with_collision_event"] = sum(r["collision_steps"] > 0 for r in rs)
        pairs = {"HL": f"HL/{heading}", "HL-Ahead": f"HL-Ahead/{heading}",
                 "holonomic": "holonomic/random"}
        for name, other in pairs.items():
            if other in results and other != cell:
                rt = ratios({cell: runs, other: results[other]}, cell, other, "time")
                s[f"time_over_{name}"] = dict(n=len(rt), median=q(rt, 50), p90=q(rt, 90),
                                              max=max(rt) if rt else None)
                r15 = [a["time_to_15cm"] / b["time_to_15cm"] for seed, a in runs.items()
                       if a["time_to_15cm"] and (b := results[other].get(seed))
                       and b["time_to_15cm"]]
                s[f"time_to_15cm_over_{name}"] = dict(n=len(r15), median=q(r15, 50),
                                                      p90=q(r15, 90))
        rp = [r["path"] / shortest[seed] for seed, r in runs.items() if r["arrived"]]
        s["path_over_shortest"] = dict(median=q(rp, 50), max=max(rp) if rp else None)
        costs = [r["cost_mean_us"] for r in rs if "cost_mean_us" in r]
        if costs:
            s["cost_us"] = dict(mean=statistics.fmean(costs),
                                mean_max=max(costs),
                                median=q([r["cost_median_us"] for r in rs], 50),
                                p99=max(r["cost_p99_us"] for r in rs))
        summary[cell] = s
    return summary


def fmt(x, spec=".2f", none="—"):
    return none if x is None else format(x, spec)


def table(summary: dict) -> str:
    lines = ["| entry | heading | arrived | runs with contact | runs below the margin | "
             "least clearance (mm) | "
             "time median / p90 (s) | time / HL's: median, p90 | time / HL-Ahead's | time / "
             "holonomic: median, p90 | path / shortest: median, max | µs per command: median "
             "(p99) |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for cell, s in summary.items():
        entry, heading = cell.split("/")
        if entry == "holonomic":
            heading = "—"
        contact = f"{s['runs_with_contact']}/{s['runs']}"
        if "runs_with_collision_event" in s:
            contact += f" (navground events: {s['runs_with_collision_event']})"
        hl = s.get("time_over_HL")
        ha = s.get("time_over_HL-Ahead")
        ho = s.get("time_over_holonomic")
        ps = s["path_over_shortest"]
        cost = s.get("cost_us")
        lines.append(
            f"| {entry} | {heading} | {s['arrived']}/{s['runs']} | {contact} | "
            f"{s['runs_below_margin']}/{s['runs']} | "
            f"{1000 * s['least_clearance']:+.1f} | {fmt(s['time_median'], '.1f')} / "
            f"{fmt(s['time_p90'], '.1f')} | "
            + (f"{fmt(hl['median'])}, {fmt(hl['p90'])} (n={hl['n']})" if hl else "—") + " | "
            + (f"{fmt(ha['median'])}, {fmt(ha['p90'])}" if ha else "—") + " | "
            + (f"{fmt(ho['median'])}, {fmt(ho['p90'])} (n={ho['n']})" if ho else "—") + " | "
            f"{fmt(ps['median'], '.3f')}, {fmt(ps['max'], '.3f')} | "
            + (f"{cost['median']:.1f} ({cost['p99']:.0f})" if cost else "—") + " |")
    return "\n".join(lines)


def main(argv=None) -> int:
    global MARGIN
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--worlds", type=int, default=40, help="seeds 0 … N − 1")
    ap.add_argument("--start", type=int, default=0, help="first seed")
    ap.add_argument("--entries", default=",".join(ENTRIES))
    ap.add_argument("--headings", default=",".join(HEADINGS))
    ap.add_argument("--family", default="uniform", choices=("uniform", "line"),
                    help="uniform discs, or half of them on the start–goal line")
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--json", help="write every run and the summary here")
    ap.add_argument("--print-yaml", metavar="SEED", type=int,
                    help="print one world's navground HL world and exit")
    ap.add_argument("--margin", type=float, default=MARGIN,
                    help="safety margin of every entry, m (default 0.05)")
    args = ap.parse_args(argv)
    MARGIN = args.margin
    if args.print_yaml is not None:
        print(navground_yaml(make_world(args.print_yaml, args.family), "HL", "random"))
        return 0
    entries = [e for e in args.entries.split(",") if e]
    headings = [h for h in args.headings.split(",") if h]
    seeds = list(range(args.start, args.start + args.worlds))
    cells = [(e, h) for e in entries for h in (["random"] if e == "holonomic" else headings)]
    todo = [(seed, e, h, args.family) for seed in seeds for e, h in cells]
    results: dict = {f"{e}/{h}": {} for e, h in cells}
    t0 = time.perf_counter()
    with mp.get_context("fork").Pool(args.processes) as pool:
        for k, (e, h, out) in enumerate(pool.imap_unordered(run_one, todo, chunksize=1)):
            results[f"{e}/{h}"][out["seed"]] = out
            if (k + 1) % 50 == 0 or k + 1 == len(todo):
                print(f"{k + 1}/{len(todo)} runs, {time.perf_counter() - t0:.0f} s",
                      file=sys.stderr, flush=True)
    for cell in results:
        results[cell] = dict(sorted(results[cell].items()))
    worlds = {seed: make_world(seed, args.family) for seed in seeds}
    shortest = {seed: shortest_path(w, RADIUS + MARGIN) for seed, w in worlds.items()}
    straight = {seed: float(np.linalg.norm(np.subtract(w["goal"], w["start"])))
                for seed, w in worlds.items()}
    summary = summarise(results, shortest)
    elapsed = time.perf_counter() - t0
    print(table(summary))
    obstacles = [len(w["discs"]) for w in worlds.values()]
    sp = [shortest[s] / straight[s] for s in seeds]
    print(f"\n{len(seeds)} {args.family} worlds (seeds {seeds[0]}–{seeds[-1]}), {min(obstacles)}–"
          f"{max(obstacles)} discs, shortest path / straight line median "
          f"{np.median(sp):.3f} (max {max(sp):.3f}); {len(todo)} runs, {args.processes} "
          f"processes, {elapsed:.0f} s")
    if args.json:
        from importlib.metadata import version

        meta = dict(family=args.family, seeds=[seeds[0], seeds[-1] + 1], processes=args.processes, elapsed=elapsed,
                    navground=version("navground"), harmonav=harmonav.__version__,
                    radius=RADIUS, margin=MARGIN, v_max=V_MAX, omega_max=OMEGA_MAX,
                    period=PERIOD, t_max=T_MAX, goal_tolerance=GOAL_TOL,
                    command=" ".join([os.path.basename(sys.executable)] + sys.argv))
        with open(args.json, "w") as f:
            json.dump(dict(meta=meta, summary=summary, worlds=worlds, shortest=shortest,
                           runs=results), f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())

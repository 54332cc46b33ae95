"""harmonav against navground 0.7 (HL and ORCA) in the same seeded disc worlds, and in two
worlds where a purely reactive planner is known to struggle.

    pip install ./python "navground==0.7.*"      # navground is not a test dependency
    python examples/python/compare_navground.py [--worlds 20] [--markdown]

Every method drives a disc robot of radius 0.1 m from the same start to the same goal in a
disc workspace of radius 5 m.

- harmonav runs each world's scenario with its built-in integrator and its guarantee
  monitors. It senses through the paper's sector (1 m, 60°): an obstacle becomes known only
  when it is seen. Five configurations: both laws (kinematic, K = 1; dynamic, m = 1 kg,
  μ = 10), each with the paper's choices (`k = "paper"`, `damping = "paper"`, `speed =
  "paper"`) and the defaults; and the kinematic default at navground's top speed (`v_max = 1`).
  It arrives within 0.01 m.
- navground's HL and ORCA behaviours get the whole map from the start (discs as `Disc`, the
  non-disc shapes as 1024 line segments of their outlines, the wall as 256),  an omnidirectional robot with
  1 m/s top speed, 100 Hz steps, and arrival within 0.05 m (its target tolerance).

Each run is a record of harmonav's study table, printed by `harmonav.study_table` (the one
tabulation of `cargo xtask quality` and `harmonav.experiment report`): arrival within 120 s,
harmonav's guarantee monitors (navground has
none: 0), runs with a collision (the clearance to a true shape, less the radius, at or below 0),
path length over the shortest path (harmonav's visibility-graph shortest path around the grown
shapes) and time to the goal over the arrivals (median, p90, max), the closest clearance, the
integrator's steps (harmonav), and the cost of one command, timed from Python for both
(`Navigator.command` with every obstacle known, `Behavior.compute_cmd`). The path and time
quantiles are over every run that arrived, one that collided on the way included (ORCA's).
The dynamic law's "time / kinematic (paper speed)" needs a kinematic run with its `k` under the
paper's speed: only the paper's own rows have one, so "dynamic, default" shows "—". Under each
disc table: issue 27's measure, the kinematic default at 1 m/s over HL per world.
"""

import argparse
import json
import pathlib
import statistics
import sys
import tempfile
import time

import numpy as np

import harmonav

try:
    from navground import core
except ImportError:  # pragma: no cover - the comparison needs it, the tests do not
    sys.exit('navground is needed: pip install "navground==0.7.*"')

WORKSPACE_RADIUS = 5.0
ROBOT_RADIUS = 0.1
MAX_TIME = 120.0
# (row, law, k, damping and speed policy, v_max): "paper" is the paper's k, damping and
# speed K√(2Θ); "default" the defaults (speed "auto": full speed, then a constant deceleration,
# at v_max = K√2 = 1.41 m/s); the last row is the default at navground's 1 m/s top speed.
HARMONAV = [
    ("harmonav kinematic, paper", "kinematic", "paper", "paper", None),
    ("harmonav kinematic, default", "kinematic", "auto", "auto", None),
    ("harmonav kinematic, default, 1 m/s", "kinematic", "auto", "auto", 1.0),
    ("harmonav dynamic, paper", "dynamic", "paper", "paper", None),
    ("harmonav dynamic, default", "dynamic", "auto", "auto", None),
]
NAVGROUND = ["HL", "ORCA"]


# --- worlds -----------------------------------------------------------------------------------


def disc_world(m, seed):
    """`m` discs (radius 0.2–0.5 m, 0.35 m apart and from the wall) and a start and goal at
    least 6 m apart, 0.35 m clear of everything. Deterministic in `seed`."""
    rng = np.random.default_rng(seed)
    while True:
        discs = []
        for _ in range(5000):
            if len(discs) == m:
                break
            r = rng.uniform(0.2, 0.5)
            c = rng.uniform(-WORKSPACE_RADIUS, WORKSPACE_RADIUS, 2)
            if WORKSPACE_RADIUS - np.linalg.norm(c) - r < 0.35:
                continue
            if all(np.linalg.norm(c - d) - r - s >= 0.35 for d, s in discs):
                discs.append((c, r))
        if len(discs) < m:
            continue

        def clear(p):
            return WORKSPACE_RADIUS - np.linalg.norm(p) > 0.35 and all(
                np.linalg.norm(p - c) - r > 0.35 for c, r in discs
            )

        for _ in range(1000):
            s, g = rng.uniform(-4.5, 4.5, (2, 2))
            if np.linalg.norm(s - g) >= 6.0 and clear(s) and clear(g):
                shapes = [{"type": "circle", "center": list(c), "radius": r} for c, r in discs]
                return {"name": f"discs-m{m}-seed{seed}", "obstacles": shapes, "start": s, "goal": g}


def concave_star_world():
    """A deep three-lobed star (R(θ) = 1.6 + 0.8 cos 3θ: bays 1.6 m deep between lobes 2.4 m
    long) whose bay at θ = π faces the start: the straight line to the goal runs into it. The
    start is 0.3 m off the symmetry axis (on it, the descent ends at the saddle on the axis)."""
    star = {"type": "star", "center": [0.0, 0.0], "radius": 1.6, "harmonics": [[3, 0.8, 0.0]]}
    return {"name": "concave-star", "obstacles": [star], "start": np.array([-4.0, 0.3]), "goal": np.array([4.2, 0.0])}


def dense_cluster_world():
    """28 discs of radius 0.18 m on a jittered grid around the start–goal line, 0.3–0.42 m
    apart: a maze of narrow gaps (the robot's disc needs 0.2 m)."""
    rng = np.random.default_rng(7)
    shapes = []
    for i in range(7):
        for j in range(4):
            c = np.array([-2.16 + 0.72 * i, -1.08 + 0.72 * j]) + rng.uniform(-0.03, 0.03, 2)
            shapes.append({"type": "circle", "center": list(c), "radius": 0.18})
    return {"name": "dense-cluster", "obstacles": shapes, "start": np.array([-4.0, 0.2]), "goal": np.array([4.0, -0.1])}


def value_toml(v):
    """A string, a number or a (nested) list of numbers in TOML."""
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(value_toml(x) for x in v) + "]"
    return repr(float(v))


def toml(world, law, k, damping, v_max=None):
    """The world as a harmonav scenario file (`damping` also names the speed policy)."""
    lines = [
        f'name = "{world["name"]}"',
        "[workspace]",
        'type = "circle"',
        "center = [0.0, 0.0]",
        f"radius = {WORKSPACE_RADIUS}",
    ]
    for i, o in enumerate(world["obstacles"]):
        lines += ["[[obstacles]]", f'name = "O{i + 1}"']
        for key, value in o.items():
            lines.append(f"{key} = {value_toml(value)}")
    s, g = world["start"], world["goal"]
    lines += [
        "[robot]",
        f'model = "{law}"',
        f"start = {value_toml(s)}",
        f"goal = {value_toml(g)}",
        "mass = 1.0",
        f"radius = {ROBOT_RADIUS}",
        "[sensor]",
        "range = 1.0",
        "aperture_deg = 60.0",
        "[field]",
        f'k = "{k}"',
        "[controller]",
        "gain = 1.0",
        "mu = 10.0",
        f'damping = "{damping}"',
        f'speed = "{damping}"',
    ]
    if v_max is not None:
        lines.append(f"v_max = {v_max}")
    lines += [
        "[sim]",
        "dt = 0.01",
        f"max_time = {MAX_TIME}",
        "goal_tolerance = 0.01",
    ]
    return "\n".join(lines) + "\n"


def shapes(world):
    return [
        harmonav.circle(o["center"], o["radius"])
        if o["type"] == "circle"
        else harmonav.star(o["center"], o["radius"], [tuple(h) for h in o["harmonics"]])
        for o in world["obstacles"]
    ]


def clearance(world_shapes, x):
    """Distance from the robot's disc to the nearest true shape or the wall (N,)."""
    d = WORKSPACE_RADIUS - np.linalg.norm(x, axis=1)
    for s in world_shapes:
        d = np.minimum(d, s.signed_distance(x))
    return d - ROBOT_RADIUS


def path_length(x):
    return float(np.sum(np.linalg.norm(np.diff(x, axis=0), axis=1)))


# --- methods ----------------------------------------------------------------------------------


def run_harmonav(world, tmp, law, k, damping, world_shapes, v_max=None):
    """One harmonav run as a record of the study table (``harmonav.study_table``)."""
    suffix = "" if v_max is None else f"-vmax{v_max}"
    path = pathlib.Path(tmp) / f'{world["name"]}-{law}-{k}{suffix}.toml'
    path.write_text(toml(world, law, k, damping, v_max))
    sc = harmonav.Scenario.load(path)
    shortest, _ = sc.shortest_path()
    res = sc.run()
    s = res.summary
    # The cost of one command with every obstacle known, at the states of the run.
    nav = harmonav.Navigator(
        harmonav.circle([0, 0], WORKSPACE_RADIUS), world["goal"], law=law, radius=ROBOT_RADIUS,
        k=k, damping=damping, speed=damping, v_max=v_max,
    )
    for o in world_shapes:
        nav.add_obstacle(o)
    states = list(zip(res.x[:: max(1, len(res.x) // 500)], res.v[:: max(1, len(res.x) // 500)]))
    t0 = time.perf_counter()
    for x, v in states:
        nav.command(x, v)
    cost = (time.perf_counter() - t0) / len(states) * 1e6
    policy = damping if v_max is None else f"{damping}, v_max {v_max:g} m/s"
    held = all(g["passed"] for g in s["guarantees"] if g["name"] != "reached-goal")
    return record(world, law, policy, k, "sector", bool(s["reached"]),
                  clearance(world_shapes, res.x).min(), path_length(res.x) / shortest,
                  s["time_s"], cost, held, steps=s["steps"] + s["rejected_steps"])


def run_navground(world, kind, world_shapes, shortest):
    """One navground run as a record: it has no guarantee monitors (``guarantees_held`` is
    False) and no integrator steps."""
    b = core.Behavior.make_type(kind)
    b.kinematics = core.kinematics.OmnidirectionalKinematics(max_speed=1.0)
    b.radius = ROBOT_RADIUS
    b.optimal_speed = 1.0
    b.position = tuple(world["start"])
    b.target = core.Target.Point(tuple(world["goal"]), 0.05)
    state = b.environment_state
    state.static_obstacles = [
        core.Disc(tuple(o["center"]), o["radius"]) for o in world["obstacles"] if o["type"] == "circle"
    ]
    outlines = [
        s.outline(1024) for s, o in zip(world_shapes, world["obstacles"]) if o["type"] != "circle"
    ]
    # The wall as an inscribed 256-gon: on the safe side (navground sees it up to 1.5 mm early).
    outlines.append(harmonav.circle([0, 0], WORKSPACE_RADIUS).outline(256))
    state.line_obstacles = [
        core.LineSegment(tuple(p[i]), tuple(p[(i + 1) % len(p)])) for p in outlines for i in range(len(p))
    ]
    dt, xs, spent = 0.01, [np.array(world["start"])], 0.0
    reached = False
    for _ in range(int(MAX_TIME / dt)):
        t0 = time.perf_counter()
        cmd = b.compute_cmd(dt)
        spent += time.perf_counter() - t0
        b.actuate(cmd, dt)
        xs.append(np.array(b.position))
        if b.check_if_target_satisfied():
            reached = True
            break
    x = np.array(xs)
    # navground stops within its 0.05 m tolerance: count the rest of the way as travelled.
    ratio = (path_length(x) + np.linalg.norm(x[-1] - world["goal"])) / shortest
    return record(world, "navground", kind, None, "global", reached, clearance(world_shapes, x).min(),
                  ratio, (len(xs) - 1) * dt, spent / (len(xs) - 1) * 1e6, False)


def record(world, law, policy, k, sensing, reached, closest, ratio, t, cost_us, held, steps=None):
    """A row of the study table: a collision is a clearance (to a true shape, less the radius) at
    or below 0."""
    collision = bool(closest <= 0.0)
    return {
        "world": world["name"], "generator": "compare_navground",
        "obstacles": len(world["obstacles"]), "law": law,
        "damping" if law == "dynamic" else "speed": policy, "k": k, "sensing": sensing,
        "margin": 0.0, "physics": "builtin", "max_time": MAX_TIME, "error": None,
        "reached": reached, "time_s": t, "path_over_shortest": ratio,
        "min_clearance": float(closest), "collisions": int(collision), "overshoot": None,
        "steps": steps, "guarantees_held": held, "command_us": cost_us,
    }


# --- the study --------------------------------------------------------------------------------


def study(worlds):
    """The records of every method in ``worlds``."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for world in worlds:
            world_shapes = shapes(world)
            for _, law, k, damping, v_max in HARMONAV:
                rows.append(run_harmonav(world, tmp, law, k, damping, world_shapes, v_max))
            path = pathlib.Path(tmp) / f'{world["name"]}-kinematic-auto.toml'
            shortest, _ = harmonav.Scenario.load(path).shortest_path()
            for kind in NAVGROUND:
                rows.append(run_navground(world, kind, world_shapes, shortest))
    return rows


def table(title, rows, markdown):
    """The study table of ``rows`` (``harmonav.study_table``: the one tabulation of harmonav's
    studies, the table of ``cargo xtask quality``), with its title."""
    text = harmonav.study_table(rows)
    return (f"### {title}\n\n" if markdown else f"== {title}\n") + text


def against_hl(rows):
    """Issue 27's measure: the kinematic default's time at HL's top speed (1 m/s) over HL's, in
    each world both arrived in; median and max over the worlds."""
    time = lambda law, speed: {  # noqa: E731
        r["world"]: r["time_s"] for r in rows if r["law"] == law and r.get("speed") == speed and r["reached"]
    }
    mine, hl = time("kinematic", "auto, v_max 1 m/s"), time("navground", "HL")
    ratios = sorted(mine[w] / hl[w] for w in mine if w in hl)
    if not ratios:
        return "kinematic default at 1 m/s over navground HL: no world where both arrived"
    return (f"kinematic default at 1 m/s over navground HL, per world ({len(ratios)} worlds): "
            f"median {statistics.median(ratios):.3f}, max {ratios[-1]:.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", type=int, default=20, help="seeded disc worlds per size (6 and 12 discs)")
    ap.add_argument("--markdown", action="store_true", help="print a blank line after each title")
    ap.add_argument("--records", type=pathlib.Path, help="also write every run's record to this JSON file")
    args = ap.parse_args()
    records = []
    for m in (6, 12):
        worlds = [disc_world(m, seed) for seed in range(args.worlds)]
        rows = study(worlds)
        records += rows
        print(table(f"{args.worlds} seeded worlds of {m} discs", rows, args.markdown))
        print(against_hl(rows) + "\n")
    for world in (concave_star_world(), dense_cluster_world()):
        rows = study([world])
        records += rows
        print(table(f"hard world: {world['name']}", rows, args.markdown))
    if args.records:
        args.records.write_text(json.dumps(records, indent=1))


if __name__ == "__main__":
    main()

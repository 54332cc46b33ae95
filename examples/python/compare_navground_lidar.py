"""harmonav and navground 0.7, each perceiving through its own simulated 360° lidar, in the
seeded disc worlds of radius 5, 20, 50 and 100 m (issue 26, "Benchmarks"; docs/benchmarks.md,
"A simulated lidar").

    pip install ./python "navground==0.7.*"      # navground is not a test dependency
    python examples/python/compare_navground_lidar.py [--worlds 24] [--sizes 5,20,50,100]
        [--markdown] [--records FILE] [--no-navground] [--write DIR] [--depth D]

The worlds are those of ``examples/python/scale_worlds.py`` (discs of radius 0.3–1 m, start and
goal at ±0.8 R, the start 1.3 % of R off the axis; the same seeds, ``1000 seed + R + M``), with
M = 6, 60 and 20 discs at R = 5, 20 and 50 m as there; its 100 m world is empty, so here it
holds 200 discs. Every method drives a disc robot of radius 0.1 m to within 0.05 m of the goal.

- harmonav (both laws, default policies) runs each world as a scenario with
  ``[sensor] type = "lidar"`` at the sensor's defaults (360 beams over 360°, 10 Hz, ±2 cm
  uniform noise, no dropouts, seeded per world) and a range of 3 m (R = 5 m) or 5 m (larger
  worlds). The navigator gets the scans only; its perceived shapes are judged against the truth
  by the run's monitors (``perceived-covers-seen-truth``, ``perceived-shapes-only-grow``), and
  a scan it refuses ends the run with the typed outcome ``scan-refused`` (not a collision).
- navground's ``LidarStateEstimation`` (the same range, 360 beams over 360°, 10 Hz, Gaussian
  noise of the same variance, σ = 0.02/√3 m) scans a ``navground.sim.World`` holding the true
  discs and the wall (a 256-gon). No navground 0.7 behaviour reads a lidar: HL, HRVO, ORCA and
  SocialForce take a ``GeometricState`` (``Behavior.make_type(t).environment_state``), so each
  scan is handed to HL as geometry, with no memory: consecutive hits closer than
  ``JOIN_GAP`` become line segments, isolated hits zero-radius discs. 1 m/s top speed,
  100 Hz steps.

Each run is a record of harmonav's study table, printed by ``harmonav.study_table`` (one table
per world size): arrival, guarantees (harmonav's monitors but arrival and ``scans-accepted``;
navground has none), collisions (the clearance to a true shape less the radius at or below 0),
the closest clearance, path over the shortest path (harmonav's visibility graph around the
grown true shapes), time to goal, and, added by the lidar, "not arrived" (the runs that did not
arrive by outcome: ``scan-refused``, ``stalled``, ``timed-out``; navground's ``timed-out``)
and "perceived/true area" (``summary["perception"]["conservatism"]``). Under each table: the
scan refusals by the navigator's reason, and the runs whose monitors failed. The command prints
its wall time. ``--depth D`` sets harmonav's depth prior below its default (the largest true
diameter): that breaks the assumption its containment rests on (A3), so it is a diagnostic of
what the prior costs, never a result; the monitors still judge every run.
"""

import argparse
import importlib.util
import json
import math
import pathlib
import sys
import tempfile
import time
import tomllib
from collections import Counter

import numpy as np

import harmonav

ROBOT_RADIUS = 0.1
GOAL_TOLERANCE = 0.05
#: (R m, discs): scale_worlds.py's sizes; its 100 m world is empty, here it has 200 discs.
SIZES = {5: 6, 20: 60, 50: 20, 100: 200}
#: Lidar scans per second (the default of ``[sensor] type = "lidar"``), for both planners.
RATE_HZ = 10.0
BEAMS = 360
#: The defaults' uniform noise half-width, m; navground's Gaussian gets the same variance.
RANGE_NOISE = 0.02
#: Consecutive navground hits closer than this are joined by a segment, m.
JOIN_GAP = 0.25
NAVGROUND_DT = 0.01
NAVGROUND_SPEED = 1.0
LAWS = ["kinematic", "dynamic"]


def lidar_range(radius):
    """The lidar's range for a world of radius ``radius`` m: 3 m in the 5 m worlds, 5 m above."""
    return 3.0 if radius <= 5 else 5.0


def max_time(radius):
    """The time budget, s: four times the straight route at 1 m/s, plus a minute."""
    return 4.0 * 1.6 * radius + 60.0


def scale_worlds():
    """``examples/python/scale_worlds.py`` as a module (its generator is the one used)."""
    path = pathlib.Path(__file__).with_name("scale_worlds.py")
    spec = importlib.util.spec_from_file_location("scale_worlds", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def make_world(gen, radius, count, seed):
    """The seeded world of ``scale_worlds.world``: its discs, start and goal."""
    name = f"r{radius}-{count}-lidar-s{seed}"
    doc = tomllib.loads(gen.world(name, radius, count, False, 1000 * seed + radius + count))
    discs = [(tuple(o["center"]), o["radius"]) for o in doc.get("obstacles", [])]
    return {
        "name": name, "radius": float(radius), "seed": seed, "discs": discs,
        "start": np.array(doc["robot"]["start"], float), "goal": np.array(doc["robot"]["goal"], float),
    }


def scenario_toml(world, law, depth=None):
    """The world as a lidar scenario for ``law``; ``depth`` sets the depth prior ``D``
    (``max_obstacle_depth``, m; ``None``: its default, the largest true diameter)."""
    lines = [f'name = "{world["name"]}-{law}"', "[workspace]", 'type = "circle"',
             "center = [0.0, 0.0]", f'radius = {world["radius"]}']
    for (cx, cy), r in world["discs"]:
        lines += ["[[obstacles]]", 'type = "circle"', f"center = [{cx!r}, {cy!r}]", f"radius = {r!r}"]
    (sx, sy), (gx, gy) = (map(float, world["start"]), map(float, world["goal"]))
    lines += [
        "[robot]", f'model = "{law}"', f"start = [{sx!r}, {sy!r}]", f"goal = [{gx!r}, {gy!r}]",
        "mass = 1.0", f"radius = {ROBOT_RADIUS}",
        "[sensor]", 'type = "lidar"', f"range = {lidar_range(world['radius'])}",
        f"seed = {world['seed']}",
        *([f"max_obstacle_depth = {depth!r}"] if depth is not None else []),
        "[sim]", "dt = 0.01", f"max_time = {max_time(world['radius'])}",
        f"goal_tolerance = {GOAL_TOLERANCE}",
    ]
    return "\n".join(lines) + "\n"


def clearance(world, x):
    """Distance from the robot's disc to the nearest true disc or the wall, at each of ``x``
    (N, 2)."""
    d = world["radius"] - np.linalg.norm(x, axis=1)
    for c, r in world["discs"]:
        d = np.minimum(d, np.linalg.norm(x - np.array(c), axis=1) - r)
    return d - ROBOT_RADIUS


def record(world, law, policy, reached, outcome, closest, ratio, t, held, steps=None, area=None,
           sensing="lidar"):
    """A row of the study table (``harmonav.study_table``), with the lidar's columns
    ``outcome`` and ``conservatism``."""
    return {
        "world": world["name"], "generator": "compare_navground_lidar",
        "obstacles": len(world["discs"]), "law": law,
        "damping" if law == "dynamic" else "speed": policy, "k": "auto" if law != "navground" else None,
        "sensing": sensing, "margin": 0.0, "physics": "builtin", "max_time": max_time(world["radius"]),
        "error": None, "reached": bool(reached), "outcome": outcome, "time_s": float(t),
        "path_over_shortest": float(ratio), "min_clearance": float(closest),
        "collisions": int(closest <= 0.0), "overshoot": None, "steps": steps,
        "guarantees_held": bool(held), "command_us": None, "conservatism": area,
    }


def run_harmonav(world, law, tmp, depth=None):
    """One harmonav run with its lidar (depth prior ``depth``, see :func:`scenario_toml`), and
    the shortest path of the world."""
    path = pathlib.Path(tmp) / f'{world["name"]}-{law}.toml'
    path.write_text(scenario_toml(world, law, depth))
    sc = harmonav.Scenario.load(path)
    shortest, _ = sc.shortest_path()
    s = sc.run().summary
    held = all(g["passed"] for g in s["guarantees"] if g["name"] not in ("reached-goal", "scans-accepted"))
    area = (s.get("perception") or {}).get("conservatism")
    sensing = "lidar" if depth is None else f"lidar, D = {depth:g} m"
    row = record(world, law, "auto", s["reached"], s["outcome"]["kind"], s["min_clearance"],
                 s["path_length"] / shortest, s["time_s"], held, s["steps"] + s["rejected_steps"],
                 area, sensing=sensing)
    # Not columns of the study table: why a scan was refused, and the monitors that failed.
    row["refusal"] = refusal_reason(s)
    row["failed"] = [g["name"] for g in s["guarantees"]
                     if not g["passed"] and g["name"] not in ("reached-goal", "scans-accepted")]
    return row, shortest


def refusal_reason(summary):
    """The navigator's reason for the refused scan that ended the run (``None``: none), from
    the ``scans-accepted`` monitor's detail: the text after ``was refused:``."""
    for g in summary["guarantees"]:
        if g["name"] == "scans-accepted" and not g["passed"]:
            detail = g.get("detail") or ""
            return detail.split("was refused:", 1)[-1].strip() or detail
    return None


def reading(rows):
    """The lines under a table: the refusals by reason, and the runs whose monitors failed."""
    reasons = Counter(r["refusal"] for r in rows if r.get("refusal"))
    lines = [f"scan refusals ({sum(reasons.values())}): "
             + ("; ".join(f"{n}× {why}" for why, n in reasons.most_common()) or "none")]
    failed = [f'{r["world"]} {r["law"]}: {", ".join(r["failed"])}' for r in rows if r.get("failed")]
    lines.append("guarantees failed (other than arrival and scans-accepted): "
                 + ("; ".join(failed) or "none"))
    return "\n".join(lines)


def scan_geometry(core, position, angles, ranges, max_range):
    """One navground scan as HL's geometry: the hits (``range < max_range``) in the world
    frame, consecutive ones closer than ``JOIN_GAP`` joined by segments, lone ones as discs of
    radius 0."""
    hit = ranges < max_range * (1.0 - 1e-6)
    p = position + ranges[:, None] * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    n = len(ranges)
    segments, joined = [], np.zeros(n, bool)
    for i in range(n):
        j = (i + 1) % n
        if hit[i] and hit[j] and np.linalg.norm(p[i] - p[j]) < JOIN_GAP:
            segments.append(core.LineSegment(tuple(p[i]), tuple(p[j])))
            joined[i] = joined[j] = True
    discs = [core.Disc(tuple(p[i]), 0.0) for i in range(n) if hit[i] and not joined[i]]
    return discs, segments


def run_navground(world, shortest):
    """One navground HL run fed by navground's own lidar (``LidarStateEstimation``)."""
    from navground import core, sim

    ng = sim.World()
    ng.seed = world["seed"]
    for c, r in world["discs"]:
        ng.add_obstacle(sim.Obstacle(core.Disc(c, r)))
    wall = harmonav.circle([0, 0], world["radius"]).outline(256)
    for i in range(len(wall)):
        ng.add_wall(sim.Wall(core.LineSegment(tuple(wall[i]), tuple(wall[(i + 1) % len(wall)]))))
    agent = sim.Agent(radius=ROBOT_RADIUS)
    agent.pose = core.Pose2(tuple(world["start"]), 0.0)
    ng.add_agent(agent)
    rng = lidar_range(world["radius"])
    lidar = sim.state_estimations.LidarStateEstimation(
        range=rng, resolution=BEAMS, error_std_dev=RANGE_NOISE / math.sqrt(3.0))
    lidar.prepare(agent, ng)
    sensing = core.SensingState()
    angles = np.array(lidar.angles)

    b = core.Behavior.make_type("HL")
    b.kinematics = core.kinematics.OmnidirectionalKinematics(max_speed=NAVGROUND_SPEED)
    b.radius = ROBOT_RADIUS
    b.optimal_speed = NAVGROUND_SPEED
    b.position = tuple(world["start"])
    b.target = core.Target.Point(tuple(world["goal"]), GOAL_TOLERANCE)
    state = b.environment_state
    every = max(1, round(1.0 / (RATE_HZ * NAVGROUND_DT)))
    xs, reached = [np.array(world["start"])], False
    steps = int(max_time(world["radius"]) / NAVGROUND_DT)
    for step in range(steps):
        if step % every == 0:
            agent.pose = core.Pose2(tuple(b.position), 0.0)
            lidar.update(agent, ng, sensing)
            discs, segments = scan_geometry(core, np.array(b.position), angles,
                                            np.array(lidar.read_ranges(sensing)), rng)
            state.static_obstacles = discs
            state.line_obstacles = segments
        b.actuate(b.compute_cmd(NAVGROUND_DT), NAVGROUND_DT)
        xs.append(np.array(b.position))
        if b.check_if_target_satisfied():
            reached = True
            break
    x = np.array(xs)
    length = float(np.sum(np.linalg.norm(np.diff(x, axis=0), axis=1)))
    # navground stops within its tolerance: count the rest of the way as travelled.
    ratio = (length + np.linalg.norm(x[-1] - world["goal"])) / shortest
    return record(world, "navground", "HL, lidar", reached, "reached" if reached else "timed-out",
                  clearance(world, x).min(), ratio, (len(xs) - 1) * NAVGROUND_DT, False)


def study(worlds, navground, depth=None):
    """The records of every method in ``worlds``."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for world in worlds:
            shortest = None
            for law in LAWS:
                row, shortest = run_harmonav(world, law, tmp, depth)
                rows.append(row)
            if navground:
                rows.append(run_navground(world, shortest))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", type=int, default=24, help="seeded worlds per size")
    ap.add_argument("--sizes", default="5,20,50,100", help="world radii, m, among 5, 20, 50, 100")
    ap.add_argument("--markdown", action="store_true", help="print a blank line after each title")
    ap.add_argument("--no-navground", action="store_true", help="harmonav only")
    ap.add_argument("--depth", type=float, metavar="D",
                    help="harmonav's depth prior max_obstacle_depth, m (default: the largest true "
                         "diameter; a smaller one breaks assumption A3: a diagnostic, not a result)")
    ap.add_argument("--records", type=pathlib.Path, help="also write every run's record to this JSON file")
    ap.add_argument("--write", type=pathlib.Path, metavar="DIR",
                    help="only write the harmonav scenario files into DIR (to rerun one with harmonav run)")
    args = ap.parse_args()
    if args.write:
        args.write.mkdir(parents=True, exist_ok=True)
        gen = scale_worlds()
        for radius in (int(s) for s in args.sizes.split(",")):
            for seed in range(args.worlds):
                world = make_world(gen, radius, SIZES[radius], seed)
                for law in LAWS:
                    (args.write / f'{world["name"]}-{law}.toml').write_text(
                        scenario_toml(world, law, args.depth))
        return
    navground = not args.no_navground
    if navground:
        try:
            import navground.sim  # noqa: F401
        except ImportError:  # pragma: no cover - the comparison needs it, the tests do not
            sys.exit('navground is needed: pip install "navground==0.7.*" (or --no-navground)')
    gen = scale_worlds()
    records, begin = [], time.perf_counter()
    for radius in (int(s) for s in args.sizes.split(",")):
        if radius not in SIZES:
            sys.exit(f"--sizes: {radius} is not one of {sorted(SIZES)}")
        t0 = time.perf_counter()
        worlds = [make_world(gen, radius, SIZES[radius], seed) for seed in range(args.worlds)]
        rows = study(worlds, navground, args.depth)
        records += rows
        title = (f"{args.worlds} seeded worlds of radius {radius} m, {SIZES[radius]} discs, "
                 f"lidar range {lidar_range(radius):g} m")
        print((f"#### {title}\n\n" if args.markdown else f"== {title}\n") + harmonav.study_table(rows))
        print(reading(rows) + "\n")
        print(f"({time.perf_counter() - t0:.0f} s)\n", flush=True)
    print(f"wall time {time.perf_counter() - begin:.0f} s")
    if args.records:
        args.records.write_text(json.dumps(records, indent=1))


if __name__ == "__main__":
    main()

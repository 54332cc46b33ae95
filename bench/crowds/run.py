#!/usr/bin/env python3
"""Issue 54's crowd benchmark: harmonav against navground's ORCA and HL in navground's own Cross,
Antipodal and Corridor scenarios, plus one robot among 19 agents that ignore it (docs/movers.md
§9; bench/crowds/README.md has the command).

Every cell runs the same seeds (0 … N − 1) of navground's example configurations (20 agents,
Omni kinematics with ``heading: idle``, the examples' radius, optimal and max speed, safety
margin, sensing range, time step 0.1 s = control period), terminating when every agent is idle
or stuck. Entries: ``ORCA``, ``HL`` (navground's), ``harmonav`` (the ``Harmonav`` behaviour of
``harmonav.navground``: the kinematic law, the certified mover filter with every other agent as
a reciprocal mover, KeepRight) and ``ORCA+filter`` (navground's ORCA with the ``HarmonavFilter``
modulation). ``mixed``: Cross with one robot (harmonav with non-cooperative rows and
V = 0.166 m/s, the same with a ``comfort`` of 0.1 m (``harmonav+comfort``, ``--comfort``), or
ORCA, or HL) among 19 navground ``Dummy`` agents that ignore everyone.

    python bench/crowds/run.py --seeds 100 --json crowds.json

Metrics per cell (see ``summarise``): runs with a recorded contact and navground's collision
events (``min_interval`` 10 steps), the smallest gap between two bodies over every period
(closest approach of the straight steps between recorded poses, lattice-aware) and the runs
and pair-periods below the safety margin, deadlocks (runs ending with every agent stuck while
some has not arrived, or with an agent stuck for its last 5 s), Cross throughput (waypoints
reached per agent in 300 s), Antipodal arrival and makespan, Corridor efficacy, harmonav's
modes; mixed: the robot's contact episodes and those not preceded by an ``Overwhelmed`` (or
refused) command in the period the contact began in, and the waypoints the robot reached.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

from harmonav import navground as hn  # noqa: E402  (registers Harmonav, HarmonavFilter, HarmonavSensing)

#: navground's example experiments (navground_examples_yaml/experiment/*.yaml), Omni with
#: heading idle (the proof's straight hold), and the number of steps of 0.1 s.
SCENARIOS = {
    "cross": dict(steps=3000, scenario="type: Cross\n  agent_margin: 0.1\n  side: 4\n"
                  "  target_margin: 0.1\n  tolerance: 0.5",
                  radius=0.08, speed_tolerance=0.02, optimal_speed=0.12, horizon=5.0,
                  safety_margin=0.02, range=5.0),
    "antipodal": dict(steps=3000, scenario="type: Antipodal\n  position_noise: 0.005\n"
                      "  orientation_noise: 0.01\n  radius: 2\n  tolerance: 0.2",
                      radius=0.1, speed_tolerance=0.01, optimal_speed=0.08, horizon=10.0,
                      safety_margin=0.01, range=10.0),
    "corridor": dict(steps=1000, scenario="type: Corridor\n  length: 8.0\n  width: 0.6",
                     radius=0.08, speed_tolerance=0.02, optimal_speed=0.12, horizon=5.0,
                     safety_margin=0.02, range=5.0),
}
MAX_SPEED = 0.166
TIME_STEP = 0.1
AGENTS = 20
ENTRIES = ("ORCA", "HL", "harmonav", "ORCA+filter")
MIXED_ROBOTS = ("harmonav", "harmonav+comfort", "ORCA", "HL")
#: A body gap below the margin by more than this is a margin violation (navground stores
#: positions in single precision: 4 m carries a rounding of 2.4e-7 m).
FLOAT_TOLERANCE = 1e-6
#: Deadlock: stuck since earlier than this before the end (navground's tutorial rule), s.
DEADLOCK_TIME = 5.0
#: A contact episode is explained by an uncertified command in the period it began in or in
#: this many periods before (0: the theorem's test, the command held while contact occurred;
#: navground's collision record at step k is the period from pose k − 1 to pose k, whose
#: command is the robot's k-th, checked against the recorded poses).
EXPLAIN_PERIODS = 0
#: The harmonav behaviour's ``deadlock_rule`` (``--rule``; None: the behaviour's default).
RULE = None
#: The ``comfort`` of the entry ``harmonav+comfort`` (``--comfort``), m.
DEFAULT_COMFORT = 0.1
COMFORT = DEFAULT_COMFORT


def behaviour_yaml(entry: str, s: dict, indent: str, peers: str = "reciprocal") -> str:
    """The ``behavior`` and state estimation lines of one group."""
    common = (f"optimal_speed: {s['optimal_speed']}, horizon: {s['horizon']}, "
              f"safety_margin: {s['safety_margin']}, heading: idle")
    bounded = f"{{type: Bounded, range: {s['range']}}}"
    sensing = f"{{type: HarmonavSensing, range: {s['range']}}}"
    if entry == "Dummy":  # ignores everyone: no sensing
        return f"{indent}behavior: {{type: Dummy, {common}}}\n"
    if entry in ("ORCA", "HL"):
        return (f"{indent}behavior: {{type: {entry}, {common}}}\n"
                f"{indent}state_estimation: {bounded}\n")
    if entry in ("harmonav", "harmonav+comfort"):
        extra = "" if peers == "reciprocal" else \
            f", peers: noncooperative, mover_speed_bound: {MAX_SPEED}"
        if RULE is not None:
            extra += f", deadlock_rule: {RULE}"
        if entry == "harmonav+comfort":
            extra += f", comfort: {COMFORT}"
        return (f"{indent}behavior: {{type: Harmonav, {common}{extra}}}\n"
                f"{indent}state_estimations: [{sensing}]\n")
    if entry == "ORCA+filter":
        return (f"{indent}behavior: {{type: ORCA, {common}, "
                f"modulations: [{{type: HarmonavFilter}}]}}\n"
                f"{indent}state_estimations: [{bounded}, {sensing}]\n")
    raise ValueError(entry)


def group_yaml(entry: str, s: dict, number: int, peers: str = "reciprocal") -> str:
    indent = "      "
    return (f"    - type: thymio\n{indent}number: {number}\n{indent}radius: {s['radius']}\n"
            f"{indent}control_period: {TIME_STEP}\n"
            f"{indent}speed_tolerance: {s['speed_tolerance']}\n"
            f"{indent}kinematics: {{type: Omni, max_speed: {MAX_SPEED}}}\n"
            + behaviour_yaml(entry, s, indent, peers))


def experiment_yaml(scenario: str, entry: str) -> str:
    """The navground experiment of one cell (``scenario`` ``mixed`` puts ``entry`` as one robot
    among 19 Dummy agents in Cross)."""
    base = "cross" if scenario == "mixed" else scenario
    s = SCENARIOS[base]
    if scenario == "mixed":
        groups = group_yaml(entry, s, 1, peers="noncooperative") + \
            group_yaml("Dummy", s, AGENTS - 1)
    else:
        groups = group_yaml(entry, s, AGENTS)
    return (f"steps: {s['steps']}\ntime_step: {TIME_STEP}\nrecord_pose: true\n"
            "record_collisions: true\nrecord_deadlocks: true\nrecord_efficacy: true\n"
            "record_task_events: true\nterminate_when_all_idle_or_stuck: true\n"
            f"scenario:\n  {s['scenario']}\n  groups:\n{groups}")


# --- metrics of one run ------------------------------------------------------------------------


def lattice_periods(world) -> tuple:
    out = []
    for axis in (0, 1):
        lattice = world.get_lattice(axis)
        out.append(None if lattice is None else float(lattice[1] - lattice[0]))
    return tuple(out)


def wrap(d: np.ndarray, periods: tuple) -> np.ndarray:
    for axis, period in enumerate(periods):
        if period:
            d[..., axis] -= period * np.round(d[..., axis] / period)
    return d


def swept_gaps(poses: np.ndarray, radii: np.ndarray, periods: tuple) -> tuple:
    """The least body gap of every pair over every period between recorded poses, the agents
    moving straight (Omni, heading idle): ``(gaps (T − 1, pairs), i, j, steps (T − 1, n))``
    with the agents' own displacements."""
    p = poses[:, :, :2].astype(float)
    n = p.shape[1]
    i, j = np.triu_indices(n, 1)
    step = wrap(p[1:] - p[:-1], periods)
    d0 = wrap(p[:-1, j] - p[:-1, i], periods)
    w = step[:, j] - step[:, i]
    ww = np.einsum("tpk,tpk->tp", w, w)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(ww > 0.0, -np.einsum("tpk,tpk->tp", d0, w) / ww, 0.0)
    s = np.clip(s, 0.0, 1.0)
    closest = d0 + s[..., None] * w
    gaps = np.hypot(closest[..., 0], closest[..., 1]) - (radii[i] + radii[j])
    return gaps, i, j, np.hypot(step[..., 0], step[..., 1])


def wall_gaps(world, poses: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """The body gap of every agent to every straight wall (as its line) at every recorded pose:
    over a straight step the distance to a line is linear, so the least is at a pose."""
    out = []
    p = poses[:, :, :2].astype(float)
    for wall in world.walls:
        a = np.asarray(wall.line.p1, dtype=float)
        b = np.asarray(wall.line.p2, dtype=float)
        t = (b - a) / np.hypot(*(b - a))
        n = np.array([-t[1], t[0]])
        out.append(np.abs((p - a) @ n) - radii[None, :])
    return np.stack(out) if out else np.zeros((0,))


def episodes(steps) -> list:
    """Maximal runs of consecutive steps, as their first steps."""
    out, last = [], None
    for k in sorted(set(int(k) for k in steps)):
        if last is None or k > last + 1:
            out.append(k)
        last = k
    return out


def harmonav_logs(world) -> list:
    """Each agent's mode log (behaviour or modulation), or None."""
    logs = []
    for agent in world.agents:
        b = agent.behavior
        log = getattr(b, "log", None)
        if log is None:
            for m in getattr(b, "modulations", []):
                log = getattr(m, "log", None) or log
        logs.append(log)
    return logs


def measure(run, scenario: str, entry: str) -> dict:
    """The metrics of one finished run."""
    world = run.world
    agents = world.agents
    s = SCENARIOS["cross" if scenario == "mixed" else scenario]
    margin = s["safety_margin"]
    radii = np.array([a.radius for a in agents], dtype=float)
    periods = lattice_periods(world)
    poses = np.asarray(run.poses)
    gaps, pi, pj, moved = swept_gaps(poses, radii, periods)
    wall_gap = wall_gaps(world, poses, radii)
    collisions = np.asarray(run.collisions).reshape(-1, 3)
    events = np.asarray(run.get_collision_events(min_interval=10)).reshape(-1, 4)
    final = float(run.final_sim_time)
    horizon = s["steps"] * TIME_STEP
    done = [bool(a.task.done()) if a.task is not None else False for a in agents]
    stuck_since = np.asarray(run.deadlocks, dtype=float)
    task_events = run.task_events
    reached = [max(len(task_events.get(k, [])) - 1, 0) for k in range(len(agents))]
    deadlocked = [k for k, t in enumerate(stuck_since)
                  if t >= 0.0 and t < final - DEADLOCK_TIME and not done[k]]
    ended_stuck = final < horizon - 1e-6 and not all(done)
    out = dict(
        seed=int(run.seed),
        steps=int(run.recorded_steps),
        final_time=final,
        collisions=int(len(collisions)),
        collision_events=int(len(events)),
        min_gap=float(min(np.nanmin(gaps) if gaps.size else np.inf, wall_gap.min(initial=np.inf))),
        min_wall_gap=float(wall_gap.min()) if wall_gap.size else None,
        margin_violations=int(np.count_nonzero(gaps < margin - FLOAT_TOLERANCE)
                              + np.count_nonzero(wall_gap < margin - FLOAT_TOLERANCE)),
        swept_contacts=int(np.count_nonzero(gaps <= 0.0) + np.count_nonzero(wall_gap <= 0.0)),
        deadlocked_agents=len(deadlocked),
        ended_stuck=bool(ended_stuck),
        deadlock=bool(deadlocked) or bool(ended_stuck),
        all_arrived=bool(all(done)),
        arrived=int(sum(done)),
        waypoints_per_agent=float(np.mean(reached)),
        efficacy=float(np.nanmean(np.asarray(run.efficacy, dtype=float))),
    )
    if scenario == "antipodal" and all(done):
        out["makespan"] = max(float(np.asarray(task_events[k])[-1, 0])
                              for k in range(len(agents)))
    logs = harmonav_logs(world)
    if any(log is not None for log in logs):
        counts: dict = {}
        for log in logs:
            if log is not None:
                for name, c in log.summary().items():
                    counts[name] = counts.get(name, 0) + c
        out["modes"] = counts
    if scenario == "mixed":
        out.update(mixed_metrics(agents, collisions, logs[0], gaps, pi, pj, moved))
        # The robot's own progress: contacts avoided by standing still would show here.
        out["robot_waypoints"] = reached[0]
    return out


def mixed_metrics(agents, collisions, log, gaps, pi, pj, moved) -> dict:
    """The robot's (agent 0) contact episodes, and those no uncertified command explains."""
    robot = agents[0]._uid
    steps = [int(c[0]) for c in collisions if int(c[1]) == robot or int(c[2]) == robot]
    starts = episodes(steps)
    mine = (pi == 0) | (pj == 0)
    swept = np.flatnonzero((gaps[:, mine] <= 0.0).any(1)) + 1
    bad = (hn.MODES.index("overwhelmed"), hn.MODES.index("refused"))
    unexplained, bound_broken, unjudged = 0, 0, 0
    bound = 0.166 * TIME_STEP * (1.0 + 1e-4)
    for k in starts:
        if log is None:
            continue
        if k >= len(log.modes):
            # The run's last record (step = steps): the robot logged no command for it, so
            # the episode cannot be judged (it was once counted as unexplained: an empty
            # window has no uncertified command).
            unjudged += 1
            continue
        window = log.modes[max(0, k - EXPLAIN_PERIODS):k + 1]
        if not any(code in bad for code in window):
            unexplained += 1
            # Did any other agent break its speed bound (A2) just before?
            lo = max(0, k - 2)
            if (moved[lo:k + 1, 1:] > bound).any():
                bound_broken += 1
    out = dict(robot_contact_episodes=len(starts),
               robot_swept_contact_episodes=len(episodes(swept)),
               robot_contacts=len(steps))
    if log is not None:
        out["unexplained_episodes"] = unexplained
        out["unexplained_with_speed_bound_broken"] = bound_broken
        out["unjudged_episodes"] = unjudged
        out["robot_uncertified"] = sum(1 for c in log.modes if c in bad)
        out["robot_commands"] = len(log.modes)
    return out


# --- running --------------------------------------------------------------------------------

_EXPERIMENTS: dict = {}


def run_one(task: tuple) -> tuple:
    scenario, entry, seed = task
    from navground import sim

    key = (scenario, entry)
    exp = _EXPERIMENTS.get(key)
    if exp is None:
        exp = sim.load_experiment(experiment_yaml(scenario, entry))
        _EXPERIMENTS[key] = exp
    t0 = time.perf_counter()
    run = exp.run_once(seed)
    wall = time.perf_counter() - t0
    m = measure(run, scenario, entry)
    m["wall_time"] = wall
    del run
    exp.remove_all_runs()  # run_once keeps every run: a worker would grow by ~5 MB a run
    return scenario, entry, m


def cells(scenarios, entries, mixed_robots) -> list:
    out = [(sc, e) for sc in scenarios if sc != "mixed" for e in entries]
    if "mixed" in scenarios:
        out += [("mixed", r) for r in mixed_robots]
    return out


def wilson(k: int, n: int, z: float = 1.96) -> tuple:
    if n == 0:
        return (0.0, 1.0)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * ((p * (1 - p) / n + z * z / (4 * n * n)) ** 0.5) / d
    return (max(0.0, c - h), min(1.0, c + h))


def summarise(runs: list, scenario: str) -> dict:
    n = len(runs)
    out = dict(runs=n)
    out["runs_with_contact"] = sum(1 for r in runs if r["collisions"] > 0)
    out["runs_with_contact_wilson95"] = wilson(out["runs_with_contact"], n)
    out["collision_events"] = sum(r["collision_events"] for r in runs)
    out["min_gap"] = min((r["min_gap"] for r in runs if r["min_gap"] is not None),
                         default=None)
    out["runs_with_margin_violation"] = sum(1 for r in runs if r["margin_violations"] > 0)
    out["margin_violations"] = sum(r["margin_violations"] for r in runs)
    out["runs_with_deadlock"] = sum(1 for r in runs if r["deadlock"])
    out["runs_ended_all_stuck"] = sum(1 for r in runs if r["ended_stuck"])
    out["deadlocked_agents"] = sum(r["deadlocked_agents"] for r in runs)
    out["efficacy"] = statistics.fmean(r["efficacy"] for r in runs) if runs else None
    out["wall_time_per_run"] = statistics.fmean(r["wall_time"] for r in runs) if runs else None
    if scenario in ("cross", "mixed"):
        out["waypoints_per_agent"] = statistics.fmean(r["waypoints_per_agent"] for r in runs)
    if scenario == "antipodal":
        out["runs_all_arrived"] = sum(1 for r in runs if r["all_arrived"])
        spans = sorted(r["makespan"] for r in runs if "makespan" in r)
        if spans:
            q = np.percentile(spans, [25, 50, 75])
            out["makespan_median"] = float(q[1])
            out["makespan_iqr"] = [float(q[0]), float(q[2])]
    modes = [r["modes"] for r in runs if "modes" in r]
    if modes:
        out["modes"] = {k: sum(m[k] for m in modes) for k in modes[0]}
    if scenario == "mixed":
        for key in ("robot_contact_episodes", "robot_swept_contact_episodes",
                    "unexplained_episodes", "unexplained_with_speed_bound_broken",
                    "unjudged_episodes",
                    "robot_uncertified", "robot_commands"):
            vals = [r[key] for r in runs if key in r]
            if vals:
                out[key] = sum(vals)
        out["runs_with_robot_contact"] = sum(1 for r in runs if r["robot_contact_episodes"])
        out["robot_waypoints"] = statistics.fmean(r["robot_waypoints"] for r in runs)
    return out


def table(summary: dict) -> str:
    """A Markdown table of the main cells."""
    lines = ["| scenario | entry | runs with contact | collision events | least gap (m) | "
             "runs below margin | runs with deadlock (all stuck) | task | efficacy |",
             "|---|---|---|---|---|---|---|---|---|"]
    for key, c in summary.items():
        scenario, entry = key.split("/")
        if scenario == "mixed":
            continue
        if scenario == "cross":
            task = f"{c['waypoints_per_agent']:.2f} waypoints / agent"
        elif scenario == "antipodal":
            task = f"all arrived {c['runs_all_arrived']}/{c['runs']}"
            if "makespan_median" in c:
                lo, hi = c["makespan_iqr"]
                task += f", makespan {c['makespan_median']:.1f} s ({lo:.1f}–{hi:.1f})"
        else:
            task = "—"
        gap = "—" if c["min_gap"] is None else f"{c['min_gap']:.4f}"
        lines.append(
            f"| {scenario} | {entry} | {c['runs_with_contact']}/{c['runs']} | "
            f"{c['collision_events']} | {gap} | {c['runs_with_margin_violation']} | "
            f"{c['runs_with_deadlock']} ({c['runs_ended_all_stuck']}) | {task} | "
            f"{c['efficacy']:.3f} |")
    mixed = [(k, c) for k, c in summary.items() if k.startswith("mixed/")]
    if mixed:
        lines += ["", "| robot among 19 Dummy (Cross) | runs with robot contact | contact "
                  "episodes | certified while contact began | of those, a Dummy over its bound "
                  "| uncertified commands | the robot's waypoints |",
                  "|---|---|---|---|---|---|---|"]
        for key, c in mixed:
            entry = key.split("/")[1]
            unexplained = c.get("unexplained_episodes", "—")
            broken = c.get("unexplained_with_speed_bound_broken", "—")
            unc = (f"{c['robot_uncertified']}/{c['robot_commands']}"
                   if "robot_uncertified" in c else "—")
            lines.append(f"| {entry} | {c['runs_with_robot_contact']}/{c['runs']} | "
                         f"{c['robot_contact_episodes']} | {unexplained} | {broken} | {unc} | "
                         f"{c['robot_waypoints']:.2f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=100, help="seeds 0 … N − 1 per cell")
    ap.add_argument("--start", type=int, default=0, help="first seed")
    ap.add_argument("--scenarios", default="cross,antipodal,corridor,mixed")
    ap.add_argument("--entries", default=",".join(ENTRIES))
    ap.add_argument("--mixed-robots", default=",".join(MIXED_ROBOTS))
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--json", help="write every run's metrics and the summary here")
    ap.add_argument("--rule", choices=hn.RULES,
                    help="the harmonav behaviour's deadlock_rule on a direction task (the "
                    "Corridor; towards a point the navigator's own rule runs); default: gap")
    ap.add_argument("--comfort", type=float, default=DEFAULT_COMFORT,
                    help="the comfort of the mixed robot harmonav+comfort, m (default "
                    f"{DEFAULT_COMFORT})")
    ap.add_argument("--print-yaml", metavar="SCENARIO/ENTRY",
                    help="print one cell's navground experiment and exit")
    args = ap.parse_args(argv)
    global RULE, COMFORT
    RULE = args.rule
    COMFORT = args.comfort
    if args.print_yaml:
        scenario, entry = args.print_yaml.split("/")
        print(experiment_yaml(scenario, entry))
        return 0
    scenarios = [s for s in args.scenarios.split(",") if s]
    entries = [e for e in args.entries.split(",") if e]
    robots = [e for e in args.mixed_robots.split(",") if e]
    todo = [(sc, e, seed) for seed in range(args.start, args.start + args.seeds)
            for sc, e in cells(scenarios, entries, robots)]
    results: dict = {f"{sc}/{e}": [] for sc, e in cells(scenarios, entries, robots)}
    t0 = time.perf_counter()
    ctx = mp.get_context("fork")
    with ctx.Pool(args.processes, maxtasksperchild=200) as pool:
        for k, (sc, e, m) in enumerate(pool.imap_unordered(run_one, todo, chunksize=1)):
            results[f"{sc}/{e}"].append(m)
            if (k + 1) % 20 == 0 or k + 1 == len(todo):
                print(f"{k + 1}/{len(todo)} runs, {time.perf_counter() - t0:.0f} s",
                      file=sys.stderr, flush=True)
    for runs in results.values():
        runs.sort(key=lambda r: r["seed"])
    summary = {key: summarise(runs, key.split("/")[0]) for key, runs in results.items()}
    elapsed = time.perf_counter() - t0
    print(table(summary))
    print(f"\n{len(todo)} runs, seeds {args.start}–{args.start + args.seeds - 1}, "
          f"{args.processes} processes, {elapsed:.0f} s")
    if args.json:
        from importlib.metadata import version

        import harmonav
        meta = dict(seeds=[args.start, args.start + args.seeds], processes=args.processes,
                    elapsed=elapsed, navground=version("navground"),
                    harmonav=harmonav.__version__, rule=args.rule, comfort=args.comfort,
                    command=" ".join([os.path.basename(sys.executable)] + sys.argv))
        with open(args.json, "w") as f:
            json.dump(dict(meta=meta, summary=summary, runs=results), f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())

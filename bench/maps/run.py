#!/usr/bin/env python3
"""Issue 52: navground's HL on the ten public ROS map_server maps of docs/benchmarks.md,
"Public maps (issue 52)", following A* waypoints (``HL+A*``, a planner-plus-controller stack as
Nav2 users run) and given only the goal (``HL``). bench/maps/README.md has the commands.

The maps: ``scenarios/floorplans/public/<name>.toml`` and its ``maps/<name>.yaml``, read with
map_server's conventions (``resolution``, ``origin`` (its yaw must be 0), ``negate``,
``occupied_thresh``, ``free_thresh``; a colour image made grey by averaging its colour
channels, alpha left out, as ROS 1's map_server does; occupancy ``p = (255 − v)/255``, or
``v/255`` with ``negate``; occupied when ``p > occupied_thresh``, free when ``p <
free_thresh``). Every pixel that is not free — occupied **and unknown** (Nav2's costmap treats
unknown as lethal by default, and harmonav takes unknown pixels as walls too) — is an obstacle,
and so is everything outside the image (a one-pixel border of obstacle pixels around it).

The robot of every file: a disc of radius 0.2 m, safety margin 0.05 m, holonomic, top speed
1.41 m/s (harmonav's kinematic law's default ``v_max``), from the file's ``robot.start`` and
its four seeded ``[starts]`` to its ``robot.goal``, 240 s at most. The starts are harmonav's
own: by default (``--starts-from auto``) from its Python bindings, ``FloorPlan.load(FILE).starts``
(the same Rust code, ``FloorScenario::load``, draws them as for ``harmonav check``; seconds even on
``willow-full``, where ``check`` also certifies the map and takes minutes); without the bindings,
or with ``--starts-from check``, the ones ``harmonav check FILE --json`` prints
(``starts[].position``, cached in ``--cache``). Where neither gives them (the map does not load,
or ``check`` takes longer than ``--check-timeout``), ``robot.start`` and four starts of ours
(seed 52, uniform over the cells of the A* grid that reach the goal, more than 1 m from it),
marked † in the table; ``--own-starts a,b`` asks for these on the maps named.

Entries, both in navground 0.7's own loop (``World.update(0.1)``, control period 0.1 s):

- ``HL+A*``: A* on the 8-connected pixel grid (diagonal steps √2 pixels, no corner cutting)
  inflated by radius + margin (a cell is blocked when its centre is within 0.25 m of an
  obstacle pixel's square, or in it). The optimal path is taken from one Dijkstra search from
  the goal cell (the path A* with an admissible heuristic returns, for every start at once),
  from the start's cell; it is pruned to waypoints by line of sight on the inflated grid
  (greedy: from each waypoint, the farthest path cell seen along a segment sampled every
  quarter pixel), the start and goal put in exactly. The waypoints are a ``Waypoints`` task
  (``loop: false``), tolerance 0.25 m at each intermediate waypoint, 0.01 m at the goal.
  navground's ``Waypoints`` task makes HL stop at each waypoint (measured: it decelerates to
  rest within the tolerance, about 0.8 s, then sets off to the next), so the time counts these
  stops; navground's ``Path`` task (``follow_path``) was tried on tb3-world and not kept (no
  start arrived within 30 s, one touched a wall, one raised a shapely error).
- ``HL``: the same with the goal as the only waypoint.

HL: ``optimal_speed`` = ``max_speed`` = 1.41 m/s, ``safety_margin`` 0.05 m, ``Omni``
(omnidirectional) kinematics with ``max_speed`` 1.41 m/s, HL's defaults otherwise (horizon
5 m, 101 rays over its aperture). Sensing, the same for both entries: ``Bounded`` state
estimation over a range of the map's diagonal (every wall known). The walls: every pixel edge
between the free component that holds the goal (4-connected free pixels) and anything else,
merged into maximal straight segments along each grid line.

navground's collision resolution is off (``World.ignore_collisions``; ``--resolve-collisions``
turns it on): with it, a disc driven into a wall is pushed back out before its position is
recorded, so the judge reads about 0 mm where the disc was in the wall, and a run pressed against
a wall for minutes counted as no contact.

Judged by an independent check on the map's pixels: each period's motion is the straight
segment between navground's recorded positions (omnidirectional: navground integrates a
constant velocity over the step), sampled every centimetre; at each sample the least distance
from the robot's centre to the squares of the obstacle pixels nearby (exact point-to-square
distance); a contact is a distance below the radius (clearance < 0). With
``--resolve-collisions``, navground's own collision events (``World.collisions`` non-empty after
a step) are counted too (navground records none while it ignores collisions). Arrival: the
centre within 0.05 m of the goal within 240 s; time the first such time, path the length
driven until then. (harmonav's arrival tolerance is 0.01 m, but HL at a 0.1 s period dithers
a few centimetres about the goal, sometimes for tens of seconds; each run goes on for up to
10 s after arrival, and the first time within 0.01 m, if any, is in the JSON.)

The geodesic: the 8-connected Dijkstra distance (√2 diagonals) on the inflated grid from the
start's cell to the goal's, plus the two straight offsets from the start and goal to their
cells' centres (an 8-connected path is up to 8 % longer than the straight lines it stands for,
so a ratio below 1 is no error). The table also gives the path over the length of the pruned
waypoint polyline (``any_angle``, per run in the JSON): the A* path with line-of-sight
shortcuts, 1–10 % shorter than the 8-connected geodesic on these maps and no shorter than the
any-angle geodesic of the inflated grid, so this ratio, if anything, understates the detour.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import os
import subprocess
import sys
import time
import tomllib

import numpy as np
import yaml
from PIL import Image
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

RADIUS = 0.2
MARGIN = 0.05
V_MAX = 1.41
PERIOD = 0.1
T_MAX = 240.0
GOAL_TOL = 0.05
#: harmonav's arrival tolerance: HL dithers a few centimetres about the goal at a 0.1 s period
#: (measured on lse-arena: within 5 cm after 2–3 s, within 1 cm after 8–54 s or never), so
#: arrival is judged at GOAL_TOL and the first time within 1 cm is recorded in the JSON.
FINE_TOL = 0.01
WAYPOINT_TOL = 0.25
SAMPLE_STEP = 0.01
OWN_STARTS = 4
OWN_SEED = 52
ENTRIES = ("HL+A*", "HL")
#: navground's ``World.ignore_collisions``: on by default, so that navground neither records
#: collisions nor pushes the disc back out of a wall and the judge sees every overlap on the
#: recorded positions; ``--resolve-collisions`` turns navground's resolution (its own default)
#: back on, and its collision events are then counted.
IGNORE_COLLISIONS = True
MAPS = ("lse-arena", "tb3-world", "tb3-sandbox", "small-house", "small-warehouse", "depot",
        "warehouse", "fetch-office", "willow-2010", "willow-full")
PUBLIC = "scenarios/floorplans/public"


# --- the map ----------------------------------------------------------------------------------


def grey_image(path: str) -> np.ndarray:
    """The image's grey values 0–255 (float), row 0 at the top; colour channels averaged."""
    im = Image.open(path)
    if im.mode in ("L", "P", "I", "I;16", "1"):
        return np.asarray(im.convert("L"), float)
    rgb = np.asarray(im.convert("RGBA" if "A" in im.mode else "RGB"), float)
    return rgb[..., :3].mean(axis=2)


def load_map(yaml_path: str) -> dict:
    """The map as a grid ``blocked[j, i]`` (row 0 at the bottom, a border of obstacle pixels
    added all round), its resolution and the world position of cell (0, 0)'s corner."""
    with open(yaml_path) as f:
        meta = yaml.safe_load(f)
    if meta.get("origin", [0, 0, 0])[2] not in (0, 0.0):
        raise ValueError(f"{yaml_path}: a rotated origin is not supported")
    v = grey_image(os.path.join(os.path.dirname(yaml_path), meta["image"]))
    p = v / 255.0 if meta.get("negate", 0) else (255.0 - v) / 255.0
    free = p < float(meta["free_thresh"])
    obstacle = np.pad(~free[::-1], 1, constant_values=True)
    res = float(meta["resolution"])
    origin = np.array(meta["origin"][:2], float) - res
    return dict(obstacle=obstacle, res=res, origin=origin, shape=obstacle.shape)


def cell_of(m: dict, p) -> tuple:
    i = int(math.floor((p[0] - m["origin"][0]) / m["res"]))
    j = int(math.floor((p[1] - m["origin"][1]) / m["res"]))
    return j, i


def centre_of(m: dict, j, i) -> np.ndarray:
    return m["origin"] + (np.stack([i, j], axis=-1) + 0.5) * m["res"]


def inflate(m: dict, reach: float) -> np.ndarray:
    """Cells whose centre lies within ``reach`` of an obstacle pixel's square (or in one)."""
    k = int(math.ceil(reach / m["res"])) + 1
    d = np.arange(-k, k + 1)
    dx = np.maximum(np.abs(d)[None, :] - 0.5, 0.0)
    dy = np.maximum(np.abs(d)[:, None] - 0.5, 0.0)
    kernel = np.hypot(dx, dy) * m["res"] <= reach
    return ndimage.binary_dilation(m["obstacle"], structure=kernel)


def wall_segments(m: dict, goal) -> np.ndarray:
    """Pixel edges between the free component holding the goal and the rest, merged into
    maximal straight segments: an array (n, 2, 2) of end points."""
    labels, _ = ndimage.label(~m["obstacle"])
    inside = labels == labels[cell_of(m, goal)]
    res, (ox, oy) = m["res"], m["origin"]
    segs = []
    # Horizontal edges: between rows j and j + 1 (the grid line y = j + 1).
    for flip, grid in ((False, inside), (True, inside.T)):
        edge = grid[1:, :] != grid[:-1, :]
        padded = np.pad(edge.astype(np.int8), ((0, 0), (1, 1)))
        step = np.diff(padded, axis=1)
        rows, a = np.nonzero(step == 1)
        _, b = np.nonzero(step == -1)  # same row order: runs alternate
        line = rows + 1.0
        if not flip:
            p = np.stack([ox + a * res, oy + line * res], 1)
            q = np.stack([ox + b * res, oy + line * res], 1)
        else:
            p = np.stack([ox + line * res, oy + a * res], 1)
            q = np.stack([ox + line * res, oy + b * res], 1)
        segs.append(np.stack([p, q], 1))
    return np.concatenate(segs)


# --- the planner ------------------------------------------------------------------------------


def grid_graph(free: np.ndarray):
    """The 8-connected graph of the free cells (no corner cutting), as a sparse matrix."""
    h, w = free.shape
    idx = np.arange(h * w).reshape(h, w)
    i0, i1 = 1, w - 1  # columns 0 and w − 1 are the obstacle border: never free

    def at(a, dj, di):  # a[j + dj, i + di] over j in [0, h − 1), i in [1, w − 1)
        return a[dj: h - 1 + dj, i0 + di: i1 + di]

    rows, cols, wts = [], [], []
    for dj, di, wt in ((0, 1, 1.0), (1, 0, 1.0), (1, 1, math.sqrt(2)), (1, -1, math.sqrt(2))):
        ok = at(free, 0, 0) & at(free, dj, di)
        if dj and di:  # both orthogonal neighbours free too
            ok &= at(free, dj, 0) & at(free, 0, di)
        rows.append(at(idx, 0, 0)[ok])
        cols.append(at(idx, dj, di)[ok])
        wts.append(np.full(int(ok.sum()), wt))
    r, c, x = np.concatenate(rows), np.concatenate(cols), np.concatenate(wts)
    return coo_matrix((x, (r, c)), shape=(h * w, h * w)).tocsr()


def nearest_free(free: np.ndarray, cell: tuple) -> tuple:
    """``cell`` if free, else the nearest free cell (the start or goal in an inflated cell)."""
    if free[cell]:
        return cell
    js, is_ = np.nonzero(free)
    k = int(np.argmin((js - cell[0]) ** 2 + (is_ - cell[1]) ** 2))
    return int(js[k]), int(is_[k])


def plan_field(m: dict, goal) -> dict:
    """One Dijkstra search from the goal's cell on the inflated grid: distances (m) and
    predecessors of every cell."""
    free = ~inflate(m, RADIUS + MARGIN)
    g = nearest_free(free, cell_of(m, goal))
    dist, pred = dijkstra(grid_graph(free), directed=False, indices=g[0] * free.shape[1] + g[1],
                          return_predecessors=True)
    return dict(free=free, goal_cell=g, dist=dist * m["res"], pred=pred)


def line_of_sight(m: dict, free: np.ndarray, p, q) -> bool:
    n = max(2, int(math.ceil(np.linalg.norm(np.subtract(q, p)) / (m["res"] / 4))) + 1)
    t = np.linspace(0.0, 1.0, n)[:, None]
    pts = np.asarray(p) + t * (np.asarray(q) - np.asarray(p))
    ij = np.floor((pts - m["origin"]) / m["res"]).astype(int)
    return bool(free[ij[:, 1], ij[:, 0]].all())


def plan(m: dict, field: dict, start, goal) -> dict:
    """The A* path from ``start``: its cells, the pruned waypoints and the geodesic."""
    free, w = field["free"], field["free"].shape[1]
    s = nearest_free(free, cell_of(m, start))
    k = s[0] * w + s[1]
    if not np.isfinite(field["dist"][k]):
        return dict(reachable=False)
    cells = [k]
    while cells[-1] >= 0 and cells[-1] != field["goal_cell"][0] * w + field["goal_cell"][1]:
        cells.append(int(field["pred"][cells[-1]]))
    cells = np.asarray(cells)
    pts = centre_of(m, cells // w, cells % w)
    pts = np.vstack([np.asarray(start, float), pts, np.asarray(goal, float)])
    geodesic = (field["dist"][k] + np.linalg.norm(pts[1] - pts[0])
                + np.linalg.norm(pts[-1] - pts[-2]))
    way = [0]
    while way[-1] < len(pts) - 1:
        a, nxt = way[-1], way[-1] + 1
        for b in range(a + 2, len(pts)):
            if line_of_sight(m, free, pts[a], pts[b]):
                nxt = b
            elif b - nxt > 40:  # blocked well past the last visible cell
                break
        way.append(nxt)
    poly = pts[way]
    any_angle = float(np.linalg.norm(np.diff(poly, axis=0), axis=1).sum())
    return dict(reachable=True, geodesic=float(geodesic), any_angle=any_angle,
                waypoints=pts[way[1:]].tolist(),
                inflated_start=not free[cell_of(m, start)])


def own_starts(m: dict, field: dict, goal, count: int, seed: int) -> list:
    """``count`` seeded starts: uniform over the reachable cells of the A* grid, more than
    1 m from the goal (for maps where ``harmonav check`` gives none)."""
    rng = np.random.default_rng(seed)
    js, is_ = np.nonzero(np.isfinite(field["dist"]).reshape(field["free"].shape))
    c = centre_of(m, js, is_)
    far = np.linalg.norm(c - np.asarray(goal), axis=1) > 1.0
    pick = rng.choice(np.flatnonzero(far), size=count, replace=False)
    return [c[k].tolist() for k in pick]


# --- the judge --------------------------------------------------------------------------------


def clearance(m: dict, p, q) -> float:
    """Least distance, less the radius, from the segment ``p``–``q`` (sampled every
    centimetre) to the squares of the obstacle pixels within 0.5 m of it."""
    n = max(2, int(math.ceil(np.linalg.norm(np.subtract(q, p)) / SAMPLE_STEP)) + 1)
    pts = np.asarray(p) + np.linspace(0.0, 1.0, n)[:, None] * (np.asarray(q) - np.asarray(p))
    reach = RADIUS + 0.3
    lo = np.floor((pts.min(0) - reach - m["origin"]) / m["res"]).astype(int)
    hi = np.floor((pts.max(0) + reach - m["origin"]) / m["res"]).astype(int) + 1
    lo = np.maximum(lo, 0)
    hi = np.minimum(hi, [m["shape"][1], m["shape"][0]])
    win = m["obstacle"][lo[1]: hi[1], lo[0]: hi[0]]
    js, is_ = np.nonzero(win)
    if js.size == 0:
        return reach - RADIUS
    c = centre_of(m, js + lo[1], is_ + lo[0])
    dx = np.maximum(np.abs(pts[:, None, 0] - c[None, :, 0]) - m["res"] / 2, 0.0)
    dy = np.maximum(np.abs(pts[:, None, 1] - c[None, :, 1]) - m["res"] / 2, 0.0)
    return min(float(np.hypot(dx, dy).min()), reach) - RADIUS


# --- navground --------------------------------------------------------------------------------


def make_world(walls: np.ndarray, start, waypoints: list, sensing_range: float):
    from navground import core, sim

    world = sim.World()
    world.ignore_collisions = IGNORE_COLLISIONS
    for (a, b) in walls:
        world.add_wall(sim.Wall((float(a[0]), float(a[1])), (float(b[0]), float(b[1]))))
    behavior = core.behaviors.HLBehavior()
    behavior.optimal_speed = V_MAX
    behavior.safety_margin = MARGIN
    kinematics = core.kinematics.OmnidirectionalKinematics(max_speed=V_MAX)
    tols = [WAYPOINT_TOL] * (len(waypoints) - 1) + [FINE_TOL]
    task = sim.tasks.WaypointsTask(waypoints=[np.asarray(w, float) for w in waypoints],
                                   loop=False, tolerance=FINE_TOL, tolerances=tols)
    agent = sim.Agent(radius=RADIUS, behavior=behavior, kinematics=kinematics, task=task,
                      state_estimations=[sim.state_estimations.BoundedStateEstimation(
                          range=sensing_range)], control_period=PERIOD)
    agent.position = np.asarray(start, float)
    world.add_agent(agent)
    return world, agent


def fly(m: dict, walls: np.ndarray, start, goal, waypoints: list, sensing_range: float) -> dict:
    world, agent = make_world(walls, start, waypoints, sensing_range)
    goal = np.asarray(goal, float)
    x = np.asarray(agent.position, float)
    least, contacts, events, path, t, arrived = float("inf"), 0, 0, 0.0, 0.0, None
    path_at = 0.0
    clock = time.perf_counter()
    fine = None
    while True:
        if fine is None and np.linalg.norm(x - goal) <= FINE_TOL + 1e-6:
            fine = t
        if arrived is None and np.linalg.norm(x - goal) <= GOAL_TOL + 1e-6:
            arrived = t
        if fine is not None or (arrived is not None and t >= arrived + 10.0 - 1e-9):
            break
        if t >= T_MAX - 1e-9:
            break
        world.update(PERIOD)
        x1 = np.asarray(agent.position, float)
        c = clearance(m, x, x1)
        least = min(least, c)
        contacts += c < 0.0
        events += bool(world.collisions)
        path += float(np.linalg.norm(x1 - x))
        if arrived is None:
            path_at = path
        x, t = x1, t + PERIOD
    return dict(arrived=arrived is not None, time=arrived, time_to_1cm=fine, path=path_at,
                path_driven=path, least_clearance=least,
                contact_periods=int(contacts), collision_steps=int(events), end=x.tolist(),
                to_goal=float(np.linalg.norm(x - goal)), wall_s=time.perf_counter() - clock)


# --- per map ----------------------------------------------------------------------------------


def python_starts(name: str) -> tuple:
    """The file's starts from harmonav's Python bindings, ``FloorPlan.load(FILE).starts``:
    ``robot.start`` then the seeded ``[starts]``, drawn by the same Rust code as ``check``'s
    (``FloorScenario::load``), in seconds where ``check`` also certifies the map (minutes on the
    large ones). ``(None, reason)`` when the bindings are missing or the file does not load."""
    try:
        import harmonav
    except ImportError as e:
        return None, f"no harmonav Python bindings ({e})"
    try:
        starts = harmonav.FloorPlan.load(f"{PUBLIC}/{name}.toml").starts
    except Exception as e:  # the bindings' own error types; the message says what failed
        return None, f"FloorPlan.load: {e}"[:200]
    return [[float(x), float(y)] for x, y in np.asarray(starts, float)], "harmonav.FloorPlan"


def harmonav_starts(name: str, harmonav: str, cache: str, timeout: float) -> tuple:
    """``harmonav check --json``'s starts, cached; ``(None, reason)`` when it gives none."""
    out = os.path.join(cache, f"{name}.check.json")
    if not os.path.exists(out) or os.path.getsize(out) == 0:
        try:
            r = subprocess.run([harmonav, "check", f"{PUBLIC}/{name}.toml", "--json"],
                               capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, f"check > {timeout:.0f} s"
        if r.returncode != 0 or not r.stdout.strip():
            return None, (r.stderr.strip().splitlines() or ["check failed"])[-1][:200]
        with open(out, "w") as f:
            f.write(r.stdout)
    with open(out) as f:
        try:
            return [s["position"] for s in json.load(f)["starts"]], "harmonav check"
        except (ValueError, KeyError):
            return None, "check output unreadable"


def prepare(name: str, args) -> dict:
    """The map, walls, A* field, starts and plans of one file."""
    with open(f"{PUBLIC}/{name}.toml", "rb") as f:
        robot = tomllib.load(f)["robot"]
    clock = time.perf_counter()
    m = load_map(f"{PUBLIC}/maps/{name}.yaml")
    goal = robot["goal"]
    walls = wall_segments(m, goal)
    field = plan_field(m, goal)
    starts, source = None, "--own-starts"
    if name not in args.own_starts and args.starts_from in ("auto", "python"):
        starts, source = python_starts(name)
        if starts is None:
            print(f"{name}: {source}", file=sys.stderr, flush=True)
    if starts is None and name not in args.own_starts and args.starts_from in ("auto", "check"):
        starts, source = harmonav_starts(name, args.harmonav, args.cache, args.check_timeout)
    own = starts is None
    if own:
        starts = [robot["start"]] + own_starts(m, field, goal, OWN_STARTS, OWN_SEED)
    plans = [plan(m, field, s, goal) for s in starts]
    h, w = m["shape"]
    return dict(name=name, map=m, goal=goal, walls=walls, starts=starts, own_starts=own,
                starts_source=source, plans=plans,
                sensing_range=float(math.hypot(h, w) * m["res"]),
                prepare_s=time.perf_counter() - clock)


def run_one(task: tuple) -> tuple:
    name, entry, k = task
    p = PREPARED[name]
    plan_k = p["plans"][k]
    if not plan_k["reachable"]:
        return name, entry, k, dict(arrived=False, unreachable=True)
    way = plan_k["waypoints"] if entry == "HL+A*" else [p["goal"]]
    out = fly(p["map"], p["walls"], p["starts"][k], p["goal"], way, p["sensing_range"])
    out.update(start=p["starts"][k], waypoints=len(way), geodesic=plan_k["geodesic"],
               any_angle=plan_k["any_angle"])
    return name, entry, k, out


PREPARED: dict = {}


# --- the report -------------------------------------------------------------------------------


def summarise(runs: list) -> dict:
    ok = [r for r in runs if r["arrived"]]
    times = [r["time"] for r in ok]
    ratio = [r["path"] / r["geodesic"] for r in ok]
    ratio_aa = [r["path"] / r["any_angle"] for r in ok]
    flown = [r for r in runs if not r.get("unreachable")]
    return dict(starts=len(runs), arrived=len(ok),
                time_median=float(np.median(times)) if times else None,
                time_max=max(times) if times else None,
                path_over_geodesic_median=float(np.median(ratio)) if ratio else None,
                path_over_geodesic_max=max(ratio) if ratio else None,
                path_over_any_angle_median=float(np.median(ratio_aa)) if ratio_aa else None,
                path_over_any_angle_max=max(ratio_aa) if ratio_aa else None,
                runs_with_contact=sum(r["contact_periods"] > 0 for r in flown),
                least_clearance=min((r["least_clearance"] for r in flown), default=None),
                runs_with_collision_event=sum(r["collision_steps"] > 0 for r in flown),
                sim_s=sum(r.get("wall_s", 0.0) for r in flown))


def fmt(x, spec=".2f") -> str:
    return "—" if x is None else format(x, spec)


def table(summary: dict, meta: dict) -> str:
    events = not IGNORE_COLLISIONS  # navground records no collision when it ignores them
    lines = ["| map | walls | entry | arrived | time median (worst) s | path / geodesic median "
             "(worst) | path / any-angle median (worst) | runs with contact | least clearance mm |"
             + (" navground collisions |" if events else ""),
             "|---|---|---|---|---|---|---|---|---|" + ("---|" if events else "")]
    for name, cells in summary.items():
        mark = "†" if meta[name]["own_starts"] else ""
        for entry, s in cells.items():
            least = None if s["least_clearance"] is None else 1000 * s["least_clearance"]
            lines.append(
                f"| `{name}`{mark} | {meta[name]['walls']} | {entry} | {s['arrived']}/{s['starts']} | "
                f"{fmt(s['time_median'], '.1f')} ({fmt(s['time_max'], '.1f')}) | "
                f"{fmt(s['path_over_geodesic_median'], '.3f')} "
                f"({fmt(s['path_over_geodesic_max'], '.3f')}) | "
                f"{fmt(s['path_over_any_angle_median'], '.3f')} "
                f"({fmt(s['path_over_any_angle_max'], '.3f')}) | "
                f"{s['runs_with_contact']}/{s['starts']} | {fmt(least, '+.1f')} |"
                + (f" {s['runs_with_collision_event']}/{s['starts']} |" if events else ""))
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--maps", default=",".join(MAPS))
    ap.add_argument("--entries", default=",".join(ENTRIES))
    ap.add_argument("--harmonav", default="target/release/harmonav",
                    help="the CLI whose `check --json` gives the starts")
    ap.add_argument("--cache", default="/tmp/hlmaps", help="where check's JSON is kept")
    ap.add_argument("--check-timeout", type=float, default=300.0)
    ap.add_argument("--starts-from", choices=("auto", "python", "check"), default="auto",
                    help="the file's starts from harmonav's Python bindings "
                         "(FloorPlan.load(FILE).starts, seconds) or `harmonav check --json` "
                         "(minutes on the large maps); auto: the bindings if importable, else "
                         "check")
    ap.add_argument("--own-starts", default="", type=lambda v: [n for n in v.split(",") if n],
                    help="maps whose starts are drawn here without asking check "
                         "(willow-2010: check takes more than 900 s)")
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--json", help="write every run and the summary here")
    ap.add_argument("--resolve-collisions", action="store_true",
                    help="navground's default collision resolution (a disc in a wall is pushed "
                         "back out, so the judge sees about 0 mm there) and its collision "
                         "events; by default World.ignore_collisions is set and the judge sees "
                         "the raw overlap")
    args = ap.parse_args(argv)
    global IGNORE_COLLISIONS
    IGNORE_COLLISIONS = not args.resolve_collisions
    os.makedirs(args.cache, exist_ok=True)
    names = [n for n in args.maps.split(",") if n]
    entries = [e for e in args.entries.split(",") if e]
    t0 = time.perf_counter()
    meta = {}
    for name in names:
        PREPARED[name] = p = prepare(name, args)
        meta[name] = dict(walls=len(p["walls"]), starts=p["starts"], own_starts=p["own_starts"],
                          starts_source=p["starts_source"], prepare_s=p["prepare_s"],
                          waypoints=[len(q.get("waypoints", [])) for q in p["plans"]],
                          geodesic=[q.get("geodesic") for q in p["plans"]])
        print(f"{name}: {len(p['walls'])} walls, {len(p['starts'])} starts "
              f"({p['starts_source']}), prepared in {p['prepare_s']:.1f} s",
              file=sys.stderr, flush=True)
    todo = [(n, e, k) for n in names for e in entries for k in range(len(PREPARED[n]["starts"]))]
    results: dict = {n: {e: {} for e in entries} for n in names}
    with mp.get_context("fork").Pool(args.processes) as pool:
        for name, entry, k, out in pool.imap_unordered(run_one, todo, chunksize=1):
            results[name][entry][k] = out
            print(f"{time.perf_counter() - t0:6.0f} s  {name} {entry} start {k}: "
                  f"arrived={out['arrived']} t={out.get('time')} "
                  f"clearance={out.get('least_clearance', float('nan')):+.4f} "
                  f"sim {out.get('wall_s', 0):.0f} s", file=sys.stderr, flush=True)
    summary = {n: {e: summarise([results[n][e][k] for k in sorted(results[n][e])])
                   for e in entries} for n in names}
    print(table(summary, meta))
    elapsed = time.perf_counter() - t0
    print(f"\n{len(todo)} runs, {args.processes} processes, {elapsed:.0f} s")
    if args.json:
        from importlib.metadata import version

        info = dict(navground=version("navground"), radius=RADIUS, margin=MARGIN, v_max=V_MAX,
                    period=PERIOD, t_max=T_MAX, goal_tolerance=GOAL_TOL,
                    waypoint_tolerance=WAYPOINT_TOL, processes=args.processes, elapsed=elapsed,
                    ignore_collisions=IGNORE_COLLISIONS,
                    command=" ".join([os.path.basename(sys.executable)] + sys.argv))
        with open(args.json, "w") as f:
            json.dump(dict(meta=info, maps=meta, summary=summary,
                           runs={n: {e: {str(k): v for k, v in sorted(r.items())}
                                     for e, r in c.items()} for n, c in results.items()}),
                      f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())

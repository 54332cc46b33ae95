"""harmonav's floor plans (docs/maths.md §13) against navground 0.7 (HL and ORCA) in the same
maps: issue 25, "Benchmarks" item 5.

    pip install ./python "navground==0.7.*"      # navground is not a test dependency
    python examples/python/compare_navground_floorplans.py [--markdown] [--records runs.json]

Every floor-plan file in scenarios/floorplans/*.toml (not limits/) and every start of it
(``FloorPlan.starts``: ``robot.start``, then the file's seeded ``[starts]``) is run by four
methods, each driving a disc robot of the file's ``robot.radius`` (0.1 m) to its goal:

- harmonav, both laws: ``FloorPlan.run(model=..., start=...)``, the file as it stands (its
  harmonic map, its ``margin``, its sensed ``[[obstacles]]`` found online within
  ``sensor_range`` or, with ``[sensor] type = "lidar"``, from the scans alone, its
  ``max_time``, arrival within ``sim.arrival`` = 0.05 m).
- navground's HL and ORCA behaviours, given the whole map from the start: the plan's true
  walls as ``LineSegment``s, the file's ``[[obstacles]]`` too (a circle as a ``Disc``, the rest
  as 256 segments of harmonav's outline of the shape); an omnidirectional robot with 1 m/s top
  speed, 100 Hz steps, arrival within 0.05 m (its target tolerance), the file's ``max_time``.

The true walls. ``harmonav.FloorPlan`` does not expose its rings (nor its shortest path), so
this script reads the geometry from the file itself: a polygon plan's ``outer`` and ``holes``
as written; a ROS map's pixels (PGM, classified as map_server does with the YAML's thresholds,
an unknown pixel counted as occupied) with the walls the edges between free and occupied
pixels. That is the map before harmonav's pipeline (marching squares, simplification and the
opening by the robot's clearance, docs/maths.md §13.1), which only grows the walls: every
method is judged against the same, unmodified map.

Measured per run (a record of ``harmonav.study_table``, the project's one tabulation):
arrival; a collision when the clearance to a true wall or obstacle less the robot's radius is
at or below 0 (inside a wall counts negative); the closest such clearance; path length over
the shortest path, the path plus the distance still to go when stopped (both stop within
0.05 m); the time to arrive; harmonav's guarantee monitors (navground has none: False);
harmonav's kept states as "steps"; and the cost of a command: ``Behavior.compute_cmd`` timed for
navground, and for harmonav the wall time of ``FloorPlan.run`` over its commands (the
integrator and the monitors included, the map's solve on load not).

The shortest path is this script's own: a visibility graph in the free space shrunk by the
robot's radius. Its nodes are the start, the goal and, at every corner of a wall or obstacle
that points into the free space, a fan of points on the arc of radius r around it (at most
22.5° apart, at r(1 + 10⁻⁶)/cos(half a step) so the chords stay clear); an edge is kept when its
segment stays at least r from every wall segment. Dijkstra on it. The length is an upper
bound of the geodesic within the chords' excess (at most 1.3 % of a wrapped arc: 2 mm round a
right angle at r = 0.1 m); curved obstacles enter as 64-gons, within 0.3 mm. It ignores
harmonav's margin, so harmonav's ratio also carries the extra 0.1 m it keeps from the walls.
"""

import argparse
import heapq
import json
import pathlib
import sys
import time
import tomllib

import numpy as np
import yaml

import harmonav

try:
    from navground import core
except ImportError:  # pragma: no cover - the comparison needs it, the tests do not
    sys.exit('navground is needed: pip install "navground==0.7.*"')

ROOT = pathlib.Path(__file__).resolve().parents[2]
PLANS = sorted((ROOT / "scenarios" / "floorplans").glob("*.toml"))
NAVGROUND = ["HL", "ORCA"]
LAWS = ["kinematic", "dynamic"]
DT = 0.01
TOLERANCE = 0.05


# --- geometry ---------------------------------------------------------------------------------


def signed_area(ring):
    r = np.asarray(ring, float)
    return 0.5 * float(np.sum(r[:, 0] * np.roll(r[:, 1], -1) - np.roll(r[:, 0], -1) * r[:, 1]))


def oriented(ring, ccw):
    """``ring`` counter-clockwise (``ccw``) or clockwise: with the outer ring counter-clockwise
    and every hole clockwise, the free space is on the left of every edge."""
    r = np.asarray(ring, float)
    return r if (signed_area(r) > 0) == ccw else r[::-1].copy()


def ring_segments(ring):
    return np.stack([ring, np.roll(ring, -1, axis=0)], axis=1)


def corner_fans(ring, r):
    """The fan of nodes around every vertex of ``ring`` (free space on the left) where the
    ring turns right, i.e. a wall corner pointing into the free space."""
    nodes = []
    n = len(ring)
    for i in range(n):
        p0, p, p1 = ring[i - 1], ring[i], ring[(i + 1) % n]
        d1, d2 = p - p0, p1 - p
        if d1[0] * d2[1] - d1[1] * d2[0] >= 0:  # left turn or straight: not a corner to wrap
            continue
        # The normal on the left (free side) of an edge d is (-d_y, d_x); its angle:
        a1 = np.arctan2(d1[0], -d1[1])
        a2 = np.arctan2(d2[0], -d2[1])
        turn = (a1 - a2) % (2 * np.pi)  # clockwise from a1 to a2
        nodes += fan(p, a1, -turn, r)
    return nodes


def fan(p, a, sweep, r):
    """Nodes on the arc of radius r around corner ``p`` from angle ``a`` over ``sweep``: at most
    22.5° apart, out at r(1 + 10⁻⁶)/cos(half the step) so the chords between them keep r. A
    turn below 22.5° gets one node on the bisector: the vertex of the offset polygon."""
    steps = int(np.ceil(abs(sweep) / (np.pi / 8)))
    if steps <= 1:
        rho = r * (1 + 1e-6) / np.cos(sweep / 2)
        return [p + rho * np.array([np.cos(a + sweep / 2), np.sin(a + sweep / 2)])]
    rho = r * (1 + 1e-6) / np.cos(abs(sweep) / steps / 2)
    return [p + rho * np.array([np.cos(a + sweep * j / steps), np.sin(a + sweep * j / steps)])
            for j in range(steps + 1)]


def point_segment_distance(p, seg):
    """Distances (N, M) from points ``p`` (N, 2) to segments ``seg`` (M, 2, 2)."""
    a, b = seg[None, :, 0], seg[None, :, 1]
    ab = b - a
    t = np.clip(np.sum((p[:, None] - a) * ab, -1) / np.maximum(np.sum(ab * ab, -1), 1e-300), 0, 1)
    return np.linalg.norm(p[:, None] - (a + t[..., None] * ab), axis=-1)


def segment_clear(p, q, walls, r):
    """For each pair (p[i], q[i]): whether the segment stays at least r from every wall."""
    ok = np.ones(len(p), bool)
    for c in range(0, len(p), 256):
        P, Q = p[c:c + 256], q[c:c + 256]
        a, b = walls[:, 0], walls[:, 1]
        # Distances between segments that do not cross: the least of the four endpoint distances.
        d = np.minimum(point_segment_distance(P, walls), point_segment_distance(Q, walls))
        d = np.minimum(d, point_segment_distance(a, np.stack([P, Q], 1)).T)
        d = np.minimum(d, point_segment_distance(b, np.stack([P, Q], 1)).T)

        def orient(u, v, w):
            return (v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1]) - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0])

        Pi, Qi = P[:, None], Q[:, None]
        cross = (np.sign(orient(Pi, Qi, a[None])) * np.sign(orient(Pi, Qi, b[None])) < 0) & (
            np.sign(orient(a[None], b[None], Pi)) * np.sign(orient(a[None], b[None], Qi)) < 0)
        d = np.where(cross, 0.0, d)
        ok[c:c + 256] = d.min(axis=1) >= r
    return ok


def visibility_graph(world):
    """The corners' nodes in the shrunk free space and their visible pairs (built once a world)."""
    r, walls = world["radius"], world["vis_walls"]
    pts = np.array(world["corners"])
    pts = pts[world["clearance"](pts) >= -1e-9]
    i, j = np.triu_indices(len(pts), 1)
    ok = segment_clear(pts[i], pts[j], walls, r)
    adj = [[] for _ in range(len(pts) + 2)]
    for a, b in zip(i[ok], j[ok]):
        w = float(np.linalg.norm(pts[a] - pts[b]))
        adj[a + 2].append((b + 2, w))
        adj[b + 2].append((a + 2, w))
    return pts, adj


def shortest_path(world, graph, start, goal):
    """The visibility-graph shortest path of the disc from ``start`` to ``goal`` (module
    docstring), or inf: the world's graph with the two ends joined to every node they see."""
    r, walls = world["radius"], world["vis_walls"]
    corners, base = graph
    ends = np.array([start, goal], float)
    pts = np.concatenate([ends, corners])
    adj = [list(a) for a in base]
    for e in (0, 1):
        others = np.arange(e + 1, len(pts))
        ok = segment_clear(np.repeat(pts[e:e + 1], len(others), 0), pts[others], walls, r)
        for v in others[ok]:
            w = float(np.linalg.norm(pts[e] - pts[v]))
            adj[e].append((v, w))
            adj[v].append((e, w))
    dist = [np.inf] * len(pts)
    dist[0] = 0.0
    heap = [(0.0, 0)]
    while heap:
        d, u = heapq.heappop(heap)
        if u == 1:
            return d
        if d > dist[u]:
            continue
        for v, w in adj[u]:
            if d + w < dist[v]:
                dist[v] = d + w
                heapq.heappush(heap, (d + w, v))
    return np.inf


# --- the worlds -------------------------------------------------------------------------------


def load_world(path):
    """The true geometry of a floor-plan file: wall segments, navground's obstacles, the corners'
    fans and a signed clearance function (less the robot's radius)."""
    spec = tomllib.loads(path.read_text())
    r = float(spec["robot"].get("radius", 0.1))
    fp = spec["floor_plan"]
    rings, segs, corners = [], [], []
    if "outer" in fp:
        rings.append(oriented(fp["outer"], True))
        rings += [oriented(h, False) for h in fp.get("holes", [])]
        occupied = None
    else:
        occupied, to_world, res = read_map(path.parent / fp["map"])
        segs.append(pixel_walls(occupied, to_world, res))
        corners += pixel_corners(occupied, to_world, res, r)
    shapes, discs, obstacle_rings, vis = [], [], [], []
    for o in spec.get("obstacles", []):
        if o["type"] == "circle":
            s = harmonav.circle(o["center"], o["radius"])
            discs.append((tuple(o["center"]), float(o["radius"])))
        elif o["type"] == "ellipse":
            s = harmonav.ellipse(o["center"], o["semi_axes"], o.get("angle_deg", 0.0))
        elif o["type"] == "polygon":
            s = harmonav.polygon(o["vertices"], o.get("corner_radius", 0.0))
        elif o["type"] == "star":
            s = harmonav.star(o["center"], o["radius"], [tuple(h) for h in o["harmonics"]])
        else:
            raise ValueError(f"{path}: obstacle type {o['type']!r} not handled")
        shapes.append(s)
        ring = oriented(s.outline(256), False)
        obstacle_rings.append((o["type"] == "circle", ring))
        coarse = oriented(s.outline(64), False)
        vis.append(ring_segments(coarse))
        corners += corner_fans(coarse, r)
    for ring in rings:
        segs.append(ring_segments(ring))
        corners += corner_fans(ring, r)
    vis = segs + vis
    for _, ring in obstacle_rings:
        segs.append(ring_segments(ring))
    walls = np.concatenate(segs)
    # navground: the plan's walls and the non-circle obstacles as segments, circles as discs.
    ng_segments = np.concatenate(
        [s for s in segs[: len(segs) - len(obstacle_rings)]]
        + [ring_segments(ring) for is_circle, ring in obstacle_rings if not is_circle] or [np.zeros((0, 2, 2))])

    def clearance(x):
        """Signed distance from the robot's disc to the true walls and obstacles (N,)."""
        x = np.atleast_2d(np.asarray(x, float))
        d = np.empty(len(x))
        for c in range(0, len(x), 512):
            xs = x[c:c + 512]
            dw = point_segment_distance(xs, walls[: len(walls) - sum(len(q) for _, q in obstacle_rings)]).min(1)
            if occupied is not None:
                inside = pixel_occupied(occupied, xs, to_world, res)
            else:
                inside = ~in_polygon(xs, rings)
            dw = np.where(inside, -dw, dw)
            for s in shapes:
                dw = np.minimum(dw, s.signed_distance(xs))
            d[c:c + 512] = dw
        return d - r

    return {"name": spec["name"], "radius": r, "walls": walls, "vis_walls": np.concatenate(vis), "ng_segments": ng_segments,
            "discs": discs, "corners": corners, "clearance": clearance,
            "obstacles": len(spec.get("obstacles", [])), "goal": np.array(spec["robot"]["goal"], float),
            # harmonav's perception: the file's lidar (the obstacles from scans alone), or the
            # exact shapes within sim.sensor_range.
            "sensing": (f"lidar {spec['sensor']['range']:g} m" if spec.get("sensor", {}).get("type") == "lidar"
                        else f"disc {spec.get('sim', {}).get('sensor_range', 1.0):g} m"),
            "max_time": float(spec.get("sim", {}).get("max_time", 120.0))}


def in_polygon(x, rings):
    """Even-odd rule over every ring: inside the outer ring and outside every hole."""
    inside = np.zeros(len(x), bool)
    for ring in rings:
        a, b = ring, np.roll(ring, -1, axis=0)
        ya, yb = a[None, :, 1], b[None, :, 1]
        px, py = x[:, None, 0], x[:, None, 1]
        straddle = (ya > py) != (yb > py)
        xint = a[None, :, 0] + (py - ya) * (b[None, :, 0] - a[None, :, 0]) / np.where(yb == ya, 1, yb - ya)
        inside ^= (np.sum(straddle & (px < xint), axis=1) % 2).astype(bool)
    return inside


def read_map(yaml_path):
    """A map_server map: occupied (rows top to bottom), pixel → world, resolution."""
    meta = yaml.safe_load(yaml_path.read_text())
    data = (yaml_path.parent / meta["image"]).read_bytes()
    tokens, pos = [], 0
    while len(tokens) < 4:  # P5, width, height, maxval; comments skipped
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        tokens.append(data[pos:end])
        pos = end
    assert tokens[0] == b"P5", f"{yaml_path}: only binary PGM is read here"
    w, h, maxval = int(tokens[1]), int(tokens[2]), int(tokens[3])
    img = np.frombuffer(data[pos + 1: pos + 1 + w * h], np.uint8).reshape(h, w).astype(float)
    p = img / maxval if meta.get("negate", 0) else (maxval - img) / maxval
    occupied = p >= float(meta.get("free_thresh", 0.196))  # occupied or unknown: a wall
    res = float(meta["resolution"])
    ox, oy = meta["origin"][0], meta["origin"][1]

    def to_world(col, row):
        """The world point of the pixel grid's corner (col, row), rows counted from the top."""
        return np.stack([ox + np.asarray(col, float) * res, oy + (h - np.asarray(row, float)) * res], -1)

    return occupied, to_world, res


def pixel_occupied(occupied, x, to_world, res):
    h, w = occupied.shape
    o = to_world(0, h)
    col = np.floor((x[:, 0] - o[0]) / res).astype(int)
    row = h - 1 - np.floor((x[:, 1] - o[1]) / res).astype(int)
    out = (col < 0) | (col >= w) | (row < 0) | (row >= h)
    return out | occupied[np.clip(row, 0, h - 1), np.clip(col, 0, w - 1)]


def pixel_walls(occupied, to_world, res):
    """The edges between free and occupied pixels, merged into runs (segments (M, 2, 2))."""
    h, w = occupied.shape
    pad = np.pad(occupied, 1, constant_values=True)
    segs = []
    # Horizontal edges: between row i-1 and i (grid line i), over columns.
    for i in range(h + 1):
        diff = pad[i, 1:-1] != pad[i + 1, 1:-1]
        for c0, c1 in runs(diff):
            segs.append(to_world([c0, c1], [i, i]))
    for j in range(w + 1):
        diff = pad[1:-1, j] != pad[1:-1, j + 1]
        for r0, r1 in runs(diff):
            segs.append(to_world([j, j], [r0, r1]))
    return np.array(segs)


def runs(mask):
    """[start, end) of every run of True."""
    m = np.concatenate([[False], mask, [False]]).astype(int)
    d = np.diff(m)
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)))


def pixel_corners(occupied, to_world, res, r):
    """The fans around every grid corner where one of the four pixels is occupied (a wall's
    corner pointing into the free space)."""
    h, w = occupied.shape
    pad = np.pad(occupied, 1, constant_values=True)
    # Grid corner (i, j): pixels pad[i, j] (up-left), pad[i, j+1] (up-right), pad[i+1, j], pad[i+1, j+1].
    ul, ur, dl, dr = pad[:-1, :-1], pad[:-1, 1:], pad[1:, :-1], pad[1:, 1:]
    count = ul.astype(int) + ur + dl + dr
    nodes = []
    # The occupied pixel's direction (in world axes, y up) → the fan points away from it.
    for occ, away in ((ul, (1, -1)), (ur, (-1, -1)), (dl, (1, 1)), (dr, (-1, 1))):
        for i, j in zip(*np.nonzero(occ & (count == 1))):
            p = to_world(j, i)
            a = np.arctan2(away[1], away[0])
            nodes += fan(p, a - np.pi / 4, np.pi / 2, r)
    return nodes


# --- methods ----------------------------------------------------------------------------------


def path_length(x):
    return float(np.sum(np.linalg.norm(np.diff(x, axis=0), axis=1)))


def run_harmonav(plan, world, law, start, index, shortest):
    t0 = time.perf_counter()
    res = plan.run(model=law, start=start)
    wall = time.perf_counter() - t0
    s = res.summary
    held = all(g["passed"] for g in s["guarantees"] if g["name"] != "reached-goal")
    ratio = (path_length(res.x) + np.linalg.norm(res.x[-1] - world["goal"])) / shortest
    cost = wall / max(1, s.get("commands") or len(res.x)) * 1e6
    return record(world, law, "file", index, bool(s["reached"]), world["clearance"](res.x).min(), ratio,
                  s["time_s"], cost, held, steps=len(res.x) - 1, error=s.get("error"), end=res.x[-1])


def run_navground(world, kind, start, index, shortest):
    """One navground run as a record; a run that raises is a record with reached False."""
    xs, spent, reached, error = [np.asarray(start, float)], 0.0, False, None
    try:
        b = core.Behavior.make_type(kind)
        b.kinematics = core.kinematics.OmnidirectionalKinematics(max_speed=1.0)
        b.radius = world["radius"]
        b.optimal_speed = 1.0
        b.position = tuple(start)
        b.target = core.Target.Point(tuple(world["goal"]), TOLERANCE)
        state = b.environment_state
        state.static_obstacles = [core.Disc(c, r) for c, r in world["discs"]]
        state.line_obstacles = [core.LineSegment(tuple(p), tuple(q)) for p, q in world["ng_segments"]]
        for _ in range(int(world["max_time"] / DT)):
            t0 = time.perf_counter()
            cmd = b.compute_cmd(DT)
            spent += time.perf_counter() - t0
            b.actuate(cmd, DT)
            xs.append(np.array(b.position))
            if b.check_if_target_satisfied():
                reached = True
                break
    except Exception as e:  # noqa: BLE001 - a failed run is a row, not a crash
        error = f"{type(e).__name__}: {e}"
    x = np.array(xs)
    ratio = (path_length(x) + np.linalg.norm(x[-1] - world["goal"])) / shortest
    steps = max(1, len(xs) - 1)
    return record(world, "navground", kind, index, reached, world["clearance"](x).min(), ratio,
                  (len(xs) - 1) * DT, spent / steps * 1e6, False, error=error, end=x[-1])


def record(world, law, policy, index, reached, closest, ratio, t, cost_us, held, steps=None, error=None,
           end=None):
    """A row of the study table: a collision is a clearance (to a true wall or obstacle, less
    the radius) at or below 0."""
    return {
        "world": world["name"], "generator": "compare_navground_floorplans",
        "obstacles": world["obstacles"], "law": law,
        "damping" if law == "dynamic" else "speed": policy, "k": None, "sensing": "global" if law == "navground" else world["sensing"],
        "margin": 0.0 if law == "navground" else 0.1, "physics": "builtin", "max_time": world["max_time"],
        "error": error, "reached": bool(reached), "time_s": t if reached else None,
        "path_over_shortest": float(ratio) if reached else None,
        "min_clearance": float(closest), "collisions": int(closest <= 0.0), "overshoot": None,
        "steps": steps, "guarantees_held": held, "command_us": cost_us, "start_index": index,
        # Not columns of the table: the start's index and where the run ended.
        "end": None if end is None else [float(end[0]), float(end[1])],
        "final_distance": None if end is None else float(np.linalg.norm(np.asarray(end) - world["goal"])),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--markdown", action="store_true", help="print a blank line after each title")
    ap.add_argument("--records", type=pathlib.Path, help="also write every run's record to this JSON file")
    args = ap.parse_args()
    records = []
    for path in PLANS:
        plan = harmonav.FloorPlan.load(path)
        world = load_world(path)
        rows = []
        graph = visibility_graph(world)
        for index, start in enumerate(plan.starts):
            shortest = shortest_path(world, graph, start, world["goal"])
            for law in LAWS:
                rows.append(run_harmonav(plan, world, law, start, index, shortest))
            for kind in NAVGROUND:
                rows.append(run_navground(world, kind, start, index, shortest))
            for r in rows[-4:]:
                r["shortest_m"] = shortest
        records += rows
        title = f"{world['name']} ({len(plan.starts)} starts)"
        print((f"#### {title}\n\n" if args.markdown else f"== {title}\n") + harmonav.study_table(rows))
        for r in rows:
            print(f"  start {r['start_index']} {r['law']:9} {str(r.get('speed') or r.get('damping')):5} "
                  f"shortest {r['shortest_m']:.2f} m  reached {r['reached']!s:5} clearance {r['min_clearance']:+.3f} "
                  f"path/shortest {r['path_over_shortest'] or float('nan'):.3f} time {r['time_s'] or float('nan'):.2f} "
                  f"end ({r['end'][0]:.2f}, {r['end'][1]:.2f}) {r['final_distance']:.2f} m to go"
                  + (f"  error {r['error']}" if r["error"] else ""))
        print()
    if args.records:
        args.records.write_text(json.dumps(records, indent=1, default=float))


if __name__ == "__main__":
    main()

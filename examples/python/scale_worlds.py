"""The seeded disc worlds of the dynamic law's scale table (docs/maths.md §9, part 3, and
docs/benchmarks.md): worlds of radius 5, 20, 50 and 100 m whose discs keep their size (radius
0.3–1 m) while the world grows, start and goal at ±0.8 R.

    python examples/python/scale_worlds.py OUT_DIR [--seeds 3]
    for f in OUT_DIR/*.toml; do
        harmonav run "$f" --model kinematic --json
        harmonav run "$f" --model dynamic --damping auto --json    # or shaped, paper
    done

Writes scenario files only: no dependency beyond the standard library.
"""

import argparse
import math
import pathlib
import random

# (name, radius m, discs, sector sensing)
CASES = [
    ("r5-6-sector", 5, 6, True),
    ("r20-60-sector", 20, 60, True),
    ("r50-20-global", 50, 20, False),
    ("r50-20-sector", 50, 20, True),
    ("r100-0", 100, 0, False),
]


def world(name: str, radius: float, count: int, sector: bool, seed: int) -> str:
    """One scenario: `count` disjoint discs clear of the start, the goal and the wall."""
    rng = random.Random(seed)
    start, goal = (-0.8 * radius, 0.0), (0.8 * radius, 0.0)
    discs: list[tuple[tuple[float, float], float]] = []
    for _ in range(100_000):
        if len(discs) == count:
            break
        r = rng.uniform(0.3, 1.0)
        a = rng.uniform(0.0, 2.0 * math.pi)
        d = math.sqrt(rng.uniform(0.0, 1.0)) * (radius - r - 1.0)
        c = (d * math.cos(a), d * math.sin(a))
        if any(math.dist(c, p) < r + 0.8 for p in (start, goal)):
            continue
        if any(math.dist(c, q) < r + rq + 0.3 for q, rq in discs):
            continue
        if math.hypot(*c) + r > radius - 0.5:
            continue
        discs.append((c, r))
    lines = [f'name = "{name}"', "[workspace]", 'type = "circle"', "center = [0.0, 0.0]",
             f"radius = {radius}"]
    for c, r in discs:
        lines += ["[[obstacles]]", 'type = "circle"', f"center = [{c[0]:.4f}, {c[1]:.4f}]",
                  f"radius = {r:.4f}"]
    # The start 1.3 % of R off the axis through the goal (off its saddle's stable manifold).
    lines += ["[robot]", 'model = "kinematic"', f"start = [{start[0]}, {start[1] + 0.013 * radius}]",
              f"goal = [{goal[0]}, {goal[1]}]"]
    if sector:
        lines += ["[sensor]", "range = 3.0", "aperture_deg = 120.0"]
    lines += ["[sim]", "dt = 0.01", "max_time = 2000.0", "goal_tolerance = 0.05"]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=pathlib.Path)
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for seed in range(args.seeds):
        for name, radius, count, sector in CASES:
            text = world(f"{name}-s{seed}", radius, count, sector, 1000 * seed + radius + count)
            (args.out / f"{name}-s{seed}.toml").write_text(text)


if __name__ == "__main__":
    main()

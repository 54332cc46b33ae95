"""``report``: the tables of docs/benchmarks.md from an experiment's records, and the
distributions of path/shortest and of time by cell (matplotlib, optional).

A *cell* is one configuration of the grid over its worlds and starts: the generated worlds of
one obstacle count are one cell, as in ``cargo xtask quality``; each scenario file is its own.
The statistics are those of ``harmonav_bench::quality::CellStats`` (nearest-rank quantiles, the
path and time over the runs that arrived, the time ratio against the kinematic law under the
paper's speed in the same world, a run that did not arrive counting as ``inf``), and the table
is printed as ``cargo xtask quality`` prints it, so the two can be compared line by line."""

from __future__ import annotations

import math
import os
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

from .records import read_records

#: The columns the report reads.
COLUMNS = (
    "run",
    "world",
    "generator",
    "obstacles",
    "law",
    "k",
    "damping",
    "speed",
    "sensing",
    "margin",
    "max_time",
    "physics",
    "start_index",
    "error",
    "reached",
    "outcome",
    "time_s",
    "path_over_shortest",
    "min_clearance",
    "collisions",
    "overshoot",
    "steps",
    "rejected_steps",
    "guarantees_held",
)

#: The speed policy of the kinematic law that the dynamic law's time is compared with (the
#: table's "time / kinematic (paper speed)", as xtask's ``REFERENCE_SPEED``).
REFERENCE_SPEED = "paper"


def quantiles(values: Sequence[float]) -> Tuple[float, float, float]:
    """Median, 90th percentile (nearest rank) and maximum; NaN for no values
    (``harmonav_bench::quality::quantiles``)."""
    v = sorted(values)
    if not v:
        return (math.nan,) * 3
    n = len(v)

    def rank(q: float) -> float:
        return v[min(max(math.ceil(q * n), 1), n) - 1]

    return rank(0.5), rank(0.9), v[-1]


def _fixed(x: float, digits: int) -> str:
    """Rust's ``{:.digits}``."""
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return f"{x:.{digits}f}"


def _exp(x: float, digits: int) -> str:
    """Rust's ``{:.digits e}``: ``4.2e-3``, ``0.0e0``."""
    if math.isnan(x) or math.isinf(x):
        return _fixed(x, digits)
    mantissa, exponent = f"{x:.{digits}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def _plain(x: float) -> str:
    """Rust's ``{}`` of an f64 for the margins: ``0``, ``0.1``."""
    return str(int(x)) if float(x).is_integer() else repr(float(x))


def _fmt3(v: Tuple[float, float, float], digits: int) -> str:
    return " / ".join(_fixed(x, digits) for x in v)


@dataclass
class Cell:
    """The statistics of one cell (``harmonav_bench::quality::CellStats``)."""

    key: Tuple
    label: Dict[str, Any]
    runs: int = 0
    errors: int = 0
    reached: int = 0
    guarantees_held: int = 0
    collisions: int = 0
    ratio: Tuple[float, float, float] = (math.nan,) * 3
    time: Tuple[float, float, float] = (math.nan,) * 3
    min_clearance: float = math.inf
    overshoot: float = 0.0
    steps: Tuple[float, float, float] = (math.nan,) * 3
    #: Time to goal per (world, start), None where it did not arrive.
    times: Dict[Tuple, Optional[float]] = field(default_factory=dict)
    ratios: List[float] = field(default_factory=list)
    arrived_times: List[float] = field(default_factory=list)


def _cell_key(r: Dict[str, Any]) -> Tuple:
    world = None if r["generator"] else r["world"]
    policy = r["damping"] if r["law"] == "dynamic" else r["speed"]
    return (
        world,
        r["obstacles"],
        r["law"],
        policy,
        r["k"],
        r["sensing"],
        r["margin"],
        r["physics"],
        r["max_time"],
    )


def cells(table) -> List[Cell]:
    """The cells of the records in ``table`` (an Arrow table with ``COLUMNS``), ordered as
    ``cargo xtask quality`` orders them: by world, obstacle count, law, sensing, ``k``, margin
    and policy, each in the order the records first give its values."""
    rows = table.to_pylist()
    order: List[Dict[Any, int]] = [dict() for _ in range(9)]
    grouped: Dict[Tuple, List[Dict[str, Any]]] = {}
    for r in rows:
        key = _cell_key(r)
        for i, v in enumerate(key):
            # A policy is ordered among its law's policies (speed or damping).
            order[i].setdefault((key[2], v) if i == 3 else v, len(order[i]))
        grouped.setdefault(key, []).append(r)

    def rank(k: Tuple, i: int) -> int:
        return order[i][(k[2], k[3]) if i == 3 else k[i]]

    # world, M, law, sensing, k, margin, policy, physics, max time
    sort = (0, 1, 2, 5, 4, 6, 3, 7, 8)
    keys = sorted(grouped, key=lambda k: tuple(rank(k, i) for i in sort))
    out = []
    for key in keys:
        runs = grouped[key]
        first = runs[0]
        c = Cell(key, {k: first[k] for k in first})
        c.runs = len(runs)
        c.errors = sum(r["error"] is not None for r in runs)
        arrived = [r for r in runs if r["reached"]]
        c.reached = len(arrived)
        c.guarantees_held = sum(bool(r["guarantees_held"]) for r in runs)
        c.collisions = sum(r["collisions"] or 0 for r in runs)
        c.ratios = [r["path_over_shortest"] for r in arrived if r["path_over_shortest"] is not None]
        c.ratio = quantiles(c.ratios)
        c.arrived_times = [r["time_s"] for r in arrived]
        c.time = quantiles(c.arrived_times)
        clearances = [r["min_clearance"] for r in runs if r["min_clearance"] is not None]
        c.min_clearance = min(clearances, default=math.inf)
        c.overshoot = max((r["overshoot"] for r in runs if r["overshoot"] is not None), default=0.0)
        c.steps = quantiles(
            [float(r["steps"] + r["rejected_steps"]) for r in runs if r["steps"] is not None]
        )
        c.times = {
            (r["world"], r["start_index"]): (r["time_s"] if r["reached"] else None) for r in runs
        }
        out.append(c)
    return out


def time_ratio(cell: Cell, reference: Cell) -> Tuple[float, float, float]:
    """The time of ``cell`` over the time of ``reference`` in each world and start both ran
    (``harmonav_bench::quality::time_ratio``): one that ``cell`` did not finish counts as
    ``inf``, one that ``reference`` did not finish is left out."""
    ratios = []
    for where, t in cell.times.items():
        r = reference.times.get(where)
        if r is None:
            continue
        ratios.append((t if t is not None else math.inf) / r)
    return quantiles(ratios)


def _twin(all_cells: Sequence[Cell], c: Cell) -> Optional[Cell]:
    world, m, _, _, k, sensing, margin, physics, max_time = c.key
    for o in all_cells:
        if o.key == (world, m, "kinematic", REFERENCE_SPEED, k, sensing, margin, physics, max_time):
            return o
    return None


HEADER = (
    "| law | damping or speed | k | sensing | margin | M | arrived | guarantees held | "
    "collisions | path/shortest median / p90 / max | time to goal median / p90 / max (s) | "
    "time / kinematic (paper speed) median / p90 / max | min clearance (m) | overshoot (m) | "
    "steps median / p90 / max |"
)


def table_text(all_cells: Sequence[Cell]) -> str:
    """The Markdown table of ``cargo xtask quality`` (``xtask/src/quality.rs::table``), with a
    leading ``world`` column when a cell is a scenario file, ``physics`` and ``max time`` when
    they vary, and ``errors`` when a run could not be made."""
    world_col = any(c.key[0] is not None for c in all_cells)
    physics_col = len({c.key[7] for c in all_cells}) > 1
    time_col = len({c.key[8] for c in all_cells}) > 1
    error_col = any(c.errors for c in all_cells)
    head, cols = HEADER, HEADER.count("|") - 1
    extra_front = (["world"] if world_col else [])
    extra_back = (["physics"] if physics_col else []) + (["max time (s)"] if time_col else [])
    extra_back += ["errors"] if error_col else []
    if extra_front:
        head = "| " + " | ".join(extra_front) + " " + head
    if extra_back:
        head = head + " " + " | ".join(extra_back) + " |"
    n = cols + len(extra_front) + len(extra_back)
    lines = [head, "|" + "---|" * n]
    for c in all_cells:
        world, m, law, policy, k, sensing, margin, physics, max_time = c.key
        twin = _twin(all_cells, c) if law == "dynamic" else None
        ratio = _fmt3(time_ratio(c, twin), 2) if twin is not None else "—"
        cells_ = [
            law.capitalize() if law else "—",
            policy or "—",
            k or "—",
            sensing or "—",
            _plain(margin) if margin is not None else "—",
            str(m) if m is not None else "—",
            f"{c.reached}/{c.runs}",
            f"{c.guarantees_held}/{c.runs}",
            str(c.collisions),
            _fmt3(c.ratio, 3),
            _fmt3(c.time, 1),
            ratio,
            _fixed(c.min_clearance, 4),
            _exp(c.overshoot, 1),
            _fmt3(c.steps, 0),
        ]
        front = [world] if world_col else []
        back = ([physics] if physics_col else []) + ([_plain(max_time)] if time_col else [])
        back += [str(c.errors)] if error_col else []
        lines.append("| " + " | ".join(front + cells_ + back) + " |")
    return "\n".join(lines) + "\n"


def summary_text(table) -> str:
    """The experiment in a few lines: runs, outcomes, errors (the first three messages)."""
    rows = table.select(["outcome", "error"]).to_pylist()
    outcomes = Counter(r["outcome"] or "error" for r in rows)
    errors = [r["error"] for r in rows if r["error"] is not None]
    text = f"{len(rows)} runs: " + ", ".join(f"{n} {o}" for o, n in outcomes.most_common()) + "\n"
    for e in errors[:3]:
        text += f"  error: {e}\n"
    if len(errors) > 3:
        text += f"  … and {len(errors) - 3} more errors (column `error`)\n"
    return text


def _label(c: Cell) -> str:
    world, m, law, policy, k, sensing, margin, physics, _ = c.key
    parts = [world or f"M={m}", f"{law} {policy}", f"k {k}", sensing]
    if margin:
        parts.append(f"margin {_plain(margin)}")
    if physics and physics != "builtin":
        parts.append(physics)
    return ", ".join(str(p) for p in parts)


def plot(all_cells: Sequence[Cell], folder: Path) -> List[Path]:
    """Box plots of path/shortest and of time to goal by cell (runs that arrived), as SVG files
    in ``folder``. Needs matplotlib (``pip install './python[report]'``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams["svg.fonttype"] = "none"  # text stays text
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    labels = [_label(c) for c in all_cells]
    for name, values, xlabel in (
        ("path_over_shortest", [c.ratios for c in all_cells], "path length / shortest path"),
        ("time_s", [c.arrived_times for c in all_cells], "time to goal (s)"),
    ):
        height = 1.2 + 0.32 * len(all_cells)
        fig, ax = plt.subplots(figsize=(8.0, height))
        shown = [v if v else [math.nan] for v in values]
        try:  # matplotlib ≥ 3.10
            ax.boxplot(shown, orientation="horizontal", whis=(0, 90), showfliers=False)
        except TypeError:
            ax.boxplot(shown, vert=False, whis=(0, 90), showfliers=False)
        ax.set_yticks(range(1, len(labels) + 1), labels, fontsize=7)
        ax.invert_yaxis()
        ax.set_xlabel(xlabel + " (runs that arrived; whiskers: min and p90)")
        ax.grid(axis="x", alpha=0.3)
        fig.tight_layout()
        path = folder / f"{name}.svg"
        fig.savefig(path)
        plt.close(fig)
        written.append(path)
    return written


def report(out: "os.PathLike[str] | str", plots: Optional["os.PathLike[str] | str"] = None) -> str:
    """The report of the experiment in ``out``: the summary and the table, as text; with
    ``plots`` (a folder) also the distributions as SVG files there."""
    table = read_records(out, COLUMNS)
    all_cells = cells(table)
    text = summary_text(table) + "\n" + table_text(all_cells)
    if plots is not None:
        for p in plot(all_cells, Path(plots)):
            text += f"\nwrote {p}"
        text += "\n"
    return text


def main_report(args) -> int:
    plots = None
    if not args.no_plots:
        try:
            import matplotlib  # noqa: F401

            plots = args.plots or Path(args.out) / "report"
        except ImportError:
            if args.plots:
                raise SystemExit(
                    "report --plots needs matplotlib: pip install './python[report]'"
                ) from None
    try:
        text = report(args.out, plots)
    except FileNotFoundError as e:
        print(f"report: {e}", file=__import__("sys").stderr)
        return 2
    print(text, end="")
    if plots is None and not args.no_plots:
        print("(no plots: matplotlib is not installed; pip install './python[report]')")
    return 0

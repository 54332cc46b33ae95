"""``report``: the tables of docs/benchmarks.md from an experiment's records, and the
distributions of path/shortest and of time by cell (matplotlib, optional).

A *cell* is one configuration of the grid over its worlds and starts: the generated worlds of
one obstacle count are one cell, as in ``cargo xtask quality``; each scenario file is its own.
The cells, their statistics and the table come from ``harmonav_bench::table`` through the
extension (``harmonav.study_cells``, ``harmonav.study_table``): the one implementation that
``cargo xtask quality`` also prints, so nothing here computes a statistic. A column that no
run of a cell measured (path/shortest under ``[measure] shortest = false``, the time to goal of a
cell where no run arrived) is printed ``—``, as the table's other unmeasured cells are."""

from __future__ import annotations

import math
import os
import re
import sys
from collections import Counter
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

from ..harmonav import study_cells, study_table
from .records import manifest, read_records

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


def cells(table) -> List[Dict[str, Any]]:
    """The cells of the records in ``table`` (an Arrow table with ``COLUMNS``), in the table's
    order (``harmonav.study_cells``, i.e. ``harmonav_bench::table::cells``): a dict each with
    the cell's configuration, its statistics and the path/shortest ``ratios`` and
    ``arrived_times`` of its runs that arrived."""
    return study_cells(table.to_pylist())


#: A table cell of no measured value: ``NaN``, or ``NaN / NaN / NaN`` (median, p90, max of no
#: runs), between the cell separators.
_UNMEASURED = re.compile(r"(?<=\| )NaN(?: / NaN)*(?= \|)")


def _dashes(text: str) -> str:
    """``text`` (a Markdown table) with its unmeasured cells ``—``."""
    return _UNMEASURED.sub("—", text)


def table_text(table) -> str:
    """The Markdown table of the records in ``table``, as ``cargo xtask quality`` prints it
    (``harmonav.study_table``, i.e. ``harmonav_bench::table::table``: one implementation for
    both), a statistic of no runs printed ``—``."""
    return _dashes(study_table(table.to_pylist()))


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


def _plain(x: float) -> str:
    """A margin as the table prints it: ``0``, ``0.1``."""
    return str(int(x)) if float(x).is_integer() else repr(float(x))


def _label(c: Dict[str, Any]) -> str:
    parts = [c["world"] or f"M={c['obstacles']}", f"{c['law']} {c['policy']}", f"k {c['k']}",
             c["sensing"]]
    if c["margin"]:
        parts.append(f"margin {_plain(c['margin'])}")
    if c["physics"] and c["physics"] != "builtin":
        parts.append(c["physics"])
    return ", ".join(str(p) for p in parts)


def plot(all_cells: Sequence[Dict[str, Any]], folder: Path) -> List[Path]:
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
        ("path_over_shortest", [c["ratios"] for c in all_cells], "path length / shortest path"),
        ("time_s", [c["arrived_times"] for c in all_cells], "time to goal (s)"),
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
    runs = manifest(out)["runs"]
    rows = table.to_pylist()  # once: the table and the plots read the same rows
    text = summary_text(table) + "\n" + _dashes(study_table(rows))
    if table.num_rows < runs:
        text = (
            f"{table.num_rows} of the experiment's {runs} runs are written: it is not finished "
            "(run it again to resume)\n" + text
        )
    if plots is not None:
        for p in plot(study_cells(rows), Path(plots)):
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
                print(
                    "error: report --plots needs matplotlib: pip install './python[report]'",
                    file=sys.stderr,
                )
                return 2
    if plots is not None and Path(plots).exists() and not Path(plots).is_dir():
        print(f"error: --plots {plots} is a file, not a folder", file=sys.stderr)
        return 2
    try:
        text = report(args.out, plots)
    except OSError as e:  # no records, or a --plots folder that cannot be written
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(text, end="")
    if plots is None and not args.no_plots:
        print("(no plots: matplotlib is not installed; pip install './python[report]')")
    return 0

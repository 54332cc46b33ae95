"""From a spec to tasks, and from a task to its records.

Run ``i`` of an experiment is world ``i // (C·S)``, cell ``(i // S) % C`` and start ``i % S``
(``C`` cells, ``S`` starts per world, 1 without ``[starts]``): the same spec always gives the
same runs in the same order. Task ``t`` holds runs ``[t·T, (t + 1)·T)`` (``T`` =
``engine.task_runs``) and becomes the Parquet part ``part-<t>.parquet``. Tasks are made one at a
time, so the driver's memory does not grow with the number of runs.

``execute(task)`` is the one function both engines run (a thread of the local engine, a Ray
worker): it calls ``harmonav.run_batch`` on the task's runs and returns their records as an
Arrow table. The records of a configuration are therefore the same whichever engine ran it."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any, Dict, Iterator, List, Optional, Sequence

import harmonav

from .spec import RUN_KEYS, Spec, run_config

#: The configuration columns, first in every record (``docs/experiments.md``).
CONFIG_COLUMNS = (
    "experiment",
    "run",
    "world",
    "generator",
    "scenario",
    "seed",
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
    "start_seed",
    "start_x",
    "start_y",
)

#: The outcome columns that every record has (null where the run could not be made).
RESULT_COLUMNS = (
    "error",
    "reached",
    "outcome",
    "outcome_detail",
    "time_s",
    "path_length",
    "shortest_length",
    "path_over_shortest",
    "min_clearance",
    "final_distance",
    "max_speed",
    "speed_bound",
    "collisions",
    "discoveries",
    "steps",
    "rejected_steps",
    "recorded_states",
    "overshoot",
    "guarantees_held",
    "all_passed",
    "k_policy",
    "warnings",
    "version",
)


@dataclass(frozen=True)
class Task:
    """Runs ``first .. first + len(runs)`` of an experiment: ``runs`` are pairs of the record's
    configuration columns and the run's configuration for ``harmonav.run_batch``."""

    index: int
    first: int
    runs: List[Any]
    shortest: bool


class Plan:
    """The runs of a spec, with the starts of each world drawn once."""

    def __init__(self, spec: Spec):
        self.spec = spec
        self.cells = spec.cells
        self.per_world = spec.starts.count if spec.starts is not None else 1
        self.runs = spec.runs
        self.task_runs = spec.engine.task_runs
        self.tasks = -(-self.runs // self.task_runs)
        self._starts: Dict[int, Sequence[Sequence[float]]] = {}

    def _world_starts(self, w: int) -> Optional[Sequence[Sequence[float]]]:
        """The starts of world ``w``: the spec's points, or its seeded random free starts drawn
        in the world under the grid's largest margin (so every start is free in every cell)."""
        starts = self.spec.starts
        if starts is None:
            return None
        if starts.points is not None:
            return starts.points
        if w not in self._starts:
            world = self.spec.worlds[w]
            config = dict(world.config)
            margins = [c["margin"] for c in self.cells if c["margin"] is not None]
            if margins:
                config["margin"] = max(margins)
            # One world's starts at a time: tasks are made in run order, and 10⁶ starts of each
            # of 10³ worlds would not fit.
            self._starts = {
                w: harmonav.random_start_points(config, starts.random, starts.seed)
            }
        return self._starts[w]

    def run(self, i: int):
        """Run ``i``: (its configuration columns, its ``run_batch`` configuration)."""
        s_count, c_count = self.per_world, len(self.cells)
        w, c, s = i // (c_count * s_count), (i // s_count) % c_count, i % s_count
        world, cell = self.spec.worlds[w], self.cells[c]
        config = run_config(world.config, cell)
        columns: Dict[str, Any] = {
            "experiment": self.spec.name,
            "run": i,
            "world": world.label,
            "generator": world.generator,
            "scenario": world.scenario,
            "seed": world.seed,
            "obstacles": world.config.get("obstacles"),
        }
        columns.update(cell)
        starts = self._world_starts(w)
        if starts is not None:
            x, y = starts[s]
            config["start"] = [float(x), float(y)]
            config["start_index"] = s
            columns.update(
                start_index=s,
                start_seed=self.spec.starts.seed if self.spec.starts.random else None,
                start_x=float(x),
                start_y=float(y),
            )
        return columns, config

    def task(self, t: int) -> Task:
        first = t * self.task_runs
        last = min(first + self.task_runs, self.runs)
        return Task(t, first, [self.run(i) for i in range(first, last)], self.spec.shortest)

    def iter_tasks(self, indices: Sequence[int]) -> Iterator[Task]:
        for t in indices:
            yield self.task(t)


def _flatten(columns: Dict[str, Any], record: Dict[str, Any]) -> Dict[str, Any]:
    """One row: the configuration columns (the world's own values where the spec gave none),
    the outcome columns, then ``guarantee.<name>.passed`` and ``guarantee.<name>.<measured>``
    for every guarantee of the run (a measured value that is not a number or a boolean is
    stored as its JSON text)."""
    row = dict.fromkeys(CONFIG_COLUMNS)
    row.update(columns)
    effective = record.pop("effective", None) or {}
    for key in ("law", "k", "damping", "speed", "sensing", "margin", "max_time", "obstacles"):
        name = RUN_KEYS.get(key, key)
        if name in effective:
            row[key] = effective[name]
    if row["physics"] is None:
        row["physics"] = "builtin"
    start = record.pop("start", None)
    if start is not None and row["start_x"] is None:
        row["start_x"], row["start_y"] = float(start[0]), float(start[1])
    guarantees = record.pop("guarantees", None) or []
    for key in RESULT_COLUMNS:
        row[key] = record.get(key)
    for g in guarantees:
        prefix = f"guarantee.{g['name']}."
        row[prefix + "passed"] = g["passed"]
        measured = g.get("measured")
        if not isinstance(measured, dict):
            measured = {"value": measured}
        for k, v in measured.items():
            if v is None or isinstance(v, (bool, int, float, str)):
                row[prefix + k] = v
            else:
                row[prefix + k] = json.dumps(v)
    return row


def rows_to_table(rows: List[Dict[str, Any]]):
    """An Arrow table of ``rows``: every column that any row has, in order of first appearance,
    null where a row has none (a kinematic run has no ``guarantee.speed-below-bound.*``)."""
    import pyarrow as pa

    names: Dict[str, None] = {}
    for r in rows:
        for k in r:
            names.setdefault(k, None)
    arrays = {}
    for k in names:
        values = [r.get(k) for r in rows]
        arrays[k] = pa.array(values, type=_arrow_type(pa, k, values))
    return pa.table(arrays)


def _arrow_type(pa, name: str, values: List[Any]):
    """The column's type from its Python values (bool, int64, float64 — an int among floats is
    a float —, string, null), given to pyarrow so that it does not infer it: its inference tries
    to import optional modules on every call, a millisecond per task."""
    if name == "warnings":
        return pa.list_(pa.string())
    kinds = {type(v) for v in values if v is not None}
    if not kinds:
        return pa.null()
    if kinds == {bool}:
        return pa.bool_()
    if kinds == {int}:
        return pa.int64()
    if kinds <= {int, float}:
        return pa.float64()
    if kinds == {str}:
        return pa.string()
    raise TypeError(f"column {name}: values of types {sorted(t.__name__ for t in kinds)}")


def execute(task: Task):
    """Runs ``task`` (one thread: the engines run many tasks at once) and returns its records
    as an Arrow table, in run order."""
    configs = [config for _, config in task.runs]
    records = harmonav.run_batch(configs, threads=1, shortest=task.shortest)
    rows = [_flatten(columns, record) for (columns, _), record in zip(task.runs, records)]
    return rows_to_table(rows)

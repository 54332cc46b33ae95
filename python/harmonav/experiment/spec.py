"""The experiment spec (TOML, docs/experiments.md): worlds, starts, the grid of runs, what to
measure and the engine, validated as a scenario file is: every problem is a ``SpecError``
naming the file, the field and what is wrong, and unknown keys are refused.

Values that the Rust side knows (law, policy and physics names, the quality worlds' limits, a
scenario file's validity) are checked by the Rust side itself (``harmonav.check_run_config``,
either format's preparation), so the spec cannot drift from the scenario layer.

Limits, each checked before the thing it bounds is built, so that a small spec cannot ask for
unbounded memory or time:

- a spec or a world's scenario file is a regular file (a FIFO, a device or a folder is refused
  before it is opened) of at most ``MAX_FILE_BYTES`` (4 MiB, the scenario loader's limit), read
  through that cap;
- a spec has at most ``MAX_WORLDS`` worlds (``obstacles`` × ``seeds``, or the scenario files);
- its grid has at most ``MAX_CELLS`` cells: the cell count (the product of each ``[grid]``
  table's lists, without the law's irrelevant policy, summed over the tables) is computed from
  the lists before any cell is made or prepared;
- an experiment has at most ``MAX_RUNS`` runs (worlds × cells × starts)."""

from __future__ import annotations

import glob as _glob
import hashlib
import itertools
import json
import math
import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

try:  # Python 3.11+
    import tomllib as _toml
except ModuleNotFoundError:  # pragma: no cover - Python 3.9, 3.10
    try:
        import tomli as _toml  # type: ignore[no-redef]
    except ModuleNotFoundError:
        _toml = None  # type: ignore[assignment]

import harmonav

#: The grid's keys, in the order a run's configuration lists them.
GRID_KEYS = ("law", "k", "damping", "speed", "sensing", "margin", "max_time", "physics")

#: A grid key under its name in ``harmonav.run_batch``'s configurations, where it differs: the
#: spec (and the records) say ``law`` as the issue does, the Python API says ``model`` as
#: ``Scenario.run(model=…)`` and ``harmonav run --model`` do.
RUN_KEYS = {"law": "model"}


def run_config(world_config: Dict[str, Any], cell: Dict[str, Any]) -> Dict[str, Any]:
    """The ``run_batch`` configuration of ``cell`` (grid keys, ``None``: the world's own) on a
    world (its configuration)."""
    config = dict(world_config)
    config.update({RUN_KEYS.get(k, k): v for k, v in cell.items() if v is not None})
    return config
#: Most bytes of a spec or of a world's scenario file: the scenario loader's ``MAX_FILE_BYTES``
#: (``harmonav_scenario``), so that a device or a huge file is refused instead of read whole.
MAX_FILE_BYTES = 4 << 20
#: Most worlds in one experiment: the worlds are held in memory while it runs.
MAX_WORLDS = 1_000_000
#: Most cells (distinct run configurations) in a grid: every cell is held in memory and checked
#: before the first run, so a few long lists must not multiply into millions of them.
MAX_CELLS = 100_000
#: Most starts per world (as ``harmonav sweep --starts``).
MAX_STARTS = 1_000_000
#: Most runs in one experiment (a guard against a typo, not a memory limit: runs are
#: generated task by task).
MAX_RUNS = 10**9
#: Runs per task when the spec gives none: large enough that a task's overhead (a Ray task
#: costs about a millisecond) is small against runs of ≥ 10 ms, small enough that parts are
#: written often and the last tasks share the cores.
DEFAULT_TASK_RUNS = 16


class SpecError(ValueError):
    """A problem with an experiment spec: ``file``, ``field`` (a path such as
    ``grid.law[1]``, empty for the whole file), ``line`` (where the TOML parser gives it) and
    ``problem``. ``str()`` reads ``file[:line]: `field`: problem``, as a scenario error does."""

    def __init__(self, file: str, field: str, problem: str, line: Optional[int] = None):
        self.file, self.field, self.problem, self.line = str(file), field, problem, line
        where = self.file + (f":{line}" if line is not None else "")
        super().__init__(f"{where}: `{field}`: {problem}" if field else f"{where}: {problem}")


def _not_regular(mode: int) -> str:
    """What a file of ``mode`` is, when it is not a regular file."""
    for test, kind in (
        (stat.S_ISDIR, "a folder"),
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return f"{kind}, not a regular file"
    return "not a regular file"


def read_text(path: "os.PathLike[str] | str") -> str:
    """The UTF-8 text of the file at ``path`` (newlines as ``Path.read_text`` gives them), which
    must be a regular file of at most ``MAX_FILE_BYTES``. A FIFO, a device or a folder is
    refused before it is opened (opening a FIFO blocks until a writer comes; ``/dev/zero`` never
    ends), and the file is read through the cap, so a file that grows meanwhile is read no
    further. Raises ``SpecError`` naming the file."""
    name = str(path)
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        raise SpecError(name, "", f"cannot be read: {e}") from None
    if not stat.S_ISREG(mode):
        raise SpecError(name, "", f"cannot be read: {_not_regular(mode)}")
    # O_NONBLOCK: should a FIFO replace the file between the check and the open, the open
    # returns at once and the check below refuses it.
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except OSError as e:
        raise SpecError(name, "", f"cannot be read: {e}") from None
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            raise SpecError(name, "", f"cannot be read: {_not_regular(mode)}")
        chunks, size = [], 0
        while size <= MAX_FILE_BYTES:
            chunk = os.read(fd, MAX_FILE_BYTES + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as e:
        raise SpecError(name, "", f"cannot be read: {e}") from None
    finally:
        os.close(fd)
    if size > MAX_FILE_BYTES:
        raise SpecError(name, "", f"the file is larger than {MAX_FILE_BYTES >> 20} MiB")
    try:
        text = b"".join(chunks).decode("utf-8")
    except UnicodeDecodeError as e:
        raise SpecError(name, "", f"the file is not UTF-8 text: {e}") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


@dataclass(frozen=True)
class World:
    """One world: its label (the records' ``world``), the columns that say where it comes
    from, and the part of a run configuration that names it (``harmonav.run_batch``)."""

    label: str
    generator: Optional[str]
    scenario: Optional[str]
    seed: Optional[int]
    config: Dict[str, Any] = field(hash=False)


@dataclass(frozen=True)
class Starts:
    """Several starts per world: ``random`` seeded free starts (``seed``), as
    ``harmonav sweep --starts random --seed seed`` draws them, or the same ``points`` in every
    world."""

    random: Optional[int] = None
    seed: int = 0
    points: Optional[Tuple[Tuple[float, float], ...]] = None

    @property
    def count(self) -> int:
        return self.random if self.random is not None else len(self.points or ())


@dataclass(frozen=True)
class Engine:
    """Where the tasks run: ``kind`` ``"local"`` (every core, or ``workers``) or ``"ray"``
    (``address`` joins a running cluster; none starts a local one of ``workers`` CPUs, every
    core by default); ``task_runs`` runs per task."""

    kind: str = "local"
    address: Optional[str] = None
    workers: int = 0
    task_runs: int = DEFAULT_TASK_RUNS


@dataclass(frozen=True)
class Spec:
    """A validated experiment spec. ``cells`` are the grid's distinct run configurations
    (overrides of the worlds' scenarios; ``None``: the world's own value), in grid order."""

    path: Path
    name: str
    description: str
    worlds: Tuple[World, ...]
    starts: Optional[Starts]
    cells: Tuple[Dict[str, Any], ...]
    shortest: bool
    engine: Engine
    digest: str
    #: The spec's text as it was read and validated (what ``run`` copies to ``out/spec.toml``).
    text: Optional[str] = field(default=None, repr=False, compare=False)

    @property
    def runs(self) -> int:
        per_world = self.starts.count if self.starts is not None else 1
        return len(self.worlds) * len(self.cells) * per_world


def _line(message: str) -> Optional[int]:
    m = re.search(r"line (\d+)", message)
    return int(m.group(1)) if m else None


class _Checker:
    """Typed reads of the parsed TOML, each error naming the file and the field."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, field: str, problem: str) -> SpecError:
        return SpecError(str(self.path), field, problem)

    def table(self, value: Any, field: str, keys: Sequence[str]) -> Dict[str, Any]:
        if not isinstance(value, dict):
            raise self.fail(field, f"must be a table, got {_kind(value)}")
        for k in value:
            if k not in keys:
                raise self.fail(
                    f"{field}.{k}" if field else k,
                    f"unknown key; expected one of {', '.join(keys)}",
                )
        return value

    def string(self, value: Any, field: str) -> str:
        if not isinstance(value, str):
            raise self.fail(field, f"must be a string, got {_kind(value)}")
        return value

    def integer(self, value: Any, field: str, lo: int, hi: int) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(field, f"must be an integer, got {_kind(value)}")
        if not lo <= value <= hi:
            raise self.fail(field, f"must be in [{lo}, {hi}], got {value}")
        return value

    def number(self, value: Any, field: str) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(field, f"must be a number, got {_kind(value)}")
        if not math.isfinite(value):
            raise self.fail(field, f"must be finite, got {value}")
        return float(value)

    def boolean(self, value: Any, field: str) -> bool:
        if not isinstance(value, bool):
            raise self.fail(field, f"must be true or false, got {_kind(value)}")
        return value

    def nonempty_list(self, value: Any, field: str) -> List[Any]:
        if not isinstance(value, list):
            raise self.fail(field, f"must be a list, got {_kind(value)}")
        if not value:
            raise self.fail(field, "must not be empty")
        return value


def _kind(value: Any) -> str:
    return {
        bool: "a boolean",
        int: "an integer",
        float: "a number",
        str: "a string",
        list: "a list",
        dict: "a table",
    }.get(type(value), type(value).__name__)


def load_spec(path: "os.PathLike[str] | str") -> Spec:
    """Reads and validates the experiment spec at ``path``; raises ``SpecError``."""
    path = Path(path)
    if _toml is None:  # pragma: no cover
        raise SpecError(str(path), "", "reading TOML needs Python 3.11 or `pip install tomli`")
    text = read_text(path)
    try:
        doc = _toml.loads(text)
    except _toml.TOMLDecodeError as e:
        raise SpecError(str(path), "", f"not valid TOML: {e}", _line(str(e))) from None
    return _validate(path, doc, text)


def _validate(path: Path, doc: Dict[str, Any], text: Optional[str] = None) -> Spec:
    c = _Checker(path)
    c.table(doc, "", ["name", "description", "worlds", "starts", "grid", "measure", "engine"])
    if "name" not in doc:
        raise c.fail("name", "required")
    name = c.string(doc["name"], "name")
    if not name or not re.fullmatch(r"[A-Za-z0-9._-]+", name):
        raise c.fail("name", f"must be letters, digits, '.', '_' or '-', got {name!r}")
    description = c.string(doc.get("description", ""), "description")
    if "worlds" not in doc:
        raise c.fail("worlds", "required")
    worlds = _worlds(c, doc["worlds"])
    starts = _starts(c, doc["starts"]) if "starts" in doc else None
    cells = _grid(c, doc.get("grid", {}))
    measure = c.table(doc.get("measure", {}), "measure", ["shortest"])
    shortest = c.boolean(measure.get("shortest", True), "measure.shortest")
    engine = _engine(c, doc.get("engine", {}))
    # Before any cell is prepared.
    per_world = starts.count if starts is not None else 1
    runs = len(worlds) * len(cells) * per_world
    if runs > MAX_RUNS:
        raise c.fail("", f"{runs} runs; an experiment has at most {MAX_RUNS}")
    _check_cells(c, worlds, cells)
    digest = _digest(name, worlds, starts, cells, shortest, engine.task_runs)
    return Spec(path, name, description, worlds, starts, cells, shortest, engine, digest, text)


def _worlds(c: _Checker, value: Any) -> Tuple[World, ...]:
    w = c.table(value, "worlds", ["generator", "obstacles", "seeds", "scenarios"])
    if ("generator" in w) == ("scenarios" in w):
        raise c.fail("worlds", "give either generator (with obstacles and seeds) or scenarios")
    if "generator" in w:
        gen = c.string(w["generator"], "worlds.generator")
        if gen != "quality":
            raise c.fail("worlds.generator", f'unknown generator "{gen}": expected "quality"')
        for key in ("obstacles", "seeds"):
            if key not in w:
                raise c.fail(f"worlds.{key}", 'required by generator = "quality"')
        counts = [
            c.integer(v, f"worlds.obstacles[{i}]", 1, 10**6)
            for i, v in enumerate(c.nonempty_list(w["obstacles"], "worlds.obstacles"))
        ]
        seeds = _seeds(c, w["seeds"])
        count = len(counts) * len(seeds)
        if count > MAX_WORLDS:
            raise c.fail("worlds", f"{count} worlds (obstacles × seeds); at most {MAX_WORLDS}")
        out = []
        for m in counts:
            for s in seeds:
                config = {"generator": "quality", "obstacles": m, "seed": s}
                out.append(World(f"quality-m{m}-seed{s}", "quality", None, s, config))
        return _unique(c, out, "worlds")
    for key in ("obstacles", "seeds"):
        if key in w:
            raise c.fail(f"worlds.{key}", "belongs with generator, not with scenarios")
    base = c.path.parent
    out = []
    for i, pattern in enumerate(c.nonempty_list(w["scenarios"], "worlds.scenarios")):
        f = f"worlds.scenarios[{i}]"
        pattern = c.string(pattern, f)
        full = pattern if os.path.isabs(pattern) else str(base / pattern)
        files = sorted(_glob.glob(full, recursive=True))
        if not files:
            raise c.fail(f, f"{pattern!r} matches no file (relative to {base})")
        if len(out) + len(files) > MAX_WORLDS:
            raise c.fail(f, f"{len(out) + len(files)} scenario files; at most {MAX_WORLDS} worlds")
        for file in files:
            # Read first: a FIFO, a device or a folder is refused here, before the scenario
            # loader opens it (a FIFO would block it).
            try:
                text = read_text(file)
            except SpecError as e:
                raise c.fail(f, f"{e}") from None
            # The file's path, absolute: it names the file in errors, and a floor plan's
            # `map` is found relative to it from any working directory (a remote worker reads
            # the map there; a star world needs only the text).
            config = {"scenario": os.path.abspath(file), "scenario_text": text}
            try:
                # Either format (a `[floor_plan]` table or a star world), validated as the run
                # will prepare it.
                harmonav.check_run_config(config, prepare=True)
            except ValueError as e:
                raise c.fail(f, f"{e}") from None
            label = os.path.relpath(file, base)
            out.append(World(label, None, label, None, config))
    return _unique(c, out, "worlds.scenarios")


def _unique(c: _Checker, worlds: List[World], field: str) -> Tuple[World, ...]:
    seen = set()
    for w in worlds:
        if w.label in seen:
            raise c.fail(field, f"the world {w.label} is given twice")
        seen.add(w.label)
    return tuple(worlds)


def _seeds(c: _Checker, value: Any) -> Sequence[int]:
    """A list of seeds, or ``{ first = 1, count = 24 }`` (a ``range``: counted before the worlds
    are made)."""
    if isinstance(value, dict):
        t = c.table(value, "worlds.seeds", ["first", "count"])
        for key in ("first", "count"):
            if key not in t:
                raise c.fail(f"worlds.seeds.{key}", "required")
        first = c.integer(t["first"], "worlds.seeds.first", 0, 2**63 - 10**7)
        count = c.integer(t["count"], "worlds.seeds.count", 1, 10**7)
        return range(first, first + count)
    seeds = [
        c.integer(v, f"worlds.seeds[{i}]", 0, 2**63 - 1)
        for i, v in enumerate(c.nonempty_list(value, "worlds.seeds"))
    ]
    return seeds


def _starts(c: _Checker, value: Any) -> Starts:
    t = c.table(value, "starts", ["random", "seed", "points"])
    if ("random" in t) == ("points" in t):
        raise c.fail("starts", "give either random (a count, with seed) or points")
    if "points" in t:
        if "seed" in t:
            raise c.fail("starts.seed", "belongs with random, not with points")
        pts = []
        for i, p in enumerate(c.nonempty_list(t["points"], "starts.points")):
            f = f"starts.points[{i}]"
            if not isinstance(p, list) or len(p) != 2:
                raise c.fail(f, "must be a point [x, y]")
            pts.append((c.number(p[0], f + "[0]"), c.number(p[1], f + "[1]")))
        if len(pts) > MAX_STARTS:
            raise c.fail("starts.points", f"{len(pts)} points; at most {MAX_STARTS}")
        return Starts(points=tuple(pts))
    count = c.integer(t["random"], "starts.random", 1, MAX_STARTS)
    seed = c.integer(t.get("seed", 0), "starts.seed", 0, 2**63 - 1)
    return Starts(random=count, seed=seed)


def _grid(c: _Checker, value: Any) -> Tuple[Dict[str, Any], ...]:
    """The runs' configurations: the product of each ``[grid]`` table's lists (an array of
    tables ``[[grid]]`` is the union of their products), each value checked by the Rust side,
    the law's irrelevant policy dropped (damping for the kinematic law, speed for the dynamic
    one, both for the descent), duplicates removed in order.

    The cells are counted from the lists (their distinct values, without the irrelevant
    policies) before any is made: more than ``MAX_CELLS`` is refused at once. Each law's cells
    are the product of its relevant lists only, which is the order (and the set) that the whole
    product, its irrelevant policies dropped and its duplicates removed, would give."""
    tables = value if isinstance(value, list) else [value]
    if isinstance(value, list) and not value:
        raise c.fail("grid", "must not be empty")
    checked: Dict[Tuple[str, type, Any], Any] = {}  # a value repeated is checked once
    parsed: List[Dict[str, List[Any]]] = []
    for ti, table in enumerate(tables):
        where = f"grid[{ti}]" if isinstance(value, list) else "grid"
        t = c.table(table, where, list(GRID_KEYS))
        axes: Dict[str, List[Any]] = {}
        for key in GRID_KEYS:
            if key not in t:
                continue
            raw = t[key] if isinstance(t[key], list) else [t[key]]
            if not raw:
                raise c.fail(f"{where}.{key}", "must not be empty")
            values: Dict[Any, None] = {}  # distinct, in order (0 and 0.0 are one margin)
            for i, v in enumerate(raw):
                f = f"{where}.{key}[{i}]" if isinstance(t[key], list) else f"{where}.{key}"
                memo = (key, type(v), v) if isinstance(v, (str, int, float)) else None
                if memo is not None and memo in checked:
                    x = checked[memo]
                else:
                    x = _grid_value(c, key, v, f)
                    if memo is not None:
                        checked[memo] = x
                values.setdefault(x, None)
            axes[key] = list(values)
        parsed.append(axes)
    count = sum(_cell_count(axes) for axes in parsed)
    if count > MAX_CELLS:
        raise c.fail(
            "grid",
            f"{count} cells (the product of the lists); at most {MAX_CELLS}: split the study "
            "into several experiments",
        )
    cells: List[Dict[str, Any]] = []
    seen = set()
    for axes in parsed:
        for law in axes.get("law", [None]):
            ignored = _IGNORED.get(law, ())
            keys = [k for k in GRID_KEYS if k != "law" and k in axes and k not in ignored]
            for combo in itertools.product(*(axes[k] for k in keys)):
                cell = {key: None for key in GRID_KEYS}
                cell["law"] = law
                cell.update(zip(keys, combo))
                key = tuple(cell[k] for k in GRID_KEYS)
                if key not in seen:
                    seen.add(key)
                    cells.append(cell)
    return tuple(cells)


#: The grid keys a law does not take (its cells have them ``None``): damping for the kinematic
#: law, speed for the dynamic one, both for the descent (the flow line of Θ).
_IGNORED: Dict[Optional[str], Tuple[str, ...]] = {
    "kinematic": ("damping",),
    "dynamic": ("speed",),
    "descent": ("damping", "speed"),
}


def _cell_count(axes: Dict[str, List[Any]]) -> int:
    """The cells of one grid table (its distinct values per key), counted without making them:
    for each law, the product of the lengths of the lists it takes."""
    total = 0
    for law in axes.get("law", [None]):
        n = 1
        for k in GRID_KEYS:
            if k != "law" and k in axes and k not in _IGNORED.get(law, ()):
                n *= len(axes[k])
        total += n
    return total


def _grid_value(c: _Checker, key: str, v: Any, field: str) -> Any:
    if key in ("margin", "max_time"):
        x = c.number(v, field)
        if key == "margin" and x < 0:
            raise c.fail(field, f"must be ≥ 0, got {x}")
        if key == "max_time" and x <= 0:
            raise c.fail(field, f"must be > 0, got {x}")
        v = x
    else:
        v = c.string(v, field)
    # The Rust side parses the names (and every other value) exactly as the runs will.
    probe = run_config({"generator": "quality", "obstacles": 1, "seed": 0}, {key: v})
    try:
        harmonav.check_run_config(probe)
    except ValueError as e:
        raise c.fail(field, str(e).split(": ", 1)[-1]) from None
    return v


def _engine(c: _Checker, value: Any) -> Engine:
    t = c.table(value, "engine", ["kind", "address", "workers", "task_runs"])
    kind = c.string(t.get("kind", "local"), "engine.kind")
    if kind not in ("local", "ray"):
        raise c.fail("engine.kind", f'unknown engine "{kind}": expected "local" or "ray"')
    address = t.get("address")
    if address is not None:
        address = c.string(address, "engine.address")
        if kind != "ray":
            raise c.fail("engine.address", 'belongs with kind = "ray"')
    workers = c.integer(t.get("workers", 0), "engine.workers", 0, 1 << 16)
    task_runs = c.integer(t.get("task_runs", DEFAULT_TASK_RUNS), "engine.task_runs", 1, 10**6)
    return Engine(kind, address, workers, task_runs)


def _check_cells(c: _Checker, worlds: Sequence[World], cells: Sequence[Dict[str, Any]]) -> None:
    """Prepares every cell on the first world (and every world under the first cell), so that a
    margin too large for a world or a policy a file cannot take is a spec error, not a column of
    failed runs.

    Only the cells that can fail differently are prepared (``_probes``): a grid of 1000
    ``max_time`` values (or of 1000 margins on generated worlds) costs a few preparations, not
    1000."""
    first_world, first_cell = worlds[0], cells[0]
    # The generator makes every world valid for every margin it takes (from 0 to its largest):
    # only the largest and the smallest margins need a look. A scenario file gets every margin.
    ranged = ("max_time", "margin") if first_world.generator is not None else ("max_time",)
    pairs = [(first_world, cell) for cell in _probes(cells, ranged)]
    # A generated world of each obstacle count (the generator makes every seed valid for the
    # margins it takes), every scenario file.
    counts = {first_world.config.get("obstacles")}
    for w in worlds[1:]:
        if w.generator is None or w.config["obstacles"] not in counts:
            counts.add(w.config.get("obstacles"))
            pairs.append((w, first_cell))
    for world, cell in pairs:
        config = run_config(world.config, cell)
        try:
            harmonav.check_run_config(config, prepare=True)
        except ValueError as e:
            # The world's own fault when it fails as written too, whatever the grid asks (a
            # generator that cannot place that many obstacles): named under worlds.
            try:
                harmonav.check_run_config(run_config(world.config, {}), prepare=True)
            except ValueError:
                field = "worlds.obstacles" if world.generator is not None else "worlds.scenarios"
                raise c.fail(field, f"{world.label}: {e}") from None
            given = ", ".join(f"{k} = {v!r}" for k, v in cell.items() if v is not None)
            raise c.fail("grid", f"({given or 'the world as written'}) on {world.label}: {e}") from None


def _probes(cells: Sequence[Dict[str, Any]], ranged: Sequence[str]) -> List[Dict[str, Any]]:
    """The cells whose preparations stand for every cell's, in grid order: the first cell of
    each distinct rest (the cell without ``physics`` and the ``ranged`` keys), then for each
    ``ranged`` key the first cells of its smallest and largest values (and of none, the world's
    own), unless a probe already has them.

    A preparation does not read ``physics``. It reads ``max_time`` only in checks of its own,
    its range and ``max_time / dt`` against the most recorded states (``dt`` is the world's: no
    grid key sets it), which bound it to an interval whatever the rest of the cell; on a
    generated world a margin is valid from 0 to the largest the generator builds for, whatever
    the rest, too. So a cell prepares when its rest prepares (under values that do) and the
    extreme values of each ``ranged`` key do. Every probe is a cell of the grid, so an error
    names one."""
    probes: List[Dict[str, Any]] = []
    wanted: Dict[str, set] = {}
    for key in ranged:
        values = [c[key] for c in cells if c[key] is not None]
        wanted[key] = {min(values), max(values)} if values else set()
        if len(values) < len(cells):
            wanted[key].add(None)
    rests = set()
    for cell in cells:
        rest = tuple(cell[k] for k in GRID_KEYS if k != "physics" and k not in ranged)
        if rest not in rests:
            rests.add(rest)
            probes.append(cell)
            for key in ranged:
                wanted[key].discard(cell[key])
    for cell in cells:
        if any(cell[key] in wanted[key] for key in ranged):
            probes.append(cell)
            for key in ranged:
                wanted[key].discard(cell[key])
    return probes


def _digest(name, worlds, starts, cells, shortest, task_runs) -> str:
    """What identifies an experiment's records (a resumed run must have the same): everything
    but the engine's kind, address and workers."""
    doc = {
        "name": name,
        "worlds": [w.config for w in worlds],
        "starts": None if starts is None else [starts.random, starts.seed, starts.points],
        "cells": list(cells),
        "shortest": shortest,
        "task_runs": task_runs,
        "version": harmonav.__version__,
    }
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()

"""An experiment's folder: ``experiment.json`` (the manifest: name, digest, runs, tasks),
``spec.toml`` (a copy of the spec) and one Parquet part per finished task,
``parts/part-<task>.parquet``. A part is written to a temporary name, flushed and renamed into
place, so a part is whole or absent; an interrupted experiment resumes from the parts that are
there.

A part is trusted only when it holds its task's runs: its name is ``part_path``'s for its task,
the task is one of the manifest's, its Parquet footer opens and its ``run`` column is exactly the
task's runs (``check_part``). On resume a part that is not is run again (its task's part is
rewritten); ``read_records`` and the report refuse it, naming the file, and a part of a task
the experiment does not have (a foreign or duplicate file) is refused by both."""

from __future__ import annotations

import json
import os
import re
import stat
from pathlib import Path
from typing import Any, Dict, Optional, Sequence, Set, Tuple

from .spec import Spec, SpecError, _not_regular, read_text

PARTS = "parts"
MANIFEST = "experiment.json"
_PART = re.compile(r"part-(\d+)\.parquet")


def part_path(out: Path, task: int) -> Path:
    return out / PARTS / f"part-{task:06d}.parquet"


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - a platform without directory descriptors
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover
        pass
    finally:
        os.close(fd)


def write_atomically(path: Path, write, durable_name: bool = False) -> None:
    """``write(tmp)``, flushed to disk, then renamed to ``path``: the file is whole or absent,
    even after a crash. ``durable_name`` also flushes the folder, so that the rename itself
    survives a crash; a part does without (a lost rename only means its task runs again)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    if durable_name:
        _fsync_dir(path.parent)


def write_part(out: Path, task: int, table) -> Path:
    import pyarrow.parquet as pq

    path = part_path(out, task)
    write_atomically(path, lambda tmp: pq.write_table(table, tmp, compression="zstd"))
    return path


def _not_a_folder(out: Path) -> Optional[str]:
    """What ``out`` is when it exists and is not a folder (``None``: a folder, or nothing)."""
    try:
        mode = os.stat(out).st_mode
    except FileNotFoundError:
        return None
    if stat.S_ISDIR(mode):
        return None
    if stat.S_ISREG(mode):
        return "a file, not a folder"
    return _not_regular(mode).replace("not a regular file", "not a folder")


def prepare_out(out: Path, spec: Spec, tasks: int) -> Tuple[Set[int], Dict[int, str]]:
    """Creates ``out`` (or checks that it holds this experiment) and returns the tasks whose
    parts are already written and whole, and the tasks whose parts are there but damaged (their
    problem, naming the file: they run again). A folder of another experiment — another spec,
    or the same under another harmonav version — is refused (``SpecError``): records of two
    experiments never mix; so is ``out`` being a file, and a part of a task the experiment does
    not have."""
    where = str(spec.path)
    kind = _not_a_folder(out)
    if kind is not None:
        raise SpecError(where, "", f"--out {out} is {kind}")
    try:
        _prepare_out(out, spec, tasks)
    except OSError as e:
        raise SpecError(where, "", f"--out {out}: {e}") from None
    written, damaged = set(), {}
    for task, path in parts(out, tasks).items():
        problem = check_part(path, task, spec.runs, spec.engine.task_runs)
        if problem is None:
            written.add(task)
        else:
            damaged[task] = f"{path}: {problem}"
    return written, damaged


def _prepare_out(out: Path, spec: Spec, tasks: int) -> None:
    manifest = {
        "name": spec.name,
        "digest": spec.digest,
        "runs": spec.runs,
        "tasks": tasks,
        "task_runs": spec.engine.task_runs,
    }
    path = out / MANIFEST
    if path.exists():
        try:
            old = json.loads(read_text(path))
        except SpecError as e:
            raise SpecError(
                str(spec.path), "", f"--out {out}: unreadable {MANIFEST}: {e.problem}"
            ) from None
        except ValueError as e:
            raise SpecError(str(spec.path), "", f"--out {out}: unreadable {MANIFEST}: {e}") from None
        if not isinstance(old, dict) or old.get("digest") != spec.digest:
            name = old.get("name") if isinstance(old, dict) else None
            raise SpecError(
                str(spec.path),
                "",
                f"--out {out} holds the records of another experiment ({name!r}, "
                "another spec or harmonav version): give another --out, or remove it",
            )
    elif out.exists() and (
        any(p.name not in ("spec.toml", PARTS) and not p.name.startswith(".") for p in out.iterdir())
        or written_tasks(out)
    ):
        # Only what a runner killed before its manifest was written may be there: spec.toml,
        # an empty parts/ and temporary files. Parts without a manifest are nobody's.
        raise SpecError(
            str(spec.path), "", f"--out {out} exists and is not an experiment folder (no {MANIFEST})"
        )
    (out / PARTS).mkdir(parents=True, exist_ok=True)
    if not path.exists():
        # spec.toml first (rewritten: a runner killed here may have left another spec's copy),
        # then the manifest, whose presence says the folder is this experiment's.
        text = spec.text if spec.text is not None else read_text(spec.path)
        write_atomically(out / "spec.toml", lambda tmp: tmp.write_text(text, encoding="utf-8"))
        write_atomically(
            path, lambda tmp: tmp.write_text(json.dumps(manifest, indent=2) + "\n"), True
        )
    for stale in (out / PARTS).glob(".part-*.tmp"):
        stale.unlink()  # a part whose writer was killed: never renamed, never read


def task_range(task: int, runs: int, task_runs: int) -> Tuple[int, int]:
    """The runs ``[first, last)`` of ``task``."""
    first = task * task_runs
    return first, min(first + task_runs, runs)


def parts(out: "os.PathLike[str] | str", tasks: int) -> Dict[int, Path]:
    """The part files in ``out`` by task, in task order. A ``part-*.parquet`` file that is not
    the part of one of the ``tasks`` tasks (another name, such as ``part-5.parquet`` beside
    ``part-000005.parquet``, or a task the experiment does not have) or is not a regular file is
    refused: ``SpecError`` naming it. (Whether a part holds its task's runs is ``check_part``'s
    question.)"""
    found: Dict[int, Path] = {}
    for p in (Path(out) / PARTS).glob("part-*.parquet"):
        m = _PART.fullmatch(p.name)
        task = int(m.group(1)) if m else -1
        try:
            mode = os.stat(p).st_mode
        except OSError:
            mode = stat.S_IFREG  # gone meanwhile (or a dangling link): check_part says so
        if task < 0 or p.name != part_path(Path(out), task).name:
            problem = f"not the name of a part (such as {part_path(Path(out), 0).name})"
        elif task >= tasks:
            problem = f"task {task}, but the experiment's tasks are 0 to {tasks - 1} ({MANIFEST})"
        elif not stat.S_ISREG(mode):
            problem = _not_regular(mode)
        else:
            found[task] = p
            continue
        raise SpecError(str(p), "", f"{problem}: not a part of this experiment; remove it")
    return dict(sorted(found.items()))


def check_part(path: Path, task: int, runs: int, task_runs: int) -> Optional[str]:
    """What is wrong with ``path`` as the part of ``task`` (``None``: nothing): it must be a
    regular file whose Parquet footer opens, with one row per run of the task, its ``run``
    column exactly the task's runs in order."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    first, last = task_range(task, runs, task_runs)
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        return f"cannot be read: {e}"
    if not stat.S_ISREG(mode):
        return f"cannot be read: {_not_regular(mode)}"
    try:
        f = pq.ParquetFile(path)
        rows = f.metadata.num_rows
        if rows != last - first:
            return f"{rows} rows; task {task} has {last - first} runs ({first} to {last - 1})"
        if "run" not in f.schema_arrow.names:
            return "no `run` column"
        got = f.read(columns=["run"]).column("run").to_pylist()
    except (OSError, ValueError, TypeError, KeyError, pa.ArrowException) as e:
        return f"not a whole Parquet file ({e})"
    if got != list(range(first, last)):
        return (
            f"holds the runs {got[0]} to {got[-1]}, not the runs {first} to {last - 1} of task "
            f"{task}"
        )
    return None


def written_tasks(out: Path) -> Set[int]:
    done = set()
    for p in (Path(out) / PARTS).glob("part-*.parquet"):
        m = _PART.fullmatch(p.name)
        if m:
            done.add(int(m.group(1)))
    return done


def manifest(out: "os.PathLike[str] | str") -> Dict[str, Any]:
    """The manifest of the experiment in ``out`` (``experiment.json``), checked: ``SpecError``
    naming it when it cannot be read or does not say ``runs``, ``tasks`` and ``task_runs``
    consistently."""
    path = Path(out) / MANIFEST
    text = read_text(path)
    try:
        doc = json.loads(text)
    except ValueError as e:
        raise SpecError(str(path), "", f"not valid JSON: {e}") from None
    if not isinstance(doc, dict):
        raise SpecError(str(path), "", "not an experiment's manifest (a JSON object)")
    for key in ("runs", "tasks", "task_runs"):
        v = doc.get(key)
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise SpecError(str(path), key, f"must be a positive integer, got {v!r}")
    if doc["tasks"] != -(-doc["runs"] // doc["task_runs"]):
        raise SpecError(
            str(path),
            "tasks",
            f"{doc['tasks']} tasks of {doc['task_runs']} runs cannot hold {doc['runs']} runs",
        )
    return doc


def read_records(out: "os.PathLike[str] | str", columns: Optional[Sequence[str]] = None):
    """The records of the experiment in ``out`` as one Arrow table, in run order (the parts
    written so far: an experiment still running or interrupted gives fewer than its runs).
    Parts may differ in their columns (a part of kinematic runs has no dynamic guarantees): the
    columns are the union, null where a part has none.

    Every part is checked against ``experiment.json`` first (``check_part``): a damaged,
    foreign or duplicate part raises ``SpecError`` naming the file, so each run is in the table
    at most once. No part at all raises ``FileNotFoundError``."""
    import pyarrow as pa
    import pyarrow.compute as pc
    import pyarrow.dataset as ds
    import pyarrow.parquet as pq

    out = Path(out)
    if not (out / MANIFEST).exists():
        if not list((out / PARTS).glob("part-*.parquet")):
            raise FileNotFoundError(f"{out}: no records (no {PARTS}/part-*.parquet)")
        raise SpecError(str(out), "", f"not an experiment folder (no {MANIFEST})")
    m = manifest(out)
    found = parts(out, m["tasks"])
    if not found:
        raise FileNotFoundError(f"{out}: no records (no {PARTS}/part-*.parquet)")
    for task, path in found.items():
        problem = check_part(path, task, m["runs"], m["task_runs"])
        if problem is not None:
            raise SpecError(
                str(path), "", f"{problem}: a damaged or foreign part (run the experiment "
                "again to redo its task)"
            )
    files = [str(p) for p in found.values()]
    schemas = [pq.read_schema(f) for f in files]
    schema = pa.unify_schemas(schemas, promote_options="permissive")
    if columns is not None:
        columns = [c for c in columns if c in schema.names]
    table = ds.dataset(files, schema=schema, format="parquet").to_table(columns=columns)
    if "run" in table.column_names:
        table = table.sort_by("run")
        # The parts were checked one by one; the whole, once more (a part changed meanwhile).
        distinct = pc.count_distinct(table.column("run")).as_py()
        if table.num_rows > m["runs"] or distinct != table.num_rows:
            raise SpecError(
                str(out / PARTS), "", f"{table.num_rows} records of {distinct} distinct runs; "
                f"{MANIFEST} says {m['runs']} runs, each once"
            )
    return table

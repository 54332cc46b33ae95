"""An experiment's folder: ``experiment.json`` (the manifest: name, digest, runs, tasks),
``spec.toml`` (a copy of the spec) and one Parquet part per finished task,
``parts/part-<task>.parquet``. A part is written to a temporary name, flushed and renamed into
place, so a part is whole or absent; an interrupted experiment resumes from the parts that are
there."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any, Dict, Optional, Sequence, Set

from .spec import Spec, SpecError

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


def prepare_out(out: Path, spec: Spec, tasks: int) -> Set[int]:
    """Creates ``out`` (or checks that it holds this experiment) and returns the tasks whose
    parts are already written. A folder of another experiment — another spec, or the same
    under another harmonav version — is refused (``SpecError``): records of two experiments
    never mix."""
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
            old = json.loads(path.read_text())
        except (OSError, ValueError) as e:
            raise SpecError(str(spec.path), "", f"--out {out}: unreadable {MANIFEST}: {e}") from None
        if old.get("digest") != spec.digest:
            raise SpecError(
                str(spec.path),
                "",
                f"--out {out} holds the records of another experiment ({old.get('name')!r}, "
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
        text = spec.path.read_text(encoding="utf-8")
        write_atomically(out / "spec.toml", lambda tmp: tmp.write_text(text, encoding="utf-8"))
        write_atomically(
            path, lambda tmp: tmp.write_text(json.dumps(manifest, indent=2) + "\n"), True
        )
    for stale in (out / PARTS).glob(".part-*.tmp"):
        stale.unlink()  # a part whose writer was killed: never renamed, never read
    return written_tasks(out)


def written_tasks(out: Path) -> Set[int]:
    done = set()
    for p in (Path(out) / PARTS).glob("part-*.parquet"):
        m = _PART.fullmatch(p.name)
        if m:
            done.add(int(m.group(1)))
    return done


def manifest(out: "os.PathLike[str] | str") -> Dict[str, Any]:
    return json.loads((Path(out) / MANIFEST).read_text())


def read_records(out: "os.PathLike[str] | str", columns: Optional[Sequence[str]] = None):
    """The records of the experiment in ``out`` as one Arrow table, in run order. Parts may
    differ in their columns (a part of kinematic runs has no dynamic guarantees): the columns
    are the union, null where a part has none."""
    import pyarrow as pa
    import pyarrow.dataset as ds
    import pyarrow.parquet as pq

    files = sorted(str(p) for p in (Path(out) / PARTS).glob("part-*.parquet"))
    if not files:
        raise FileNotFoundError(f"{out}: no records (no {PARTS}/part-*.parquet)")
    schemas = [pq.read_schema(f) for f in files]
    schema = pa.unify_schemas(schemas, promote_options="permissive")
    if columns is not None:
        columns = [c for c in columns if c in schema.names]
    table = ds.dataset(files, schema=schema, format="parquet").to_table(columns=columns)
    if "run" in table.column_names:
        table = table.sort_by("run")
    return table

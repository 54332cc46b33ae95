"""``run``: a spec's runs on an engine, its records as Parquet parts in ``out``, resumed from
the parts already written, with a progress bar."""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Tuple, Union

from . import engines
from .plan import Plan
from .records import prepare_out, write_part
from .spec import Spec, SpecError, load_spec


@dataclass(frozen=True)
class RunSummary:
    """What ``run`` did: the experiment's ``runs`` and ``tasks``, the tasks ``resumed`` (already
    written) and ``ran`` now, the runs ``errors`` among those, and the wall time; ``damaged``:
    the parts found damaged or holding other runs (each ``file: problem``), whose tasks ran
    again."""

    out: Path
    runs: int
    tasks: int
    resumed: int
    ran: int
    errors: int
    wall_s: float
    damaged: Tuple[str, ...] = ()


def _bar(total: int, initial: int, enabled: Optional[bool]):
    try:
        from tqdm import tqdm
    except ImportError:  # the bar is a convenience: run without it
        return None
    return tqdm(
        total=total,
        initial=initial,
        unit="run",
        smoothing=0.05,
        dynamic_ncols=True,
        disable=(not enabled) if enabled is not None else None,
    )


def run(
    spec: Union[Spec, "os.PathLike[str]", str],
    out: "os.PathLike[str] | str",
    engine: Optional[str] = None,
    address: Optional[str] = None,
    workers: Optional[int] = None,
    progress: Optional[bool] = None,
) -> RunSummary:
    """Runs every task of ``spec`` whose part is not in ``out`` yet, on ``engine`` (``"local"``
    or ``"ray"``; default: the spec's ``[engine] kind``), and writes each finished task's
    records as ``out/parts/part-<task>.parquet``. ``address`` (Ray) joins a running cluster;
    ``workers`` (local threads, or the CPUs of a local Ray cluster; 0: every core) overrides the
    spec's. ``progress``: the bar on stderr (``None``: when stderr is a terminal).

    An interrupted or failed experiment resumes on the next call with the same spec and ``out``:
    a part is kept when it holds its task's runs (``records.check_part``), else its task runs
    again. ``out`` holding another experiment's records, ``out`` a file, a part of a task the
    experiment does not have, and the Ray engine without Ray installed raise ``SpecError``,
    before anything is written."""
    if not isinstance(spec, Spec):
        spec = load_spec(spec)
    out = Path(out)
    kind = engine or spec.engine.kind
    if kind not in ("local", "ray"):
        raise ValueError(f'engine: unknown engine "{kind}": expected "local" or "ray"')
    if kind == "ray" and not engines.ray_available():
        field = "engine.kind" if engine is None else ""
        given = "" if engine is None else "--engine ray: "
        raise SpecError(
            str(spec.path),
            field,
            f"{given}the ray engine needs Ray: pip install './python[ray]' (or pip install ray)",
        )
    address = address if address is not None else spec.engine.address
    workers = spec.engine.workers if workers is None else workers
    plan = Plan(spec)
    written, damaged = prepare_out(out, spec, plan.tasks)
    todo = [t for t in range(plan.tasks) if t not in written]
    done_runs = sum(min(plan.task_runs, plan.runs - t * plan.task_runs) for t in written)
    bar = _bar(plan.runs, done_runs, progress)
    errors = 0
    start = time.perf_counter()

    def done(task, table) -> None:
        nonlocal errors
        write_part(out, task.index, table)
        errors += table.num_rows - table.column("error").null_count
        if bar is not None:
            bar.update(table.num_rows)
            if errors:
                bar.set_postfix(errors=errors, refresh=False)

    try:
        tasks = plan.iter_tasks(todo)
        if kind == "local":
            engines.run_local(tasks, done, workers)
        else:
            engines.run_ray(tasks, done, address, workers)
    finally:
        if bar is not None:
            bar.close()
    return RunSummary(
        out,
        plan.runs,
        plan.tasks,
        len(written),
        len(todo),
        errors,
        time.perf_counter() - start,
        tuple(damaged[t] for t in sorted(damaged)),
    )


def main_run(args) -> int:
    try:
        summary = run(args.spec, args.out, args.engine, args.address, args.workers, args.progress)
    except KeyboardInterrupt:
        print(
            f"interrupted: the parts written are kept in {args.out}; run the same command again "
            "to resume",
            file=sys.stderr,
        )
        return 130
    for problem in summary.damaged:
        print(f"warning: {problem}: its task ran again", file=sys.stderr)
    print(
        f"{summary.out}: {summary.tasks} tasks, {summary.runs} runs "
        f"({summary.resumed} tasks already written, {summary.ran} run now in "
        f"{summary.wall_s:.1f} s), {summary.errors} runs with an error",
        file=sys.stderr,
    )
    return 0

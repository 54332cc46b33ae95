"""Declarative studies over harmonav's closed loop (issue 28; docs/experiments.md).

A spec (TOML) gives the worlds (the quality benchmark's seeded generator, or scenario files),
optionally several starts per world, a grid of configurations (law, ``k``, damping, speed,
sensing, margin, time budget, physics), what to measure and the engine. Every run goes through
``harmonav.run_batch``, the library path of ``harmonav run`` (``physics::simulate``), and gives
one record; the records are written as Parquet parts as tasks finish.

    python -m harmonav.experiment run SPEC --out DIR [--engine local|ray] [--address ADDR]
    python -m harmonav.experiment report DIR

From Python: ``load_spec``, ``run``, ``read_records``, ``report``. Needs pyarrow (and tqdm for the
bar): ``pip install './python[experiment]'``; the Ray engine ``'./python[ray]'``; the plots
``'./python[report]'``."""

from .plan import CONFIG_COLUMNS, RESULT_COLUMNS, Plan
from .records import manifest, read_records
from .reporting import report
from .runner import RunSummary, run
from .spec import Spec, SpecError, load_spec

__all__ = [
    "CONFIG_COLUMNS",
    "RESULT_COLUMNS",
    "Plan",
    "RunSummary",
    "Spec",
    "SpecError",
    "load_spec",
    "manifest",
    "read_records",
    "report",
    "run",
]

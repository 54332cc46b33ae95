"""The two engines. Both run ``plan.execute`` on the tasks and hand each finished task's table
to ``done`` in the driver, which writes its part; neither schedules anything itself:

- ``local``: a ``concurrent.futures`` thread pool of one thread per core (``run_batch``
  releases the GIL, so the threads run in parallel);
- ``ray``: one Ray task per task (``num_cpus=1``) on the cluster at ``address``, or on a local
  cluster started by ``ray.init`` when there is none.

Both keep at most two tasks per worker in flight, so the driver's memory does not grow with
the number of tasks."""

from __future__ import annotations

import os
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from typing import Callable, Iterator, Optional

from .plan import Task, execute


def cores() -> int:
    """The cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - macOS, Windows
        return os.cpu_count() or 1


def run_local(tasks: Iterator[Task], done: Callable[[Task, object], None], workers: int = 0) -> None:
    workers = workers or cores()
    with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="harmonav") as pool:
        in_flight = {}
        try:
            for task in tasks:
                while len(in_flight) >= 2 * workers:
                    _drain(in_flight, done)
                in_flight[pool.submit(execute, task)] = task
            while in_flight:
                _drain(in_flight, done)
        except BaseException:
            # Ctrl-C or a failed write: drop the tasks not started; the running ones finish
            # (a Rust run cannot be stopped halfway) but are not written.
            for f in in_flight:
                f.cancel()
            raise


def _drain(in_flight, done) -> None:
    finished, _ = wait(list(in_flight), return_when=FIRST_COMPLETED)
    for f in sorted(finished, key=lambda f: in_flight[f].index):
        task = in_flight.pop(f)
        done(task, f.result())


def ray_available() -> bool:
    try:
        import ray  # noqa: F401
    except ImportError:
        return False
    return True


def run_ray(
    tasks: Iterator[Task],
    done: Callable[[Task, object], None],
    address: Optional[str] = None,
    workers: int = 0,
) -> None:
    try:
        import ray
    except ImportError:
        raise RuntimeError(
            "the ray engine needs Ray: pip install './python[ray]' (or pip install ray)"
        ) from None
    started = not ray.is_initialized()
    if started:
        if address:
            ray.init(address=address, log_to_driver=True)
        else:
            ray.init(num_cpus=workers or cores(), include_dashboard=False)
    try:
        remote = ray.remote(num_cpus=1, max_retries=3)(execute)
        cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
        in_flight = {}
        try:
            for task in tasks:
                while len(in_flight) >= 2 * cpus:
                    _drain_ray(ray, in_flight, done)
                in_flight[remote.remote(task)] = task
            while in_flight:
                _drain_ray(ray, in_flight, done)
        except BaseException:
            for ref in in_flight:
                ray.cancel(ref, force=True)
            raise
    finally:
        if started:
            ray.shutdown()


def _drain_ray(ray, in_flight, done) -> None:
    ready, _ = ray.wait(list(in_flight), num_returns=1)
    for ref in ready:
        task = in_flight.pop(ref)
        done(task, ray.get(ref))

"""Throughput of harmonav.experiment (docs/benchmarks.md, "Experiments"): the same runs through
`harmonav sweep` (the CLI, if built), `harmonav.sweep`, the local engine and the Ray engine on a
local cluster, wall time of each, alternated `--repeats` times (the median is reported).

    python python/bench/bench_experiment.py [--starts 1000] [--repeats 3] [--cli target/release/harmonav]

Two studies: `sweep-mixed.toml`'s kinematic runs on scenarios/shapes/mixed.toml (about 7 ms
each: the sweep's own runs, for the local engine against the sweep) and
`montecarlo-small.toml`'s runs in the 20-obstacle world (for Ray against local, runs of
≥ 10 ms). The Ray figures are given with and without the cluster's start (`ray.init`)."""

import argparse
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import harmonav
from harmonav import experiment

REPO = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples" / "experiments"


def spec_copy(tmp, name, replace):
    text = (EXAMPLES / name).read_text().replace("../../scenarios", str(REPO / "scenarios"))
    for a, b in replace:
        text = text.replace(a, b)
    path = tmp / name
    path.write_text(text)
    return experiment.load_spec(path)


def timed(f):
    """Wall seconds and CPU seconds (this process's threads and its children) of ``f()``."""
    start, cpu, child = time.perf_counter(), time.process_time(), _children()
    f()
    return time.perf_counter() - start, time.process_time() - cpu + _children() - child


def _children():
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--starts", type=int, default=1000)
    ap.add_argument("--mc-starts", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--cli", default=str(REPO / "target" / "release" / "harmonav"))
    ap.add_argument("--no-ray", action="store_true")
    args = ap.parse_args()
    tmp = pathlib.Path(tempfile.mkdtemp())
    try:
        ray = None
        if not args.no_ray:
            try:
                import ray  # noqa: F811
            except ImportError:
                print("(ray not installed: no Ray rows)", file=sys.stderr)
        n = args.starts
        sweep_spec = spec_copy(tmp, "sweep-mixed.toml", [("random = 200", f"random = {n}")])
        mixed = harmonav.Scenario.load(REPO / "scenarios" / "shapes" / "mixed.toml")
        cli = pathlib.Path(args.cli)
        rows = {}

        def add(name, runs, seconds):
            rows.setdefault(name, (runs, []))[1].append(seconds)

        for r in range(args.repeats):
            if cli.is_file():
                command = [str(cli), "sweep", str(REPO / "scenarios/shapes/mixed.toml"),
                           "--starts", str(n), "--seed", "0", "--model", "kinematic", "--json"]
                add("`harmonav sweep` (CLI, release)", n,
                    timed(lambda: subprocess.run(command, check=True, capture_output=True)))
            add("`harmonav.sweep` (Python)", n,
                timed(lambda: harmonav.sweep(mixed, n, seed=0, model="kinematic")))
            add("experiment, local engine", n,
                timed(lambda: experiment.run(sweep_spec, tmp / f"sweep-local-{r}", engine="local",
                                             progress=False)))
        mc_spec = spec_copy(tmp, "montecarlo-small.toml",
                            [("random = 400", f"random = {args.mc_starts}")])
        m = mc_spec.runs
        for r in range(args.repeats):
            add("Monte-Carlo: experiment, local engine", m,
                timed(lambda: experiment.run(mc_spec, tmp / f"mc-local-{r}", engine="local",
                                             progress=False)))
            if ray is not None:
                start = time.perf_counter()
                ray.init(num_cpus=2, include_dashboard=False)
                init = time.perf_counter() - start
                run = timed(lambda: experiment.run(mc_spec, tmp / f"mc-ray-{r}", engine="ray",
                                                   progress=False))
                stop = timed(ray.shutdown)
                add("Monte-Carlo: experiment, Ray, local 2-CPU cluster (running)", m,
                    (run[0], float("nan")))
                add("Monte-Carlo: experiment, Ray, with ray.init and shutdown", m,
                    (init + run[0] + stop[0], float("nan")))
        print("| what | runs | wall s (median of %d) | runs/s | CPU s per run (ms) |"
              % args.repeats)
        print("|---|---|---|---|---|")
        for name, (runs, times) in rows.items():
            wall = statistics.median(t[0] for t in times)
            cpu = statistics.median(t[1] for t in times)
            per = "—" if cpu != cpu else f"{1000 * cpu / runs:.2f}"
            print(f"| {name} | {runs} | {wall:.2f} | {runs / wall:.1f} | {per} |")
    finally:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()

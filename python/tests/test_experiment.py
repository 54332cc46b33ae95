"""harmonav.experiment (issue 28): the spec's errors, the batch call against the calls it must
agree with (`Scenario.run`, `sweep`), the records bit for bit across runs, thread counts and
engines (Ray on a local 2-CPU cluster), an interrupted experiment resumed, and the report."""

import json
import os
import signal
import struct
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import harmonav

pa = pytest.importorskip("pyarrow")
import pyarrow.parquet as pq  # noqa: E402
from harmonav import experiment  # noqa: E402
from harmonav.experiment import SpecError, load_spec, read_records  # noqa: E402

from conftest import REPO, SCENARIOS  # noqa: E402

EXAMPLES = REPO / "examples" / "experiments"


def write(tmp_path, text, name="spec.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


SMALL = """
    name = "small"
    [worlds]
    generator = "quality"
    obstacles = [6]
    seeds = [1, 2, 3]
    [grid]
    law = ["kinematic", "dynamic"]
    k = ["auto", "paper"]
    sensing = ["global", "sector"]
    [engine]
    task_runs = 5
"""


# ---------------------------------------------------------------------------------------------
# The spec


GOOD_WORLDS = '[worlds]\ngenerator = "quality"\nobstacles = [6]\nseeds = [1]\n'


@pytest.mark.parametrize(
    "text, field, words",
    [
        ('name = "x"\nworlds = = 1\n', "", ["TOML", "spec.toml:2:"]),
        (GOOD_WORLDS, "name", ["required"]),
        ('name = "a b"\n' + GOOD_WORLDS, "name", ["letters"]),
        ('name = "x"\nseed = 3\n' + GOOD_WORLDS, "seed", ["unknown key"]),
        ('name = "x"\n', "worlds", ["required"]),
        ('name = "x"\n[worlds]\ngenerator = "maze"\nobstacles = [6]\nseeds = [1]\n',
         "worlds.generator", ["maze", "quality"]),
        ('name = "x"\n[worlds]\ngenerator = "quality"\nseeds = [1]\n', "worlds.obstacles",
         ["required"]),
        ('name = "x"\n[worlds]\ngenerator = "quality"\nobstacles = []\nseeds = [1]\n',
         "worlds.obstacles", ["empty"]),
        ('name = "x"\n[worlds]\ngenerator = "quality"\nobstacles = [6, "12"]\nseeds = [1]\n',
         "worlds.obstacles[1]", ["integer", "string"]),
        ('name = "x"\n[worlds]\ngenerator = "quality"\nobstacles = [6]\nseeds = [-1]\n',
         "worlds.seeds[0]", ["[0,"]),
        # A count the generator cannot place is the world's problem, not the grid's.
        ('name = "x"\n[worlds]\ngenerator = "quality"\nobstacles = [6, 100]\nseeds = [1]\n',
         "worlds.obstacles", ["quality-m100-seed1"]),
        ('name = "x"\n[worlds]\nscenarios = ["nowhere/*.toml"]\n', "worlds.scenarios[0]",
         ["matches no file"]),
        ('name = "x"\n[worlds]\ngenerator = "quality"\nscenarios = ["a.toml"]\n', "worlds",
         ["either"]),
        ('name = "x"\n' + GOOD_WORLDS + '[grid]\nlaw = ["kinematic", "dinamic"]\n',
         "grid.law[1]", ["dinamic", "kinematic"]),
        ('name = "x"\n' + GOOD_WORLDS + '[grid]\nk = ["auto", "pape"]\n', "grid.k[1]",
         ["pape"]),
        ('name = "x"\n' + GOOD_WORLDS + '[grid]\ndamping = "none"\n', "grid.damping",
         ["none"]),
        ('name = "x"\n' + GOOD_WORLDS + '[grid]\nsensing = ["lidar"]\n', "grid.sensing[0]",
         ["lidar", "sector"]),
        ('name = "x"\n' + GOOD_WORLDS + '[grid]\nmargin = [-0.1]\n', "grid.margin[0]", ["≥ 0"]),
        ('name = "x"\n' + GOOD_WORLDS + '[grid]\nmax_time = [0]\n', "grid.max_time[0]", ["> 0"]),
        ('name = "x"\n' + GOOD_WORLDS + '[grid]\nlaws = ["kinematic"]\n', "grid.laws",
         ["unknown key"]),
        # The quality worlds are built for margins up to 0.1 m: the Rust side says so.
        ('name = "x"\n' + GOOD_WORLDS + '[grid]\nmargin = [0.0, 0.5]\n', "grid",
         ["margin", "0.1"]),
        ('name = "x"\n' + GOOD_WORLDS + '[starts]\nrandom = 0\n', "starts.random", ["[1,"]),
        ('name = "x"\n' + GOOD_WORLDS + '[starts]\npoints = [[1, 2, 3]]\n', "starts.points[0]",
         ["[x, y]"]),
        ('name = "x"\n' + GOOD_WORLDS + '[starts]\nrandom = 3\npoints = [[1, 2]]\n', "starts",
         ["either"]),
        ('name = "x"\n' + GOOD_WORLDS + '[measure]\nshortest = "yes"\n', "measure.shortest",
         ["true or false"]),
        ('name = "x"\n' + GOOD_WORLDS + '[engine]\nkind = "dask"\n', "engine.kind",
         ["dask", "ray"]),
        ('name = "x"\n' + GOOD_WORLDS + '[engine]\naddress = "auto"\n', "engine.address",
         ["ray"]),
        ('name = "x"\n' + GOOD_WORLDS + '[engine]\ntask_runs = 0\n', "engine.task_runs",
         ["[1,"]),
    ],
)
def test_a_bad_spec_names_the_file_the_field_and_the_problem(tmp_path, text, field, words):
    path = write(tmp_path, text)
    with pytest.raises(SpecError) as err:
        load_spec(path)
    e = err.value
    assert e.file == str(path) and e.field == field, (e.file, e.field, str(e))
    assert str(e).startswith(str(path)), str(e)
    for w in words:
        assert w in str(e), str(e)


def test_a_bad_scenario_file_is_a_spec_error_with_the_scenario_layers_message(tmp_path):
    (tmp_path / "worlds").mkdir()
    bad = tmp_path / "worlds" / "bad.toml"
    bad.write_text((SCENARIOS / "shapes" / "mixed.toml").read_text().replace("radius = 0.5", "radius = -0.5", 1))
    path = write(tmp_path, 'name = "x"\n[worlds]\nscenarios = ["worlds/*.toml"]\n')
    with pytest.raises(SpecError) as err:
        load_spec(path)
    assert err.value.field == "worlds.scenarios[0]"
    assert "bad.toml" in str(err.value) and "obstacles[0]" in str(err.value), str(err.value)


def test_the_grid_is_the_product_without_the_laws_irrelevant_policies(tmp_path):
    spec = load_spec(write(tmp_path, """
        name = "g"
        [worlds]
        generator = "quality"
        obstacles = [6, 12]
        seeds = { first = 3, count = 2 }
        [grid]
        law = ["kinematic", "dynamic"]
        speed = ["paper", "auto"]
        damping = ["paper", "auto"]
        margin = [0, 0.1]
    """))
    assert [w.label for w in spec.worlds] == [
        "quality-m6-seed3", "quality-m6-seed4", "quality-m12-seed3", "quality-m12-seed4"]
    # 2 laws × 2 own policies × 2 margins: the kinematic law ignores damping, the dynamic speed.
    assert len(spec.cells) == 8 and spec.runs == 32
    for c in spec.cells:
        assert (c["law"] == "kinematic") == (c["damping"] is None)
        assert (c["law"] == "dynamic") == (c["speed"] is None)
        assert isinstance(c["margin"], float)


def test_the_example_specs_are_valid():
    names = set()
    for path in sorted(EXAMPLES.glob("*.toml")):
        spec = load_spec(path)
        names.add(spec.name)
        assert spec.runs > 0
    assert {"quality-small", "quality", "montecarlo-small", "montecarlo", "sweep-mixed"} <= names
    assert load_spec(EXAMPLES / "quality-small.toml").runs == 64
    assert load_spec(EXAMPLES / "quality.toml").runs == 3 * 36 * 24


# ---------------------------------------------------------------------------------------------
# The batch call


def test_a_descent_is_the_flow_line_of_theta_no_shorter_than_the_shortest_path():
    # verify's Monte-Carlo world (examples/experiments/montecarlo.toml): the runner's
    # law = "descent" calls harmonav_sim::descent::descend, the function verify calls.
    world = {"generator": "quality", "obstacles": 20, "seed": 20, "sensing": "global"}
    starts = harmonav.random_start_points(world, 12, 20)
    runs = [dict(world, model="descent", start=p, start_index=i) for i, p in enumerate(starts)]
    records = harmonav.run_batch(runs, threads=2)
    assert len(records) == 12
    for r in records:
        assert r["error"] is None, r["error"]
        assert r["effective"]["model"] == "descent"
        assert r["effective"]["speed"] is None and r["effective"]["damping"] is None
        assert r["reached"] and r["outcome"] == "reached" and r["collisions"] == 0
        assert r["final_distance"] <= 0.01
        # A path from the start to within the tolerance of the goal in the free space is no
        # shorter than the shortest one, less the tolerance.
        assert r["path_length"] >= r["shortest_length"] - 0.01 - 1e-9
        assert r["time_s"] == r["path_length"] and r["max_speed"] == 1.0
    # The kinematic law at unit speed follows the same flow line: the same length, within the
    # two integrators' tolerances (the law's path stops at the same goal tolerance).
    law = harmonav.run_batch([dict(runs[0], model="kinematic", speed="paper")])[0]
    assert law["reached"]
    assert abs(law["path_length"] - records[0]["path_length"]) < 0.02 * records[0]["path_length"]
    bad = harmonav.run_batch([dict(runs[0], physics="rapier")])[0]
    assert "physics" in bad["error"] and "descent" in bad["error"]
    blind = harmonav.run_batch([dict(runs[0], sensing="sector")])[0]
    assert "sensing" in blind["error"] and "descent" in blind["error"]



def test_a_failing_run_is_a_record_with_its_error_and_the_batch_goes_on(mixed_path):
    text = mixed_path.read_text()
    runs = [
        {"generator": "quality", "obstacles": 6, "seed": 1},
        {"generator": "quality", "obstacles": 6, "seed": 1, "model": "dinamic"},
        {"scenario": "broken.toml", "scenario_text": text.replace("radius = 0.5", "radius = -0.5", 1)},
        {"generator": "quality", "obstacles": 6, "seed": 1, "colour": "red"},
        {"generator": "quality", "obstacles": 6, "seed": 1, "margin": 0.5},
        {"scenario": str(mixed_path), "start": [100.0, 0.0], "start_index": 7},
        {"scenario": str(mixed_path), "model": "kinematic"},
    ]
    records = harmonav.run_batch(runs, threads=2)
    assert len(records) == len(runs)
    assert records[0]["error"] is None and records[0]["reached"] is True
    assert "model" in records[1]["error"] and "dinamic" in records[1]["error"]
    assert "broken.toml" in records[2]["error"] and "obstacles[0]" in records[2]["error"]
    assert "colour" in records[3]["error"]
    assert "margin" in records[4]["error"]
    # A start outside the free space is the sweep's outcome, not an error.
    assert records[5]["error"] is None and records[5]["outcome"] == "invalid-start"
    assert "starts[7]" in records[5]["outcome_detail"]
    assert records[6]["error"] is None and records[6]["outcome"] == "reached"
    assert all(r["version"] == harmonav.__version__ for r in records)


def test_a_record_is_the_run_that_harmonav_run_makes(mixed_path):
    """The same library call: every number of summary.json and every guarantee agree."""
    for model in ("kinematic", "dynamic"):
        summary = harmonav.Scenario.load(mixed_path).run(model=model).summary
        (record,) = harmonav.run_batch([{"scenario": str(mixed_path), "model": model}])
        assert record["error"] is None
        for key in ("reached", "time_s", "path_length", "min_clearance", "collisions",
                    "max_speed", "steps", "rejected_steps", "recorded_states", "final_distance"):
            assert record[key] == summary[key], key
        assert record["outcome"] == summary["outcome"]["kind"]
        assert record["guarantees"] == summary["guarantees"]
        assert record["effective"]["model"] == model
        length, _ = harmonav.Scenario.load(mixed_path).shortest_path()
        assert record["shortest_length"] == length
        assert record["path_over_shortest"] == summary["path_length"] / length


def test_the_runner_and_the_sweep_agree_run_for_run(tmp_path):
    """sweep-mixed.toml holds the runs of `harmonav sweep mixed.toml --starts 200 --seed 0
    --model kinematic`; 24 of them here, through the runner and through `sweep`."""
    spec_text = (EXAMPLES / "sweep-mixed.toml").read_text().replace("random = 200", "random = 24")
    spec_text = spec_text.replace("../../scenarios", str(SCENARIOS))
    spec = load_spec(write(tmp_path, spec_text))
    experiment.run(spec, tmp_path / "out", workers=2, progress=False)
    records = read_records(tmp_path / "out").to_pylist()
    swept = harmonav.sweep(harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml"), 24,
                           seed=0, model="kinematic")
    assert [(r["start_x"], r["start_y"]) for r in records] == [tuple(p) for p in swept.starts]
    assert [r["outcome"] for r in records] == list(swept.outcomes)
    for r, t in zip(records, swept.times):
        if r["reached"]:
            assert r["time_s"] == t


def test_random_starts_are_the_sweeps(mixed_path):
    starts = harmonav.random_start_points({"scenario": str(mixed_path)}, 50, 3)
    swept = harmonav.sweep(harmonav.Scenario.load(mixed_path), 50, seed=3)
    np.testing.assert_array_equal(np.array(starts), swept.starts)


# ---------------------------------------------------------------------------------------------
# Records: bit for bit


def bits(table):
    """Every value of `table`, floats by their bit patterns (NaN equal to itself)."""
    out = {}
    for name in table.column_names:
        values = table.column(name).to_pylist()
        out[name] = [struct.pack("<d", v) if isinstance(v, float) else v for v in values]
    return out


def test_records_are_the_same_across_runs_and_thread_counts(tmp_path):
    spec = load_spec(write(tmp_path, SMALL))
    experiment.run(spec, tmp_path / "a", workers=2, progress=False)
    experiment.run(spec, tmp_path / "b", workers=1, progress=False)
    a, b = read_records(tmp_path / "a"), read_records(tmp_path / "b")
    assert a.num_rows == spec.runs == 3 * 2 * 2 * 2
    assert a.column("run").to_pylist() == list(range(spec.runs))
    assert bits(a) == bits(b)
    # And one batch call on two threads gives the records the tasks gave.
    plan = experiment.Plan(spec)
    configs = [plan.run(i)[1] for i in range(spec.runs)]
    batch = harmonav.run_batch(configs, threads=2)
    assert [r["time_s"] for r in batch] == a.column("time_s").to_pylist()
    assert [r["steps"] for r in batch] == a.column("steps").to_pylist()


def test_records_carry_the_configuration_the_outcome_and_every_guarantee(tmp_path):
    spec = load_spec(write(tmp_path, SMALL))
    experiment.run(spec, tmp_path / "out", progress=False)
    t = read_records(tmp_path / "out")
    for column in experiment.CONFIG_COLUMNS + experiment.RESULT_COLUMNS:
        assert column in t.column_names, column
    rows = t.to_pylist()
    assert {r["law"] for r in rows} == {"kinematic", "dynamic"}
    assert {r["sensing"] for r in rows} == {"global", "sector"}
    assert all(r["obstacles"] == 6 and r["margin"] == 0.0 and r["error"] is None for r in rows)
    assert all((r["damping"] is None) == (r["law"] == "kinematic") for r in rows)
    for r in rows:
        assert r["guarantee.no-collision.passed"] is True
        assert r["guarantee.no-collision.min_clearance"] == r["min_clearance"]
        assert r["guarantee.reached-goal.passed"] == r["reached"]
        if r["law"] == "dynamic":
            assert r["guarantee.speed-below-bound.max_speed"] == r["max_speed"]
        else:
            assert r["guarantee.speed-below-bound.passed"] is None
        # An arrived run ends within the goal tolerance (0.01 m) of the goal: its path is at
        # least the shortest path less that (and the outline's chord error, ~1e-5 m).
        if r["reached"]:
            assert r["path_length"] >= r["shortest_length"] - 0.01 - 1e-4
            assert r["path_over_shortest"] == r["path_length"] / r["shortest_length"]


def ray_or_skip():
    try:
        import ray  # noqa: F401
    except ImportError:
        if os.environ.get("HARMONAV_REQUIRE_RAY"):
            raise
        pytest.skip("ray is not installed (pip install './python[ray]')")


def test_the_ray_engine_gives_the_local_engines_records_bit_for_bit(tmp_path):
    ray_or_skip()
    spec = load_spec(write(tmp_path, SMALL))
    experiment.run(spec, tmp_path / "local", engine="local", progress=False)
    summary = experiment.run(spec, tmp_path / "ray", engine="ray", workers=2, progress=False)
    assert summary.ran == summary.tasks == 5
    local, remote = read_records(tmp_path / "local"), read_records(tmp_path / "ray")
    assert local.schema == remote.schema
    assert bits(local) == bits(remote)


# ---------------------------------------------------------------------------------------------
# Interrupted, resumed


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL])
def test_an_interrupted_experiment_resumes_to_the_same_records(tmp_path, sig):
    """The runner is interrupted once some parts are written — Ctrl-C (it exits with 130) or
    SIGKILL (no clean-up at all) — and the same command resumes from the parts. The records
    equal an uninterrupted experiment's, and no part is half-written."""
    spec = write(tmp_path, """
        name = "resume"
        [worlds]
        generator = "quality"
        obstacles = [6]
        seeds = { first = 1, count = 12 }
        [grid]
        law = ["kinematic", "dynamic"]
        sensing = ["global", "sector"]
        [engine]
        task_runs = 2
        workers = 2
    """)
    tasks = load_spec(spec).runs // 2
    out = tmp_path / "interrupted"
    command = [sys.executable, "-m", "harmonav.experiment", "run", str(spec), "--out", str(out),
               "--no-progress"]
    proc = subprocess.Popen(command, cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    parts = out / "parts"
    try:
        while proc.poll() is None and len(list(parts.glob("part-*.parquet"))) < 3:
            time.sleep(0.01)
    finally:
        proc.send_signal(sig)
        _, stderr = proc.communicate()
    if sig == signal.SIGINT:
        assert proc.returncode == 130 and "resume" in stderr, (proc.returncode, stderr)
    before = sorted(p.name for p in parts.glob("part-*.parquet"))
    assert 3 <= len(before) < tasks, len(before)
    for p in parts.glob("part-*.parquet"):
        pq.read_table(p)  # whole
    resumed = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True)
    assert resumed.returncode == 0, resumed.stderr
    assert f"{len(before)} tasks already written" in resumed.stderr, resumed.stderr
    experiment.run(spec, tmp_path / "whole", progress=False)
    assert bits(read_records(out)) == bits(read_records(tmp_path / "whole"))
    assert not list(parts.glob(".*tmp"))


def test_a_folder_of_another_experiment_is_refused(tmp_path):
    spec = write(tmp_path, SMALL)
    experiment.run(spec, tmp_path / "out", progress=False)
    other = write(tmp_path, SMALL.replace("seeds = [1, 2, 3]", "seeds = [1, 2]"), "other.toml")
    with pytest.raises(SpecError, match="another experiment"):
        experiment.run(other, tmp_path / "out", progress=False)
    # The same spec again: nothing to do, the records are kept.
    again = experiment.run(spec, tmp_path / "out", progress=False)
    assert again.ran == 0 and again.resumed == again.tasks


# ---------------------------------------------------------------------------------------------
# The report


def test_the_report_prints_the_quality_table_of_the_records(tmp_path):
    spec = load_spec(write(tmp_path, SMALL))
    experiment.run(spec, tmp_path / "out", progress=False)
    text = experiment.report(tmp_path / "out")
    records = read_records(tmp_path / "out").to_pylist()
    rows = [line for line in text.splitlines() if line.startswith("| ") and "---" not in line]
    header, cells = rows[0], rows[1:]
    assert header.startswith("| law | damping or speed | k | sensing | margin | M | arrived")
    assert len(cells) == 8
    for line in cells:
        law, policy, k, sensing, margin, m, arrived = [c.strip() for c in line.split("|")[1:8]]
        mine = [r for r in records if r["law"] == law.lower() and r["k"] == k
                and r["sensing"] == sensing]
        assert arrived == f"{sum(r['reached'] for r in mine)}/{len(mine)}"
        assert m == "6" and margin == "0"
        if law == "Kinematic":
            assert policy == "auto" and line.split("|")[12].strip() == "—"
    assert f"{spec.runs} runs:" in text


def test_the_report_draws_the_distributions(tmp_path):
    pytest.importorskip("matplotlib")
    spec = load_spec(write(tmp_path, SMALL))
    experiment.run(spec, tmp_path / "out", progress=False)
    experiment.report(tmp_path / "out", plots=tmp_path / "plots")
    for name in ("path_over_shortest.svg", "time_s.svg"):
        svg = (tmp_path / "plots" / name).read_text()
        assert "<svg" in svg and "M=6, dynamic governed, k paper, sector" in svg


def test_the_command_line_runs_and_reports(tmp_path):
    spec = write(tmp_path, SMALL)
    run = subprocess.run([sys.executable, "-m", "harmonav.experiment", "run", str(spec),
                          "--out", str(tmp_path / "out")], capture_output=True, text=True,
                         cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    report = subprocess.run([sys.executable, "-m", "harmonav.experiment", "report",
                             str(tmp_path / "out"), "--no-plots"], capture_output=True,
                            text=True, cwd=tmp_path)
    assert report.returncode == 0, report.stderr
    assert "| Dynamic | governed | paper | sector | 0 | 6 |" in report.stdout
    bad = write(tmp_path, SMALL.replace('law = ["kinematic", "dynamic"]', 'law = ["fast"]'), "bad.toml")
    refused = subprocess.run([sys.executable, "-m", "harmonav.experiment", "run", str(bad),
                              "--out", str(tmp_path / "bad")], capture_output=True, text=True,
                             cwd=tmp_path)
    assert refused.returncode == 2 and "grid.law[0]" in refused.stderr, refused.stderr
    assert not (tmp_path / "bad").exists()
    manifest = json.loads((tmp_path / "out" / "experiment.json").read_text())
    assert manifest["runs"] == 24 and manifest["tasks"] == 5


# ---------------------------------------------------------------------------------------------
# Hostile inputs (docs: hostile round 2026-12-06, D4, D5, D12, D14, D15, D21)


TINY = """
    name = "tiny"
    [worlds]
    generator = "quality"
    obstacles = [6]
    seeds = [1, 2]
    [grid]
    law = ["kinematic"]
    [engine]
    task_runs = 1
"""


def command(*args, cwd, timeout=60, **kwargs):
    """`python -m harmonav.experiment ARGS`: its return code and stderr."""
    done = subprocess.run([sys.executable, "-m", "harmonav.experiment", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, timeout=timeout, **kwargs)
    return done.returncode, done.stderr


def assert_refused(rc, stderr, *words):
    """Refused as every bad input is: `error: …` on stderr, exit 2, no traceback."""
    assert rc == 2, (rc, stderr)
    assert stderr.startswith("error: ") and "Traceback" not in stderr, stderr
    for w in words:
        assert w in stderr, stderr


def in_thread(call, fifo, timeout=5.0):
    """`call()` in a thread, given `timeout` s: its result or exception. A call still blocked
    (in `open` of `fifo`, which has no writer) fails the test; the FIFO is then opened for
    writing and closed, so the call returns."""
    import threading

    result = {}

    def target():
        try:
            result["value"] = call()
        except BaseException as e:  # noqa: BLE001 - handed to the test
            result["error"] = e

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(timeout)
    if thread.is_alive():
        fd = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)
        os.close(fd)
        thread.join(timeout)
        pytest.fail(f"blocked for {timeout} s reading the FIFO {fifo}")
    return result


def test_a_spec_that_is_a_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "spec.toml"
    os.mkfifo(fifo)
    result = in_thread(lambda: load_spec(fifo), fifo)
    e = result.get("error")
    assert isinstance(e, SpecError), result
    assert e.file == str(fifo) and "a FIFO, not a regular file" in str(e), str(e)


def load_in_child(spec, timeout=30):
    """`load_spec(spec)` in a child process, given `timeout` s (the scenario loader blocks with
    the GIL held): its stderr."""
    probe = f"from harmonav.experiment import load_spec\nload_spec({str(spec)!r})\n"
    try:
        done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        pytest.fail(f"load_spec({spec}) did not return within {timeout} s")
    return done.stderr


def test_a_world_that_is_a_fifo_is_refused_without_blocking(tmp_path):
    (tmp_path / "worlds").mkdir()
    (tmp_path / "worlds" / "a.toml").write_text((SCENARIOS / "shapes" / "mixed.toml").read_text())
    fifo = tmp_path / "worlds" / "b.toml"
    os.mkfifo(fifo)
    spec = write(tmp_path, 'name = "x"\n[worlds]\nscenarios = ["worlds/*.toml"]\n')
    stderr = load_in_child(spec)
    assert "SpecError" in stderr and "`worlds.scenarios[0]`" in stderr, stderr
    assert f"{fifo}: cannot be read: a FIFO, not a regular file" in stderr, stderr


def test_a_spec_that_is_a_folder_or_too_large_is_refused(tmp_path):
    with pytest.raises(SpecError, match="a folder, not a regular file") as err:
        load_spec(tmp_path)
    assert err.value.file == str(tmp_path)
    # Valid TOML past the cap: refused by its size, not read and parsed.
    big = tmp_path / "big.toml"
    big.write_text('name = "x"\n' + GOOD_WORLDS + ("#" * 1023 + "\n") * 4096)
    assert big.stat().st_size > experiment.spec.MAX_FILE_BYTES
    with pytest.raises(SpecError, match="larger than 4 MiB") as err:
        load_spec(big)
    assert err.value.file == str(big)
    # At the cap, it is read.
    big.write_text('name = "x"\n' + GOOD_WORLDS)
    with open(big, "a") as f:
        f.write("#" * (experiment.spec.MAX_FILE_BYTES - big.stat().st_size - 1) + "\n")
    assert big.stat().st_size == experiment.spec.MAX_FILE_BYTES
    assert load_spec(big).runs == 1


def test_a_dev_zero_spec_is_refused_at_once(tmp_path):
    if not os.path.exists("/dev/zero"):
        pytest.skip("no /dev/zero")

    def cap_memory():  # without the check, /dev/zero is read until this cap, not the machine's
        import resource

        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))

    rc, stderr = command("run", "/dev/zero", "--out", tmp_path / "out", cwd=tmp_path,
                     preexec_fn=cap_memory)
    assert_refused(rc, stderr, "/dev/zero", "a character device, not a regular file")
    assert not (tmp_path / "out").exists()


def grid_spec(tmp_path, grid, worlds=GOOD_WORLDS, name="spec.toml"):
    return write(tmp_path, 'name = "x"\n' + worlds + "[grid]\n" + grid, name)


def numbers(n, step):
    return "[" + ", ".join(f"{step * (i + 1):.6f}" for i in range(n)) + "]"


def test_a_huge_grid_is_refused_before_any_cell_is_made(tmp_path):
    """X32 of the hostile round, smaller: 400 margins × 300 time budgets × 2 k (240 000 cells)
    is refused at once (it took minutes and gigabytes)."""
    spec = grid_spec(tmp_path, f'k = ["auto", "paper"]\nmargin = {numbers(400, 0.0002)}\n'
                               f"max_time = {numbers(300, 0.01)}\n")
    stderr = load_in_child(spec)
    assert "SpecError" in stderr and "`grid`: 240000 cells" in stderr, stderr
    assert f"at most {experiment.spec.MAX_CELLS}" in stderr, stderr


def test_the_cells_are_counted_without_the_laws_irrelevant_policies():
    count = experiment.spec._cell_count
    # The kinematic law takes no damping, the dynamic law no speed, the descent neither.
    axes = {"law": ["kinematic", "dynamic", "descent"], "damping": list("abc"),
            "speed": list("de"), "margin": [0.0, 0.1]}
    assert count(axes) == 2 * 2 + 3 * 2 + 2
    assert count({"margin": [0.0, 0.1], "max_time": [1.0, 2.0, 3.0]}) == 6


def test_too_many_worlds_are_refused_before_they_are_made(tmp_path):
    worlds = ('[worlds]\ngenerator = "quality"\nobstacles = [6]\n'
              "seeds = { first = 0, count = 1500000 }\n")
    stderr = load_in_child(write(tmp_path, 'name = "x"\n' + worlds))
    assert "`worlds`: 1500000 worlds (obstacles × seeds); at most 1000000" in stderr, stderr


def reference_cells(spec_path):
    """The grid's cells as the whole product, its irrelevant policies dropped and its
    duplicates removed in order (what the digest of every experiment so far holds)."""
    import itertools

    doc = experiment.spec._toml.loads(spec_path.read_text())
    tables = doc["grid"] if isinstance(doc["grid"], list) else [doc["grid"]]
    cells, seen = [], set()
    for t in tables:
        axes = []
        for key in experiment.spec.GRID_KEYS:
            if key in t:
                values = t[key] if isinstance(t[key], list) else [t[key]]
                if key in ("margin", "max_time"):
                    values = [float(v) for v in values]
                axes.append([(key, v) for v in values])
        for combo in itertools.product(*axes):
            cell = dict.fromkeys(experiment.spec.GRID_KEYS)
            cell.update(combo)
            if cell["law"] == "kinematic":
                cell["damping"] = None
            elif cell["law"] == "dynamic":
                cell["speed"] = None
            elif cell["law"] == "descent":
                cell["damping"] = cell["speed"] = None
            key = tuple(cell.values())
            if key not in seen:
                seen.add(key)
                cells.append(cell)
    return cells


def test_the_cells_and_their_order_are_the_whole_products(tmp_path):
    """The cells, made law by law from the lists they take, are the whole product's in its
    order: the digest of an experiment written before is unchanged."""
    spec = write(tmp_path, """
        name = "order"
        [worlds]
        generator = "quality"
        obstacles = [6]
        seeds = [1]
        [[grid]]
        law = ["dynamic", "kinematic", "descent", "kinematic"]
        k = ["paper", "auto"]
        damping = ["auto", "paper", "auto"]
        speed = ["paper", "auto"]
        margin = [0.1, 0, 0.0, 0.05]
        [[grid]]
        law = "kinematic"
        speed = ["auto", "paper"]
        margin = [0, 0.02]
        max_time = [30, 10]
        [[grid]]
        sensing = ["sector", "global"]
    """)
    cells = list(load_spec(spec).cells)
    assert cells == reference_cells(spec)
    # dynamic 2 k × 2 damping × 3 margins, kinematic 2 × 2 speeds × 3, descent 2 × 3; 2 × 2 × 2;
    # 2 sensings.
    assert len(cells) == 12 + 12 + 6 + 8 + 2


def test_each_distinct_preparation_is_made_once(tmp_path, monkeypatch):
    """X08 of the hostile round: 100 000 time budgets took minutes of validation. A preparation
    reads neither the physics nor (but for its range) the time budget, nor on a generated world
    the margin (but for its range): 2 laws × 2 margins × 300 budgets × 2 physics cost a
    preparation per law and per extreme value, not 2400."""
    prepared = []
    check = harmonav.check_run_config

    def counting(config, prepare=False):
        if prepare:
            prepared.append(config)
        return check(config, prepare=prepare)

    monkeypatch.setattr(harmonav, "check_run_config", counting)
    spec = load_spec(grid_spec(tmp_path, 'law = ["kinematic", "dynamic"]\nmargin = [0, 0.1]\n'
                                         f"max_time = {numbers(300, 0.5)}\n"
                                         'physics = ["builtin", "rapier"]\n'))
    assert len(spec.cells) == 2400
    assert len(prepared) <= 6, len(prepared)
    # Yet a cell that cannot be prepared is still found, whichever list makes it so.
    monkeypatch.setattr(harmonav, "check_run_config", check)
    scenario = f'[worlds]\nscenarios = ["{SCENARIOS / "shapes" / "mixed.toml"}"]\n'
    for grid, worlds, words in [
        ('margin = [0, 0.5, 0.05]\nmax_time = [10, 20]\n', GOOD_WORLDS, ["margin = 0.5"]),
        ('margin = [0, 0.05]\nmax_time = [10, 1e300, 20]\n', GOOD_WORLDS, ["max_time = 1e+300"]),
        # A file's shapes may fail under any margin: each is prepared.
        ('margin = [0, 0.5, 0.01]\nk = ["auto", "paper"]\n', scenario,
         ["margin = 0.5", "star shape"]),
    ]:
        with pytest.raises(SpecError) as err:
            load_spec(grid_spec(tmp_path, grid, worlds))
        assert err.value.field == "grid", str(err.value)
        for w in words:
            assert w in str(err.value), str(err.value)


def test_out_a_file_or_dev_null_is_refused(tmp_path):
    spec = write(tmp_path, TINY)
    rc, stderr = command("run", spec, "--out", spec, "--no-progress", cwd=tmp_path)
    assert_refused(rc, stderr, f"--out {spec} is a file, not a folder")
    if os.path.exists("/dev/null"):
        rc, stderr = command("run", spec, "--out", "/dev/null", "--no-progress", cwd=tmp_path)
        assert_refused(rc, stderr, "--out /dev/null is a character device, not a folder")


def test_the_ray_engine_without_ray_is_refused(tmp_path):
    spec = write(tmp_path, TINY.replace("task_runs = 1", 'task_runs = 1\nkind = "ray"'))
    # Ray hidden: `import ray` raises ImportError, as where it is not installed.
    code = ("import sys; sys.modules['ray'] = None\n"
            "from harmonav.experiment.__main__ import main\n"
            f"sys.exit(main(['run', {str(spec)!r}, '--out', {str(tmp_path / 'out')!r}]))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=tmp_path, timeout=60)
    assert_refused(done.returncode, done.stderr, "`engine.kind`", "needs Ray", "pip install")
    assert not (tmp_path / "out").exists()
    local = write(tmp_path, TINY, "local.toml")
    code = code.replace(str(spec), str(local)).replace("'--out'", "'--engine', 'ray', '--out'")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=tmp_path, timeout=60)
    assert_refused(done.returncode, done.stderr, "--engine ray: the ray engine needs Ray")
    assert not (tmp_path / "out").exists()


@pytest.fixture
def tiny(tmp_path):
    """A finished experiment of two runs, one per task (part-000000, part-000001)."""
    spec = load_spec(write(tmp_path, TINY))
    out = tmp_path / "out"
    experiment.run(spec, out, progress=False)
    return spec, out


def truncate(path):
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def test_a_truncated_part_is_run_again_on_resume(tiny):
    spec, out = tiny
    whole = bits(read_records(out))
    part = out / "parts" / "part-000000.parquet"
    truncate(part)
    summary = experiment.run(spec, out, progress=False)
    assert (summary.resumed, summary.ran) == (1, 1)
    assert len(summary.damaged) == 1 and str(part) in summary.damaged[0], summary.damaged
    assert bits(read_records(out)) == whole


def test_a_part_holding_another_tasks_runs_is_run_again_on_resume(tiny):
    spec, out = tiny
    whole = bits(read_records(out))
    parts = out / "parts"
    (parts / "part-000000.parquet").write_bytes((parts / "part-000001.parquet").read_bytes())
    summary = experiment.run(spec, out, progress=False)
    assert (summary.resumed, summary.ran) == (1, 1)
    assert "runs 1 to 1, not the runs 0 to 0" in summary.damaged[0], summary.damaged
    assert bits(read_records(out)) == whole


@pytest.mark.parametrize("name", ["part-000005.parquet", "part-0.parquet"])
def test_a_foreign_or_duplicate_part_is_refused_by_resume_and_report(tiny, name):
    """The hostile round's repro: a part copied in under another task's name was merged
    ("2 runs" in a 1-run experiment)."""
    spec, out = tiny
    foreign = out / "parts" / name
    foreign.write_bytes((out / "parts" / "part-000000.parquet").read_bytes())
    for call in (lambda: experiment.run(spec, out, progress=False),
                 lambda: experiment.report(out),
                 lambda: read_records(out)):
        with pytest.raises(SpecError, match="not a part of this experiment") as err:
            call()
        assert err.value.file == str(foreign), str(err.value)


def test_the_report_refuses_a_truncated_part_naming_it(tiny, tmp_path):
    _, out = tiny
    part = out / "parts" / "part-000001.parquet"
    truncate(part)
    with pytest.raises(SpecError, match="not a whole Parquet file") as err:
        experiment.report(out)
    assert err.value.file == str(part)
    rc, stderr = command("report", out, "--no-plots", cwd=tmp_path)
    assert_refused(rc, stderr, str(part), "not a whole Parquet file")


def test_the_report_of_an_unfinished_experiment_says_so(tiny):
    _, out = tiny
    (out / "parts" / "part-000001.parquet").unlink()
    text = experiment.report(out)
    assert text.startswith("1 of the experiment's 2 runs are written: it is not finished"), text


def test_the_report_prints_a_dash_for_an_unmeasured_column(tmp_path):
    spec = load_spec(write(tmp_path, TINY + "[measure]\nshortest = false\n"))
    experiment.run(spec, tmp_path / "out", progress=False)
    text = experiment.report(tmp_path / "out")
    assert "NaN" not in text, text
    row = [line for line in text.splitlines() if line.startswith("| Kinematic")][0]
    header = [line for line in text.splitlines() if line.startswith("| law")][0]
    column = [c.strip() for c in header.split("|")].index("path/shortest median / p90 / max")
    assert row.split("|")[column].strip() == "—", row

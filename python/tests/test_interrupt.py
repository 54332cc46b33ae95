"""Ctrl-C during long runs (hostile round 2026-12-06, D6): `FloorPlan.run` and `Scenario.run`
poll the signal handlers as the run goes, raise `KeyboardInterrupt` within a fraction of a
second, and leave nothing of an unfinished `out` set (no staging folder, no folder the run
created)."""

import _thread
import pathlib
import threading
import time

import pytest

import harmonav

ROOT = pathlib.Path(__file__).resolve().parents[2]

# An L-shaped room crossed so slowly (a gain of 1e-4) that the run lasts until max_time: 10⁷
# steps, more than 30 s here, unless it is interrupted.
SLOW_FLOOR = """
name = "slow-floor"

[floor_plan]
outer = [[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [2.0, 2.0], [2.0, 6.0], [0.0, 6.0]]
max_element = 0.1

[robot]
model = "kinematic"
start = [1.0, 5.4]
goal = [5.4, 1.0]
radius = 0.1
margin = 0.1
gain = 1e-4

[sim]
max_time = {max_time}
arrival = 0.05
sensor_range = 1.0
"""


def interrupted(call, after=0.5):
    """Runs `call()` with Ctrl-C (simulated) `after` seconds in; returns how long it took to
    raise KeyboardInterrupt."""
    timer = threading.Timer(after, _thread.interrupt_main)
    t0 = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            call()
    finally:
        timer.cancel()
        timer.join()
    return time.monotonic() - t0


def leftovers(folder):
    return sorted(p.name for p in folder.rglob("*")) if folder.exists() else []


def test_ctrl_c_stops_a_floor_plan_run_and_leaves_no_staging_folder(tmp_path):
    path = tmp_path / "slow.toml"
    path.write_text(SLOW_FLOOR.format(max_time=1e5))
    plan = harmonav.FloorPlan.load(path)
    out = tmp_path / "new" / "set"  # made by the run, so removed with it
    elapsed = interrupted(lambda: plan.run(out=out))
    assert elapsed < 5.0, f"interrupted after {elapsed:.1f} s"
    assert not (tmp_path / "new").exists(), leftovers(tmp_path / "new")
    # Without `out` too; and an existing folder keeps what it held, with no staging folder.
    assert interrupted(plan.run) < 5.0
    kept = tmp_path / "kept"
    kept.mkdir()
    (kept / "notes.txt").write_text("mine")
    assert interrupted(lambda: plan.run(out=kept)) < 5.0
    assert leftovers(kept) == ["notes.txt"]


def test_ctrl_c_stops_a_scenario_run_and_leaves_no_staging_folder(tmp_path):
    # The 10 km crossing at a 2 ms step: some 3·10⁶ states, about 20 s uninterrupted here.
    text = (ROOT / "scenarios" / "long" / "ten-km.toml").read_text()
    assert "dt = 0.01" in text
    path = tmp_path / "ten-km-fine.toml"
    path.write_text(text.replace("dt = 0.01", "dt = 0.002"))
    scenario = harmonav.Scenario.load(path)
    out = tmp_path / "ten-km"
    elapsed = interrupted(lambda: scenario.run(model="kinematic", out=out))
    assert elapsed < 5.0, f"interrupted after {elapsed:.1f} s"
    assert leftovers(out) == []

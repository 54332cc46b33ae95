"""Scenario files: validation errors, runs with their arrays, sweeps."""

import json

import numpy as np
import pytest

import harmonav
from conftest import SCENARIOS


def test_a_run_returns_the_summary_and_the_trajectory(tmp_path):
    sc = harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml")
    assert sc.name == "shapes-mixed"
    res = sc.run(out=tmp_path)
    s = res.summary
    assert s["reached"] and s["outcome"]["kind"] == "reached"
    assert all(g["passed"] for g in s["guarantees"])
    n = len(res.t)
    assert res.x.shape == (n, 2) and res.v.shape == (n, 2) and res.theta.shape == (n,)
    assert np.all(np.diff(res.t) >= 0) and abs(res.t[-1] - s["time_s"]) < 1e-9
    assert np.all((res.theta >= 0) & (res.theta <= 1))
    np.testing.assert_allclose(res.x[0], [-4.0, 0.1])
    assert np.linalg.norm(res.x[-1] - [4.0, 0.0]) <= 0.01
    names = [d["obstacle"] for d in res.discoveries]
    assert names == [d["obstacle"] for d in s["discoveries"]] and len(names) >= 1
    written = json.loads((tmp_path / "summary.json").read_text())
    assert written["time_s"] == s["time_s"]


def test_the_model_override_runs_the_other_law():
    sc = harmonav.Scenario.load(SCENARIOS / "shapes" / "dynamic-small.toml")
    res = sc.run(model="kinematic")
    assert res.summary["model"] == "kinematic" and res.summary["reached"]
    with pytest.raises(ValueError, match="kinematic"):
        sc.run(model="pid")
    with pytest.raises(ValueError, match="rapier"):
        sc.run(physics="bullet")


def test_controller_is_a_deprecated_alias_of_model():
    sc = harmonav.Scenario.load(SCENARIOS / "shapes" / "dynamic-small.toml")
    with pytest.warns(DeprecationWarning, match="model="):
        old = sc.run(controller="kinematic")
    assert old.summary == sc.run(model="kinematic").summary
    with pytest.raises(ValueError, match="model only"):
        sc.run(model="kinematic", controller="kinematic")
    with pytest.warns(DeprecationWarning):
        swept = harmonav.sweep(sc, 2, seed=1, controller="kinematic")
    assert list(swept.starts.ravel()) == list(harmonav.sweep(sc, 2, seed=1, model="kinematic").starts.ravel())


def test_load_errors_name_the_file_the_field_and_the_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(
        'name = "x"\n[workspace]\ntype = "circle"\ncenter = [0.0, 0.0]\nradius = -1.0\n'
        '[robot]\nmodel = "kinematic"\nstart = [0.0, 0.0]\ngoal = [1.0, 0.0]\n'
    )
    with pytest.raises(ValueError) as err:
        harmonav.Scenario.load(bad)
    msg = str(err.value)
    assert "bad.toml" in msg and "workspace.radius" in msg and "positive" in msg
    broken = tmp_path / "broken.toml"
    broken.write_text('name = "x"\n[workspace\n')
    with pytest.raises(ValueError, match=r"broken\.toml:2"):
        harmonav.Scenario.load(broken)
    with pytest.raises(ValueError, match="no-such"):
        harmonav.Scenario.load(tmp_path / "no-such.toml")


def test_sweep_from_a_count_and_from_an_array():
    sc = harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml")
    res = harmonav.sweep(sc, 12, seed=3, model="kinematic")
    assert res.starts.shape == (12, 2)
    assert res.outcomes.tolist() == ["reached"] * 12 and res.reached.all()
    assert np.all(res.times > 0) and res.report["reached"] == 12
    again = harmonav.sweep(sc, res.starts[:3], model="kinematic")
    np.testing.assert_array_equal(again.times, res.times[:3])
    with pytest.raises(ValueError, match="finite"):
        harmonav.sweep(sc, np.array([[np.nan, 0.0]]))
    with pytest.raises(TypeError):
        harmonav.sweep(sc, "many")


def test_the_shortest_path_is_shorter_than_the_run_and_longer_than_the_segment():
    sc = harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml")
    length, waypoints = sc.shortest_path()
    start, goal = np.array([-4.0, 0.1]), np.array([4.0, 0.0])
    np.testing.assert_allclose(waypoints[0], start)
    np.testing.assert_allclose(waypoints[-1], goal)
    assert abs(np.sum(np.linalg.norm(np.diff(waypoints, axis=0), axis=1)) - length) < 1e-9
    res = sc.run()
    travelled = np.sum(np.linalg.norm(np.diff(res.x, axis=0), axis=1))
    assert np.linalg.norm(goal - start) <= length <= travelled


def test_a_start_on_a_symmetry_axis_is_warned_about_and_explained(tmp_path):
    # One disc between start and goal: the run stops at the saddle behind the disc.
    sc = harmonav.Scenario.load(SCENARIOS / "adversarial" / "one-disc-on-the-axis.toml")
    s = sc.run(out=tmp_path).summary
    assert not s["reached"]
    out = s["outcome"]
    assert out["kind"] == "stalled" and out["point"] == "saddle"
    [w] = s["warnings"]
    assert w["kind"] == "start-on-saddle-manifold"
    np.testing.assert_allclose(w["saddle"], out["position"], atol=1e-3)
    assert abs(out["position"][1]) < 1e-9 and -2.0 < out["position"][0] < -1.0
    assert json.loads((tmp_path / "summary.json").read_text())["warnings"] == s["warnings"]
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_an_invalid_start_is_an_outcome_naming_it():
    # Before, the start inside the disc aborted the whole sweep with a message about a
    # discovery that named no start.
    sc = harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml")
    starts = np.array([[-4.0, 0.1], [-2.0, 1.2], [9.0, 9.0], [-4.0, -0.5]])
    res = harmonav.sweep(sc, starts, model="kinematic")
    assert res.outcomes.tolist() == ["reached", "invalid-start", "invalid-start", "reached"]
    assert res.reached.tolist() == [True, False, False, True]
    assert np.isnan(res.times[1]) and np.isnan(res.times[2]) and res.times[0] > 0
    report = res.report
    assert report["invalid_starts"] == 2 and report["reached"] == 2
    inside, outside = report["failures"]
    assert inside["reason"] == "not run: starts[1] lies inside obstacle disc"
    assert inside["outcome"] == {
        "kind": "invalid-start",
        "index": 1,
        "problem": {"kind": "in-obstacle", "obstacle": "disc"},
    }
    assert "starts[2]" in outside["reason"] and "outside the workspace" in outside["reason"]


def test_a_sweep_of_no_starts_is_refused_as_the_cli_refuses_it():
    # Before, sweep(0) returned an empty result.
    sc = harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml")
    for none in (0, np.empty((0, 2))):
        with pytest.raises(ValueError, match="at least 1"):
            harmonav.sweep(sc, none)
    with pytest.raises(ValueError, match="at most 1000000"):
        harmonav.sweep(sc, 1_000_001)


def test_ctrl_c_stops_a_sweep_between_parts():
    # 3000 starts take about 45 s here; Ctrl-C (simulated) 0.2 s in must stop the sweep within
    # a part of a few starts. Before, the interrupt waited for the whole sweep.
    import _thread
    import threading
    import time

    sc = harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml")
    timer = threading.Timer(0.2, _thread.interrupt_main)
    t0 = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        harmonav.sweep(sc, 3000, seed=1, model="kinematic")
    elapsed = time.monotonic() - t0
    timer.join()
    assert elapsed < 5.0, f"interrupted after {elapsed:.1f} s"


def test_a_file_with_movers_runs_in_rapier_and_one_with_robots_is_refused():
    """Since 2026-12-07 rapier flies a file with movers (docs/movers.md §8): the person's
    crossing arrives with every guarantee, its movers judged; several robots are refused by
    name."""
    sc = harmonav.Scenario.load(SCENARIOS / "movers" / "person-crossing.toml")
    s = sc.run(physics="rapier").summary
    assert s["physics"] == "rapier" and s["reached"], s["guarantees"]
    assert all(g["passed"] for g in s["guarantees"]), s["guarantees"]
    assert s["movers"]["mover_contacts"] == 0 and s["physics_contacts"] == 0
    robots = harmonav.Scenario.load(SCENARIOS / "movers" / "four-robots-swap.toml")
    with pytest.raises(ValueError, match=r"\[\[robots\]\].*rapier"):
        robots.run(physics="rapier")

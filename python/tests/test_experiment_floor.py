"""harmonav.experiment on floor plans (issue 51, item 4): a run configuration or a spec may
name a floor-plan file. The record is the run that ``FloorPlan.run`` (``harmonav run``) makes,
the overrides set the keys a star world's do, the starts are drawn by the file's ``[starts]``
rule, and a star world and a floor plan share one experiment's records."""

import textwrap

import numpy as np
import pytest

import harmonav

pytest.importorskip("pyarrow")
from harmonav import experiment  # noqa: E402
from harmonav.experiment import load_spec, read_records  # noqa: E402

from conftest import REPO  # noqa: E402

U_TRAP = REPO / "scenarios" / "floorplans" / "u-trap.toml"
MIXED = REPO / "scenarios" / "shapes" / "mixed.toml"


def test_a_floor_plan_record_is_the_run_that_floor_plan_run_makes():
    plan = harmonav.FloorPlan.load(U_TRAP)
    for model in ("kinematic", "dynamic"):
        summary = plan.run(model=model).summary
        (record,) = harmonav.run_batch([{"scenario": str(U_TRAP), "model": model}])
        assert record["error"] is None, record["error"]
        for key in ("reached", "time_s", "path_length", "min_clearance", "max_speed",
                    "final_distance", "speed_bound"):
            assert record[key] == summary[key], key
        assert record["steps"] == summary["commands"]
        assert record["guarantees"] == summary["guarantees"]
        assert record["outcome"] == "reached" and record["guarantees_held"]
        assert record["k_policy"] == summary["k_policy"] == "auto"
        assert record["effective"]["model"] == model
        assert record["effective"]["sensing"] == "range"
        assert record["effective"]["obstacles"] == 1
        # The reference is the grid geodesic in W_δ; the robot stops within the arrival
        # radius (0.05 m) of the goal, so its path may be that much shorter.
        shortest = record["shortest_length"]
        assert 6.0 < shortest < record["path_length"] + 0.05
        assert record["path_over_shortest"] == record["path_length"] / shortest


def test_overrides_set_a_floor_plans_keys_and_star_world_settings_are_refused_by_name():
    f = str(U_TRAP)
    records = harmonav.run_batch([
        {"scenario": f, "k": "paper"},
        {"scenario": f, "model": "dynamic", "damping": "paper", "max_time": 1.0},
        {"scenario": f, "margin": 0.15},
        {"scenario": f, "start": [4.7, 2.5], "start_index": 3},
        {"scenario": f, "sensing": "global"},
        {"scenario": f, "model": "descent"},
        {"scenario": f, "margin": -1.0},
    ], threads=2)
    paper, short, wide, walled, sensing, descent, bad = records
    assert paper["error"] is None and paper["effective"]["k"] == "paper"
    assert paper["k_policy"] == "paper" and paper["reached"]
    assert short["effective"]["damping"] == "paper" and short["effective"]["max_time"] == 1.0
    assert short["outcome"] == "timed-out" and not short["reached"]
    assert wide["effective"]["margin"] == 0.15 and wide["min_clearance"] >= 0.15 - 1e-9
    # A start in the U's wall is the sweep's outcome, named by its index, not an error.
    assert walled["error"] is None and walled["outcome"] == "invalid-start"
    assert "starts[3]" in walled["outcome_detail"] and "floor plan" in walled["outcome_detail"]
    assert "sensing" in sensing["error"] and "floor plan" in sensing["error"]
    assert "descent" in descent["error"] and "floor plan" in descent["error"]
    assert "robot.margin" in bad["error"] and "u-trap.toml" in bad["error"]


def test_random_starts_on_a_floor_plan_are_seeded_and_valid():
    config = {"scenario": str(U_TRAP)}
    a = harmonav.random_start_points(config, 4, 7)
    assert a == harmonav.random_start_points(config, 4, 7)
    assert a != harmonav.random_start_points(config, 4, 8)
    # The file's own [starts] (count 6, seed 25) are the same rule's.
    plan = harmonav.FloorPlan.load(U_TRAP)
    np.testing.assert_array_equal(harmonav.random_start_points(config, 6, 25), plan.starts[1:])
    records = harmonav.run_batch([dict(config, start=p) for p in a], threads=2)
    assert all(r["error"] is None and r["outcome"] != "invalid-start" for r in records)
    with pytest.raises(ValueError, match="starts"):
        harmonav.random_start_points(config, 0, 1)


def test_a_spec_runs_a_star_world_and_a_floor_plan_together(tmp_path):
    spec_path = tmp_path / "spec.toml"
    spec_path.write_text(textwrap.dedent(f"""
        name = "both"
        [worlds]
        scenarios = ["{MIXED.as_posix()}", "{U_TRAP.as_posix()}"]
        [starts]
        random = 2
        seed = 3
        [grid]
        law = ["kinematic", "dynamic"]
        [engine]
        task_runs = 3
    """))
    spec = load_spec(spec_path)
    experiment.run(spec, tmp_path / "out", progress=False)
    rows = read_records(tmp_path / "out").to_pylist()
    assert len(rows) == spec.runs == 2 * 2 * 2
    floor = [r for r in rows if r["world"].endswith("u-trap.toml")]
    star = [r for r in rows if r["world"].endswith("mixed.toml")]
    assert len(floor) == len(star) == 4
    assert all(r["error"] is None for r in rows), [r["error"] for r in rows]
    assert all(r["guarantee.no-collision.passed"] for r in rows)
    # The floor plan's own guarantees are columns, null for the star world's rows.
    assert all(r["guarantee.stayed-in-certified-region.passed"] for r in floor)
    assert all(r["guarantee.stayed-in-certified-region.passed"] is None for r in star)
    assert {r["sensing"] for r in floor} == {"range"}


def test_a_broken_floor_plan_in_a_spec_is_named(tmp_path):
    broken = tmp_path / "broken.toml"
    broken.write_text(U_TRAP.read_text().replace("margin = 0.1", "margin = -0.1"))
    spec_path = tmp_path / "spec.toml"
    spec_path.write_text('name = "x"\n[worlds]\nscenarios = ["broken.toml"]\n')
    with pytest.raises(experiment.SpecError) as err:
        load_spec(spec_path)
    assert err.value.field == "worlds.scenarios[0]"
    assert "robot.margin" in str(err.value) and "broken.toml" in str(err.value)

"""Floor-plan files from Python (issue 25): ``FloorPlan.load`` solves the map, ``run`` judges
every guarantee as ``harmonav run`` does, and ``out`` writes the same set."""

import json
import os
import pathlib

import numpy as np
import pytest

import harmonav

ROOT = pathlib.Path(__file__).resolve().parents[2]
L_ROOM = ROOT / "scenarios" / "floorplans" / "l-room.toml"


def test_a_floor_plan_runs_from_python_with_every_guarantee_judged(tmp_path):
    plan = harmonav.FloorPlan.load(L_ROOM)
    assert plan.name == "floorplan-l-room"
    assert plan.starts.shape == (7, 2)  # robot.start and the six seeded starts
    np.testing.assert_array_equal(plan.starts[0], [1.0, 5.4])
    assert plan.elements > 100 and plan.delta > 0.0
    result = plan.run(model="kinematic", out=tmp_path)
    s = result.summary
    assert s["reached"] and s["outcome"] == "reached"
    names = {g["name"]: g["passed"] for g in s["guarantees"]}
    assert all(names.values()), names
    assert {"stayed-in-certified-region", "no-collision-between-states"} <= names.keys()
    # The kept path starts at the start and ends within the arrival threshold of the goal.
    np.testing.assert_array_equal(result.x[0], plan.starts[0])
    assert np.linalg.norm(result.x[-1] - np.array(s["goal"])) < 0.05
    # Its length is the summary's path length (every state kept in a run this short).
    steps = np.linalg.norm(np.diff(result.x, axis=0), axis=1).sum()
    assert steps == pytest.approx(s["path_length"], rel=1e-9)
    assert json.loads((tmp_path / "summary.json").read_text()) == s
    assert (tmp_path / "trajectory.svg").read_text().startswith("<svg")


def test_a_floor_plan_flies_in_rapier_with_the_walls_as_colliders():
    plan = harmonav.FloorPlan.load(ROOT / "scenarios" / "floorplans" / "u-trap.toml")
    s = plan.run(model="kinematic", physics="rapier").summary
    assert s["reached"] and s["physics"] == "rapier" and s["physics_contacts"] == 0
    names = {g["name"]: g["passed"] for g in s["guarantees"]}
    assert names.get("physics-no-contact") is True and all(names.values()), names
    with pytest.raises(ValueError, match="physics"):
        plan.run(physics="bullet")


def test_a_floor_plans_differential_drive_flies_in_rapier():
    """Issue 53: a floor plan with `base = "diff"` runs in rapier too (refused by name before
    2026-12-07): the body driven along its heading, every guarantee held, no contact."""
    plan = harmonav.FloorPlan.load(ROOT / "scenarios" / "diff" / "floor-l-room.toml")
    s = plan.run(physics="rapier").summary
    assert s["reached"] and s["physics"] == "rapier" and s["physics_contacts"] == 0
    names = {g["name"]: g["passed"] for g in s["guarantees"]}
    assert all(names.values()), names
    assert {"diff-command-bounds", "physics-no-contact"} <= names.keys()
    assert s["diff"]["max_v"] <= 0.5 and s["diff"]["max_omega"] <= 2.0


def test_a_floor_plan_with_a_lidar_perceives_its_furniture_from_scans(tmp_path):
    """`[sensor] type = "lidar"` in a floor plan (issue 26 in issue 25's maps): the furniture
    comes from the scans alone, the summary judges the perception as a star world's does, and
    the figure draws the perceived shapes over the true ones."""
    plan = harmonav.FloorPlan.load(ROOT / "scenarios" / "floorplans" / "lidar-room.toml")
    s = plan.run(model="kinematic", out=tmp_path / "lidar").summary
    svg = (tmp_path / "lidar" / "trajectory.svg").read_text()
    assert "perceived (lidar)" in svg and "#19BED7" in svg  # the perceived outlines' colour
    assert s["reached"], s["outcome"]
    names = {g["name"]: g["passed"] for g in s["guarantees"]}
    assert all(names.values()), names
    assert {"perceived-covers-seen-truth", "perceived-shapes-only-grow", "scans-accepted"} <= set(
        names
    )
    p = s["perception"]
    assert p["scans"] > 10 and p["events"] >= 1 and p["perceived"] >= 1
    assert p["seen_points"] > 0 and p["uncovered_points"] == 0
    assert s["discoveries"] == []  # nothing handed over exact
    # Without the lidar a floor plan has no perception report and no perceived outline.
    bare = harmonav.FloorPlan.load(L_ROOM).run(model="kinematic", out=tmp_path / "bare")
    assert bare.summary["perception"] is None
    svg = (tmp_path / "bare" / "trajectory.svg").read_text()
    assert "perceived (lidar)" not in svg and "#19BED7" not in svg


def test_the_heading_policy_shortens_the_kinematic_path_and_is_checked():
    # docs/maths.md §13.3: "auto" (the default) follows the shortest path within 60° of −∇Θ,
    # "paper" the flow line of Θ; both arrive with every guarantee, and in the L room from the
    # file's start the auto path is the shorter (7.6 against 9.8 m when measured).
    plan = harmonav.FloorPlan.load(L_ROOM)
    auto = plan.run(model="kinematic").summary
    paper = plan.run(model="kinematic", heading="paper").summary
    assert auto["heading"] == "auto" and paper["heading"] == "paper"
    for s in (auto, paper):
        assert s["reached"] and all(g["passed"] for g in s["guarantees"]), s["guarantees"]
    assert auto["path_length"] < 0.85 * paper["path_length"], (auto, paper)
    # The dynamic law takes it too, as a force that does no work (§13.3).
    dynamic = plan.run(model="dynamic").summary
    assert dynamic["heading"] == "auto"
    assert plan.run(model="dynamic", heading="paper").summary["heading"] == "paper"
    assert dynamic["reached"] and all(g["passed"] for g in dynamic["guarantees"])
    with pytest.raises(ValueError, match='heading: unknown heading policy "straight"'):
        plan.run(heading="straight")


def test_the_escape_frees_a_start_held_at_a_rest_point_of_the_slide():
    # docs/maths.md §13.7: from the file's start, in the aisle below a shelf row, the hold
    # presses the robot against the edge of the certified region at a local minimum of Θ
    # there; under "auto" it escapes along the shortest path and arrives (10.2 s, 3 escapes, at
    # max_element = 0.2 on 2026-12-04), along the flow lines of Θ ("paper", no shortest path,
    # no escape) it stays (4.5 m from the goal after 300 s).
    plan = harmonav.FloorPlan.load(ROOT / "scenarios" / "floorplans" / "map-warehouse-starts.toml")
    auto = plan.run(model="kinematic").summary
    assert auto["reached"] and auto["escapes"] >= 1, auto
    assert all(g["passed"] for g in auto["guarantees"]), auto["guarantees"]
    paper = plan.run(model="kinematic", heading="paper").summary
    assert not paper["reached"] and paper["escapes"] == 0 and paper["final_distance"] > 1.0
    names = {g["name"]: g["passed"] for g in paper["guarantees"]}
    assert names["no-collision"] and names["stayed-in-certified-region"], names


def test_a_floor_plan_run_from_another_start_and_bad_input():
    plan = harmonav.FloorPlan.load(L_ROOM)
    start = plan.starts[3]
    result = plan.run(model="dynamic", start=start)
    assert result.summary["start"] == list(start)
    assert result.summary["speed_bound"] == pytest.approx(2.0)
    with pytest.raises(ValueError, match="unknown model"):
        plan.run(model="teleport")
    with pytest.raises(ValueError, match="start"):
        plan.run(start=[np.nan, 1.0])
    # In a wall, outside the plan, and inside a sensed obstacle: refused before any run, as
    # the file's robot.start is.
    for bad in ([0.0, 0.0], [100.0, 100.0], [3.5, 0.9]):
        with pytest.raises(ValueError, match="start: .*(walls|obstacles)"):
            plan.run(start=bad)
    with pytest.raises(ValueError, match="out:"):
        plan.run(out="")


def test_a_bad_floor_plan_is_named(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(L_ROOM.read_text().replace("start = [1.0, 5.4]", "start = [4.0, 4.0]"))
    with pytest.raises(ValueError, match=r"bad\.toml.*robot\.start"):
        harmonav.FloorPlan.load(bad)
    with pytest.raises(ValueError, match="cannot read"):
        harmonav.FloorPlan.load(os.fspath(tmp_path / "missing.toml"))


def test_the_certified_level_bounds_the_layer_edge_and_marks_the_starts():
    plan = harmonav.FloorPlan.load(ROOT / "scenarios" / "floorplans" / "u-trap.toml")
    c = plan.certify_level()
    assert 0.0 < c["c_delta"] <= c["c_delta_sampled"] < 1.0
    assert c["phi_certified"] <= c["phi_sampled"] and c["evaluations"] > 0
    flags = c["starts_certified"]
    assert len(flags) == len(plan.starts)
    # The start beside the goal lies below c_δ; the file's start, across the U, does not.
    assert flags[1] and not flags[0], flags
    # c_s (§13.9): the slide may rest in the U's pocket, at or above c_δ.
    assert c["c_delta"] <= c["c_slide"] < 1.0 and c["phi_slide"] >= c["phi_certified"]

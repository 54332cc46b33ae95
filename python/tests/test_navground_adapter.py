"""The navground adapter of issue 54 (``harmonav.navground``, docs/movers.md §9):
a tiny antipodal crowd in navground with the `Harmonav` behaviour arrives without contact and
never below the margin, and ORCA behind the `HarmonavFilter` modulation never touches. Skipped
when navground is not installed (it is not a dependency of harmonav), except in CI."""

import os

import numpy as np
import pytest

# HARMONAV_REQUIRE_NAVGROUND: .ci/run installs navground, so the test fails instead of skipping.
if not os.environ.get("HARMONAV_REQUIRE_NAVGROUND"):
    pytest.importorskip("navground")
from navground import core, sim  # noqa: E402

from harmonav import navground as hn  # noqa: E402

MARGIN = 0.01


def experiment(behavior: str, state: str, number: int = 4) -> str:
    """navground's Antipodal example (radius 2 m, agents of 0.1 m at 0.08 m/s), omnidirectional
    with heading idle, `number` agents, 1 200 steps of 0.1 s."""
    return f"""
steps: 1200
time_step: 0.1
record_pose: true
record_collisions: true
record_task_events: true
terminate_when_all_idle_or_stuck: true
scenario:
  type: Antipodal
  position_noise: 0.005
  orientation_noise: 0.01
  radius: 2
  tolerance: 0.2
  groups:
    - number: {number}
      radius: 0.1
      control_period: 0.1
      speed_tolerance: 0.01
      kinematics: {{type: Omni, max_speed: 0.166}}
      behavior: {behavior}
      state_estimations: {state}
"""


def least_gap(run) -> float:
    """The least body gap between two agents at the recorded poses."""
    p = np.asarray(run.poses, dtype=float)[:, :, :2]
    r = np.array([a.radius for a in run.world.agents])
    i, j = np.triu_indices(p.shape[1], 1)
    d = np.hypot(*(p[:, i] - p[:, j]).transpose(2, 0, 1))
    return float((d - r[i] - r[j]).min())


def test_the_components_are_registered_by_name():
    assert "Harmonav" in core.Behavior.types
    assert "HarmonavFilter" in core.BehaviorModulation.types
    assert "HarmonavSensing" in sim.StateEstimation.types
    b = core.Behavior.make_type("Harmonav")
    assert b.get("peers") == "reciprocal"
    assert b.get("position_error") == pytest.approx(hn.FLOAT_ERROR, rel=1e-6)  # float32


def test_a_harmonav_crowd_swaps_without_contact_and_arrives():
    behavior = ("{type: Harmonav, optimal_speed: 0.08, safety_margin: %s, heading: idle}"
                % MARGIN)
    exp = sim.load_experiment(experiment(behavior, "[{type: HarmonavSensing, range: 10.0}]"))
    run = exp.run_once(0)
    agents = run.world.agents
    assert np.asarray(run.collisions).size == 0
    assert all(a.task.done() for a in agents)
    assert least_gap(run) >= MARGIN
    for a in agents:  # every command went through the filter, and was certified
        summary = a.behavior.log.summary()
        assert len(a.behavior.log.modes) == sum(summary[m] for m in hn.MODES)
        assert summary["overwhelmed"] == summary["refused"] == 0
        assert summary["yielding"] > 0  # the crowd met in the middle


def test_orca_behind_the_filter_never_touches():
    behavior = ("{type: ORCA, optimal_speed: 0.08, safety_margin: %s, heading: idle, "
                "modulations: [{type: HarmonavFilter}]}" % MARGIN)
    state = "[{type: Bounded, range: 10.0}, {type: HarmonavSensing, range: 10.0}]"
    exp = sim.load_experiment(experiment(behavior, state))  # keep it: the run refers to it
    run = exp.run_once(0)
    assert np.asarray(run.collisions).size == 0
    assert least_gap(run) >= MARGIN
    logs = [a.behavior.modulations[0].log for a in run.world.agents]
    assert all(len(log.modes) > 0 for log in logs)


@pytest.mark.parametrize("comfort", [0.0, 0.1])
def test_the_comfort_property_keeps_noncooperative_neighbours_farther(comfort):
    """Four Harmonav agents that take each other as non-cooperative, with `comfort` (the
    navigator's `comfort=`, docs/movers.md §7): never touch, and with 0.1 m keep 0.1 m more
    than the margin (the control, 0: within 0.05 m). With the comfort they do not all arrive:
    each waits for the others to keep their distance (comfort is for people, not peers)."""
    behavior = ("{type: Harmonav, optimal_speed: 0.08, safety_margin: %s, heading: idle, "
                "peers: noncooperative, comfort: %s}" % (MARGIN, comfort))
    exp = sim.load_experiment(experiment(behavior, "[{type: HarmonavSensing, range: 10.0}]"))
    run = exp.run_once(0)
    assert np.asarray(run.collisions).size == 0
    assert all(a.behavior.comfort == pytest.approx(comfort) for a in run.world.agents)
    gap = least_gap(run)
    if comfort:
        assert gap >= MARGIN + 0.9 * comfort
    else:
        assert MARGIN <= gap < MARGIN + 0.05
        assert all(a.task.done() for a in run.world.agents)

"""Shared fixtures: the repository's scenario files and the mixed-shape world built by hand."""

import os
import pathlib
import shutil
import signal

import numpy as np
import pytest

import harmonav

# A runner may start the tests with SIGINT ignored (a background job of a shell without job
# control, as `cmd &` in a script). Python then installs no handler, `_thread.interrupt_main`
# does nothing and child processes ignore Ctrl-C too, so the Ctrl-C tests (test_interrupt.py,
# test_experiment.py, test_scenario.py) would fail for the launcher's sake: give them Python's
# own handler, as a terminal does (children then start with the default disposition).
if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENARIOS = REPO / "scenarios"


@pytest.fixture
def mixed_path():
    return SCENARIOS / "shapes" / "mixed.toml"


@pytest.fixture
def mixed_shapes():
    """scenarios/shapes/mixed.toml written with the Python shape functions."""
    boundary = harmonav.circle([0.0, 0.0], 6.0)
    obstacles = [
        harmonav.circle([-2.0, 1.2], 0.5),
        harmonav.ellipse([-0.5, -1.0], [0.8, 0.3], angle_deg=30.0),
        harmonav.polygon([[0.6, 0.6], [1.6, 0.6], [1.6, 1.6], [0.6, 1.6]], 0.1),
        harmonav.star([2.5, -1.0], 0.5, [(3, 0.1, 0.0)]),
    ]
    return boundary, obstacles, np.array([4.0, 0.0])


@pytest.fixture
def cli():
    """The `harmonav` binary: $HARMONAV_CLI, else the workspace's debug or release build.
    Skips when none is built, unless $HARMONAV_CLI names one (then it must exist)."""
    named = os.environ.get("HARMONAV_CLI")
    if named:
        assert pathlib.Path(named).is_file(), f"HARMONAV_CLI={named} does not exist"
        return named
    for build in ("release", "debug"):
        path = REPO / "target" / build / "harmonav"
        if path.is_file():
            return str(path)
    found = shutil.which("harmonav")
    if found is None:
        pytest.skip("no harmonav binary built (cargo build -p harmonav-cli)")
    return found


def free_points(field, n, seed, extent=5.5):
    """`n` seeded points in the free space of `field` inside [-extent, extent]²."""
    rng = np.random.default_rng(seed)
    out = np.empty((0, 2))
    while len(out) < n:
        p = rng.uniform(-extent, extent, size=(4 * n, 2))
        out = np.vstack([out, p[field.free(p)]])
    return out[:n]

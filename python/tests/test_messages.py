"""Error messages and refusals of the hostile round of 2026-12-06 (docs of the round:
D9, D10, D19.8, D19.11): control characters escaped, NumPy imported with the package, huge
integers and scan dtypes refused by name."""

import inspect
import math
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import harmonav

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "scenarios"
OFFICE = SCENARIOS / "floorplans" / "maps" / "office.yaml"
SQUARE = [[0.0, 0.0], [5.0, 0.0], [5.0, 5.0], [0.0, 5.0]]
# Every control character a terminal acts on (C0, DEL, C1) and the bidirectional overrides.
RAW = ["\x1b", "\x07", "\x9b", "\x7f", "\r", "\u202e"]


def assert_escaped(message):
    for c in RAW:
        assert c not in message, (c, message)


# D9: control characters from paths and from file content are escaped.


def test_a_path_with_escape_sequences_is_escaped_in_the_error():
    with pytest.raises(ValueError) as err:
        harmonav.FloorPlan.load("\x1b]0;PWNED\x07x.toml")
    message = str(err.value)
    assert_escaped(message)
    # Written as Python writes them, the rest of the path kept.
    assert "\\x1b]0;PWNED\\x07x.toml" in message
    with pytest.raises(ValueError) as err:
        harmonav.Scenario.load("a\u202eb\x9b2J\rc.toml")
    assert_escaped(str(err.value))
    assert "a\\u202eb\\x9b2J\\rc.toml" in str(err.value)


def test_text_other_than_control_characters_is_kept():
    with pytest.raises(ValueError, match="Θ-é\\\\d.toml"):
        harmonav.FloorPlan.load("Θ-é\\d.toml")


def test_a_map_image_name_with_escape_sequences_is_escaped(tmp_path):
    # The map YAML names an image whose name colours the terminal red: the text comes from a
    # file the user did not write.
    yaml = tmp_path / "M46.yaml"
    yaml.write_text(
        "image: \x1b[31mRED\x1b[0m.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\n"
        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    with pytest.raises(ValueError) as err:
        harmonav.FloorNavigator.from_map(yaml, [1, 1], [4, 4])
    message = str(err.value)
    assert_escaped(message)
    assert "\\x1b[31mRED\\x1b[0m.pgm" in message


# D10: NumPy is imported with the package.


def test_a_numpy_that_cannot_be_imported_fails_the_package_import():
    # Before, `import harmonav` succeeded and the first array made from Rust panicked
    # (PanicException with a Rust backtrace).
    code = (
        "import sys\n"
        "sys.modules['numpy'] = None\n"
        "try:\n"
        "    import harmonav\n"
        "except ImportError as e:\n"
        "    print('ImportError', e)\n"
        "else:\n"
        "    harmonav.FloorNavigator([[0, 0], [5, 0], [5, 5], [0, 5]], [4, 4]).command([1, 1])\n"
        "    print('imported')\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120
    )
    assert run.stdout.startswith("ImportError"), (run.stdout, run.stderr)
    assert "panicked" not in run.stderr and "PanicException" not in run.stderr


# D19.8: integers beyond 64 bits are refused naming the keyword.


@pytest.mark.parametrize("huge", [10**30, -(10**30), 10**400])
def test_huge_integer_keywords_are_refused_by_name(huge):
    boundary = harmonav.circle([0, 0], 4.0)
    with pytest.raises(ValueError, match="`free_memory`"):
        harmonav.Navigator(boundary, [3.0, 0.0], free_memory=huge)
    with pytest.raises(ValueError, match="`free_memory`"):
        harmonav.FloorNavigator(SQUARE, [4, 4], free_memory=huge)
    with pytest.raises(ValueError, match="`speck_pixels`"):
        harmonav.FloorNavigator.from_map(OFFICE, [1.5, 1.5], [8.5, 6.5], speck_pixels=huge)
    scenario = harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml")
    with pytest.raises(ValueError, match="`seed`"):
        harmonav.sweep(scenario, 2, seed=huge)
    with pytest.raises(ValueError, match="`starts`"):
        harmonav.sweep(scenario, huge)


def test_integer_keywords_of_the_wrong_type_or_sign_are_named():
    boundary = harmonav.circle([0, 0], 4.0)
    with pytest.raises(TypeError, match="`free_memory` must be an integer, got float"):
        harmonav.Navigator(boundary, [3.0, 0.0], free_memory=1.5)
    with pytest.raises(ValueError, match="`free_memory`: must be an integer from 0 to 256"):
        harmonav.Navigator(boundary, [3.0, 0.0], free_memory=-1)
    scenario = harmonav.Scenario.load(SCENARIOS / "shapes" / "mixed.toml")
    with pytest.raises(ValueError, match="`seed` must be an integer from 0 to 2\\^64 - 1, got -1"):
        harmonav.sweep(scenario, 2, seed=-1)
    with pytest.raises(ValueError, match="`starts` must be a count .*, got -3"):
        harmonav.sweep(scenario, -3)
    # NumPy integers are integers.
    nav = harmonav.Navigator(boundary, [3.0, 0.0], free_memory=np.int64(3))
    bound = inspect.signature(harmonav.Navigator).bind(*nav.__reduce__()[1]).arguments
    assert bound["free_memory"] == 3


# D19.11: scan ranges are refused by dtype, as points are.


def test_complex_and_boolean_ranges_are_refused():
    nav = harmonav.Navigator(harmonav.circle([0, 0], 10.0), goal=[8, 0], radius=0.1)
    floor = harmonav.FloorNavigator(SQUARE, [4, 4])
    a0, da = -math.pi, 2 * math.pi / 45
    bad = [
        np.full(45, 2.0 + 0.5j),  # before: the imaginary part dropped with a ComplexWarning
        np.ones(45, dtype=bool),  # before: read as 1 m
        [True] * 45,
        ["2.0"] * 45,
        np.full((45, 2), 2.0),
        2.0,
    ]
    for ranges in bad:
        with pytest.raises(TypeError, match="ranges"):
            nav.observe_scan([-3, 0], 0.0, ranges, a0, da, 3.0)
        with pytest.raises(TypeError, match="ranges"):
            floor.observe_scan([1, 1], 0.0, ranges, a0, da, 3.0)
    assert nav.obstacle_count == 0 and floor.obstacles == []
    # Real numbers of any width, in lists, tuples or arrays, with NaN and ±inf, still go in.
    for ranges in (
        np.full(45, np.inf, dtype=np.float32),
        [float("nan")] * 45,
        tuple([3] * 45),
        np.full(45, 5, dtype=np.uint8),
    ):
        u = nav.observe_scan([-3, 0], 0.0, ranges, a0, da, 3.0)
        assert not u.changed


def test_an_obstacle_that_cannot_grow_is_not_blamed_on_robot_radius():
    """Issue 56, D19.10: `add_obstacle` of a shape that loses its star shape when grown by
    radius + margin said "`robot.radius`: offsetting the shape…"; the navigator is unchanged."""
    nav = harmonav.Navigator(harmonav.circle([0, 0], 5), goal=[2, 2], radius=0.1, margin=0.1)
    with pytest.raises(ValueError, match="radius \\+ margin") as e:
        nav.add_obstacle(harmonav.star([0, -2], 0.3, [[1000, 0.01, 0.0]]))
    assert "robot.radius" not in str(e.value) and "star shape" in str(e.value)
    assert nav.obstacle_count == 0

"""Field: Θ and ∇Θ in batches, against finite differences, the scenario loader and the CLI."""

import json
import subprocess

import numpy as np
import pytest

import harmonav
from conftest import REPO, SCENARIOS, free_points


def test_gradient_matches_central_differences(mixed_shapes):
    boundary, obstacles, goal = mixed_shapes
    field = harmonav.Field(boundary, obstacles, goal)
    pts = free_points(field, 400, seed=1)
    # Keep points whose difference stencil stays in the free space.
    h = 1e-6
    stencil = [np.array(d) for d in ([h, 0], [-h, 0], [0, h], [0, -h])]
    keep = np.all([field.free(pts + d) for d in stencil], axis=0)
    pts = pts[keep]
    theta, grad = field.eval(pts)
    assert np.all((theta >= 0.0) & (theta <= 1.0))
    fd = np.stack(
        [
            (field.eval(pts + stencil[0])[0] - field.eval(pts + stencil[1])[0]) / (2 * h),
            (field.eval(pts + stencil[2])[0] - field.eval(pts + stencil[3])[0]) / (2 * h),
        ],
        axis=1,
    )
    scale = np.linalg.norm(grad, axis=1)
    resolved = scale > 1e-6  # where Θ is within rounding of 1, differences of Θ are noise
    assert resolved.sum() > 200
    err = np.linalg.norm(grad - fd, axis=1)[resolved] / scale[resolved]
    assert err.max() < 1e-4, err.max()


def test_theta_is_zero_at_the_goal_and_nan_outside(mixed_shapes):
    boundary, obstacles, goal = mixed_shapes
    field = harmonav.Field(boundary, obstacles, goal)
    pts = np.array([goal, [-2.0, 1.2], [10.0, 0.0], [np.nan, 0.0], [0.0, np.inf]])
    theta, grad = field.eval(pts)
    assert theta[0] == 0.0
    assert np.all(np.isnan(theta[1:])) and np.all(np.isnan(grad[1:]))
    assert field.free(pts).tolist() == [True, False, False, False, False]


def test_hand_built_world_equals_the_scenario_file(mixed_shapes, mixed_path):
    boundary, obstacles, goal = mixed_shapes
    ours = harmonav.Field(boundary, obstacles, goal)
    loaded = harmonav.Scenario.load(mixed_path).field()
    pts = free_points(ours, 200, seed=2)
    a, ga = ours.eval(pts)
    b, gb = loaded.eval(pts)
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(ga, gb)
    assert ours.k == loaded.k == 30.0  # "auto": 6(M + 1)
    assert harmonav.Field(boundary, obstacles, goal, k="paper").k == 5.0


def test_eval_agrees_with_the_cli(mixed_shapes, mixed_path, cli):
    boundary, obstacles, goal = mixed_shapes
    field = harmonav.Field(boundary, obstacles, goal)
    pts = np.vstack([free_points(field, 20, seed=3), [[-2.0, 1.2]]])
    args = [cli, "eval", str(mixed_path), "--json"]
    for x, y in pts:
        args.append(f"--at={float(x)!r},{float(y)!r}")
    rows = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    theta, grad = field.eval(pts)
    for row, t, g in zip(rows, theta, grad):
        if "error" in row:
            assert np.isnan(t) and "disc" in row["error"]
        else:
            assert row["value"] == t
            assert row["grad"] == list(g)


def test_parallel_batches_equal_single_points(mixed_shapes):
    boundary, obstacles, goal = mixed_shapes
    field = harmonav.Field(boundary, obstacles, goal)
    rng = np.random.default_rng(4)
    pts = rng.uniform(-6.5, 6.5, size=(20_000, 2))  # above the parallel threshold
    theta, grad = field.eval(pts)
    for i in rng.choice(len(pts), 50, replace=False):
        t1, g1 = field.eval(pts[i : i + 1])
        np.testing.assert_array_equal(t1[0], theta[i])
        np.testing.assert_array_equal(g1[0], grad[i])
    # Strided input (a column-major copy and a slice) gives the same values.
    t2, _ = field.eval(np.asfortranarray(pts)[::2])
    np.testing.assert_array_equal(t2, theta[::2])


def test_census_has_one_minimum_and_m_saddles(mixed_shapes):
    boundary, obstacles, goal = mixed_shapes
    census = harmonav.Field(boundary, obstacles, goal).census()
    kinds = [c["kind"] for c in census]
    assert kinds == ["minimum"] + ["saddle"] * 4
    lo, hi = census[0]["eigenvalues"]
    assert lo > 0 and hi > 0


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda: harmonav.circle([0, 0], -1.0), ["radius"]),
        (lambda: harmonav.circle([0, float("nan")], 1.0), ["center"]),
        (lambda: harmonav.ellipse([0, 0], [1.0, 0.0]), ["semi_axes"]),
        (lambda: harmonav.polygon([[0, 0], [1, 0]], 0.1), ["vertices"]),
        (lambda: harmonav.star([0, 0], 0.5, [(2, 0.6, 0.0)]), ["harmonics"]),
        (
            lambda: harmonav.Field(harmonav.circle([0, 0], 5), [], [0, 0], k="n+1"),
            ["paper", "auto"],
        ),
        (
            lambda: harmonav.Field(
                harmonav.circle([0, 0], 5),
                [harmonav.circle([1, 0], 1), harmonav.circle([1.5, 0], 1)],
                [3, 0],
            ),
            ["overlap"],
        ),
        (
            lambda: harmonav.Field(harmonav.circle([0, 0], 5), [harmonav.circle([3, 0], 1)], [3, 0]),
            ["destination"],
        ),
        (lambda: harmonav.Field(harmonav.circle([0, 0], 5), [], [0, 0], margin=-1.0), ["margin"]),
    ],
)
def test_bad_input_raises_value_error_naming_the_problem(call, words):
    with pytest.raises(ValueError) as err:
        call()
    for w in words:
        assert w in str(err.value), str(err.value)


@pytest.mark.parametrize(
    "harmonics, words",
    [
        ([(1001, 1e-12, 0.0)], ["harmonics[0]", "1 to 1000", "1001"]),
        ([(3, 0.1, 0.0), (2**32, 1e-12, 0.0)], ["harmonics[1]", "1000", str(2**32)]),
        ([(4_000_000_000, 1e-12, 0.0)], ["harmonics[0]", "1000"]),  # used to hang
        ([(2**80, 1e-12, 0.0)], ["harmonics[0]", "1000"]),
        ([(0, 0.1, 0.0)], ["harmonics[0]", "from 1"]),
        ([(-3, 0.1, 0.0)], ["harmonics[0]", "-3"]),
        ([(3, 0.1)], ["harmonics[0]", "triple"]),
    ],
)
def test_star_harmonic_orders_are_capped_at_1000(harmonics, words):
    with pytest.raises(ValueError) as err:
        harmonav.star([0, 0], 0.5, harmonics)
    for w in words:
        assert w in str(err.value), str(err.value)


def test_the_harmonic_cap_is_stated_and_order_1000_is_accepted():
    assert "1000" in harmonav.star.__doc__
    stub = (REPO / "python" / "harmonav" / "harmonav.pyi").read_text()
    star_stub = stub[stub.index("def star(") :].split("\n\n")[0]
    assert "1000" in star_stub, star_stub
    top = harmonav.star([0, 0], 0.5, [(1000, 1e-5, 0.0), (np.int64(7), 0.01, 0.0)])
    assert top.contains([0.49, 0.0]) and not top.contains([0.52, 0.0])
    # Lists and arrays of triples work as tuples do.
    same = harmonav.star([0, 0], 0.5, [[1000, 1e-5, 0.0], [7, 0.01, 0.0]])
    np.testing.assert_array_equal(same.outline(64), top.outline(64))


def test_points_of_the_wrong_shape_are_refused(mixed_shapes):
    field = harmonav.Field(*mixed_shapes)
    with pytest.raises(ValueError, match=r"\(N, 2\)"):
        field.eval(np.zeros((4, 3)))
    with pytest.raises(TypeError):
        field.eval(np.zeros(4))


def test_theta_matches_an_independent_numpy_implementation():
    """reference.py implements Θ for discs from docs/maths.md §5 with exact disc distances;
    Rust measures the distances that set the band widths on certified outlines (within 1e-4 of the size). So the free
    space agrees exactly, Θ agrees to rounding away from the bands and to the chord error of the
    widths inside them."""
    from reference import from_scenario

    path = SCENARIOS / "scale" / "discs-20-global.toml"
    ours, ref = harmonav.Scenario.load(path).field(), from_scenario(path)
    assert ours.k == ref.k == 126.0
    rng = np.random.default_rng(5)
    x = rng.uniform(-7.2, 7.2, size=(50_000, 2))
    theta, grad = ours.eval(x)
    ref_theta, ref_grad = ref.eval(x)
    free = ~np.isnan(theta)
    np.testing.assert_array_equal(free, ~np.isnan(ref_theta))
    assert 0.5 < free.mean() < 0.95
    diff = np.abs(theta - ref_theta)[free]
    assert diff.max() < 2e-5, diff.max()
    assert np.mean(diff < 1e-12) > 0.5  # outside the bands: the same formula, to rounding
    norm = np.linalg.norm(grad[free], axis=1)
    rel = np.linalg.norm(grad[free] - ref_grad[free], axis=1) / norm
    assert np.percentile(rel, 99) < 1e-4 and rel.max() < 5e-3, (np.percentile(rel, 99), rel.max())

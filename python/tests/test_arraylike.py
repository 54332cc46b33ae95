"""`_Points = ArrayLike` and `_Point` as harmonav.pyi promises: lists, tuples, and int, unsigned
or float32 arrays give what the float64 array gives; anything else raises an error naming the
argument and the problem (issue 23: lists and int or float32 arrays were refused)."""

from decimal import Decimal

import numpy as np
import pytest

import harmonav

BOUNDARY = harmonav.circle([0, 0], 5.0)
OBSTACLES = [harmonav.circle([1, 0], 0.5), harmonav.ellipse([-2, 1], [0.6, 0.3])]
GOAL = np.array([3.0, 0.0])

# Integer points, so that every conversion below is exact and results can be compared bitwise.
PTS = np.array([[0, 0], [2, 1], [-1, -2], [1, 0], [7, 0], [-3, 2]], dtype=np.float64)


def forms(a):
    """The same (N, 2) integer points as every array-like the bindings must accept."""
    return {
        "list": a.tolist(),
        "list of int": a.astype(int).tolist(),
        "tuple of tuples": tuple(map(tuple, a.astype(int).tolist())),
        "int64": a.astype(np.int64),
        "int32": a.astype(np.int32),
        "int8": a.astype(np.int8),
        "uint (non-negative rows)": np.abs(a).astype(np.uint16),
        "float32": a.astype(np.float32),
        "float16": a.astype(np.float16),
        "fortran order": np.asfortranarray(a),
        "strided": np.repeat(a, 2, axis=0)[::2],
        "decimals": [[Decimal(int(x)), Decimal(int(y))] for x, y in a],
    }


def expected(a, form):
    return np.abs(a) if form.startswith("uint") else a


@pytest.fixture(scope="module")
def field():
    return harmonav.Field(BOUNDARY, OBSTACLES, GOAL)


@pytest.mark.parametrize("form", list(forms(PTS)))
def test_field_eval_and_free_accept_every_array_like(field, form):
    ref = expected(PTS, form)
    theta, grad = field.eval(ref)
    assert np.isfinite(theta).sum() >= 3  # the check is not all-NaN
    got_theta, got_grad = field.eval(forms(PTS)[form])
    np.testing.assert_array_equal(got_theta, theta)
    np.testing.assert_array_equal(got_grad, grad)
    np.testing.assert_array_equal(field.free(forms(PTS)[form]), field.free(ref))


@pytest.mark.parametrize("form", list(forms(PTS)))
def test_signed_distance_accepts_every_array_like(form):
    shape = OBSTACLES[1]
    ref = shape.signed_distance(expected(PTS, form))
    assert ref.shape == (len(PTS),) and np.all(np.isfinite(ref))
    np.testing.assert_array_equal(shape.signed_distance(forms(PTS)[form]), ref)


@pytest.mark.parametrize(
    "p",
    [[2, 1], (2, 1), np.array([2, 1]), np.array([2, 1], dtype=np.float32), [np.int16(2), 1.0]],
)
def test_single_points_accept_every_array_like(field, p):
    ref = np.array([2.0, 1.0])
    shape = OBSTACLES[1]
    assert shape.signed_distance(p) == shape.signed_distance(ref)
    assert isinstance(shape.signed_distance(p), float)
    assert shape.contains(p) == shape.contains(ref)
    nav = harmonav.Navigator(BOUNDARY, GOAL)
    nav.add_obstacle(OBSTACLES[0])
    np.testing.assert_array_equal(nav.command(p, p), nav.command(ref, ref))
    assert nav.theta(p) == nav.theta(ref)
    assert repr(harmonav.circle(p, 1.0)) == repr(harmonav.circle(ref, 1.0))
    assert repr(harmonav.ellipse(p, p)) == repr(harmonav.ellipse(ref, ref))
    a = harmonav.Field(BOUNDARY, OBSTACLES, p).eval(PTS)[0]
    np.testing.assert_array_equal(a, harmonav.Field(BOUNDARY, OBSTACLES, ref).eval(PTS)[0])


def test_polygon_vertices_accept_every_array_like():
    square = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], dtype=np.float64)
    ref = harmonav.polygon(square, 0.1).outline(64)
    assert ref.shape == (64, 2)
    for form, vs in forms(square).items():
        np.testing.assert_array_equal(harmonav.polygon(vs, 0.1).outline(64), ref, err_msg=form)


def test_empty_batches_give_empty_results(field):
    for empty in ([], np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int32)):
        theta, grad = field.eval(empty)
        assert theta.shape == (0,) and grad.shape == (0, 2)
        assert field.free(empty).shape == (0,)


@pytest.mark.parametrize(
    "call, error, words",
    [
        # The wrong row length, a ragged list: ValueError naming the argument and the shape.
        (lambda f: f.eval(np.zeros((4, 3))), ValueError, ["points_xy", "(N, 2)", "(4, 3)"]),
        (lambda f: f.eval([[1, 2], [3]]), ValueError, ["points_xy"]),
        (lambda f: f.free([[1, 2, 3]]), ValueError, ["points_xy", "(1, 3)"]),
        (lambda f: OBSTACLES[0].signed_distance([[1, 2, 3]]), ValueError, ["points_xy", "(1, 3)"]),
        (lambda f: harmonav.polygon([[0, 0, 0], [1, 0, 0], [0, 1, 0]], 0.1), ValueError, ["vertices", "(3, 3)"]),
        (lambda f: harmonav.circle([1, 2, 3], 1.0), ValueError, ["center", "[x, y]", "got 3"]),
        (lambda f: OBSTACLES[0].contains([1.0]), ValueError, ["point_xy", "got 1"]),
        # The wrong number of dimensions, or not real numbers: TypeError naming the argument.
        (lambda f: f.eval(np.zeros(4)), TypeError, ["points_xy", "(N, 2)", "(4,)"]),
        (lambda f: f.eval(np.zeros((2, 2, 2))), TypeError, ["points_xy", "(2, 2, 2)"]),
        (lambda f: f.eval([1.0, 2.0]), TypeError, ["points_xy", "one point"]),
        (lambda f: f.eval(3.0), TypeError, ["points_xy"]),
        (lambda f: f.eval([["a", "b"]]), TypeError, ["points_xy", "real numbers"]),
        (lambda f: f.eval([[True, False]]), TypeError, ["points_xy", "bool"]),
        (lambda f: f.eval([[1j, 2]]), TypeError, ["points_xy", "complex"]),
        (lambda f: f.eval([[object(), 1.0]]), TypeError, ["points_xy"]),
        (lambda f: f.eval(None), TypeError, ["points_xy"]),
        (lambda f: OBSTACLES[0].signed_distance("xy"), TypeError, ["points_xy"]),
        (lambda f: harmonav.Navigator(BOUNDARY, GOAL).command([[0, 0]]), TypeError, ["x", "(1, 2)"]),
        (lambda f: harmonav.Navigator(BOUNDARY, GOAL).command([0, 0], "v"), TypeError, ["v"]),
        (lambda f: harmonav.Field(BOUNDARY, [], ["3", 0]), TypeError, ["goal"]),
        (lambda f: harmonav.ellipse([0, 0], 1.0), TypeError, ["semi_axes"]),
        # Non-finite single points are refused; non-finite rows of a batch give NaN (test_field).
        (lambda f: harmonav.Navigator(BOUNDARY, [np.nan, 0]), ValueError, ["goal", "finite"]),
        (lambda f: OBSTACLES[0].signed_distance(np.array([np.inf, 0])), ValueError, ["point", "finite"]),
    ],
)
def test_bad_array_likes_raise_errors_naming_the_argument(field, call, error, words):
    with pytest.raises(error) as err:
        call(field)
    for w in words:
        assert w in str(err.value), str(err.value)

"""Refused input: ValueError with a message naming the parameter (the library's own message for
what the library refuses), TypeError for an option of the wrong Python type."""
import numpy as np
import pytest

import ppcr
from support import blob

TARGET = blob(2000, seed=3)


def register(source=TARGET, target=TARGET, **options):
    options.setdefault("radius", 0.1)
    return ppcr.register(source, target, **options)


@pytest.mark.parametrize("bad, words", [
    (np.zeros((10, 2)), ["shape (N, 3)", "(10, 2)"]),
    (np.zeros((10, 4)), ["shape (N, 3)", "(10, 4)"]),
    (np.zeros(30), ["shape (N, 3)", "(30,)"]),
    (np.zeros((2, 5, 3)), ["shape (N, 3)", "(2, 5, 3)"]),
    (np.array([["a", "b", "c"]] * 5), ["real numbers", "dtype"]),
    (np.array([[1 + 2j, 0, 0]] * 5), ["real numbers", "complex"]),
    (np.ones((5, 3), dtype=bool), ["real numbers", "bool"]),
    (np.array([[object()] * 3] * 5), ["real numbers", "object"]),
    ([[1, 2, 3], [4, 5]], ["array"]),
    (None, ["None"]),
    ("points.ply", ["real numbers"]),
])
@pytest.mark.parametrize("which", ["source", "target"])
def test_bad_arrays(bad, words, which):
    with pytest.raises(ValueError) as error:
        register(**{which: bad})
    message = str(error.value)
    assert message.startswith(which + ": "), message
    for word in words:
        assert word in message, message


@pytest.mark.parametrize("which", ["source", "target"])
def test_nan_only_and_empty_clouds_refused_by_the_library(which):
    for cloud, dropped in [(np.full((50, 3), np.nan), 50), (np.zeros((0, 3)), 0)]:
        with pytest.raises(ValueError) as error:
            register(**{which: cloud})
        # The library's message (cloud_preparation.cpp), naming the cloud and what it lacks.
        assert str(error.value).startswith(
            f"{which} has 0 usable point(s) (of {len(cloud)}, {dropped} non-finite"), error.value


@pytest.mark.parametrize("options, message", [
    (dict(radius=-1), "radius must be > 0, or 0 for automatic, got -1"),
    (dict(radius=float("nan")), "radius must be > 0, or 0 for automatic, got nan"),
    (dict(max_neighbours=0), "max_neighbours must be in [1, 1024], got 0"),
    (dict(dof=0), "dof must be > 0, got 0"),
    (dict(source_voxel=-0.5), "source_voxel must be >= 0 or kAutomaticVoxel (-1), got -0.5"),
    (dict(num_threads=0), "num_threads must be in [1, 1024], got 0"),
    (dict(plane_epsilon=2), "expert.plane_epsilon must be in (0, 1], got 2"),
    (dict(normal_neighbours=3), "expert.normal_neighbours must be in [5, 64], got 3"),
    (dict(scale_mode="fixed"), "expert.scale (fixed scale) must be > 0, got 0"),
])
def test_options_refused_by_the_library(options, message):
    with pytest.raises(ValueError) as error:
        register(**options)
    assert str(error.value).startswith(message), error.value


@pytest.mark.parametrize("options, words", [
    (dict(error_model="planar"), ["error_model", "'plane' or 'point'", "'planar'"]),
    (dict(scale_mode="EM"), ["scale_mode", "'em', 'raw' or 'fixed'"]),
    (dict(criteria="cost-drop"), ["criteria", "'cost-drop'"]),
    (dict(criteria=["fixed", "never"]), ["criteria", "'never'"]),
    (dict(max_iterations=2 ** 40), ["max_iterations", "does not fit"]),
])
def test_bad_option_values(options, words):
    with pytest.raises(ValueError) as error:
        register(**options)
    for word in words:
        assert word in str(error.value), error.value


@pytest.mark.parametrize("options, words", [
    (dict(radius="0.1"), ["radius", "a number", "str"]),
    (dict(radius=True), ["radius", "a number", "bool"]),
    (dict(max_neighbours=6.0), ["max_neighbours", "an integer", "float"]),
    (dict(source_normals=1), ["source_normals", "True or False", "int"]),
    (dict(error_model=1), ["error_model", "int"]),
    (dict(criteria=3), ["criteria", "int"]),
    (dict(radiuss=0.1), ["unexpected keyword argument 'radiuss'"]),
    (dict(on_iteration=5), ["on_iteration", "callable"]),
])
def test_bad_option_types(options, words):
    with pytest.raises(TypeError) as error:
        register(**options)
    for word in words:
        assert word in str(error.value), error.value


def test_numpy_scalars_accepted_as_options():
    r = register(radius=np.float32(0.1), max_neighbours=np.int64(6), source_normals=np.bool_(True))
    assert r.converged


@pytest.mark.parametrize("initial, words", [
    (np.eye(3), ["initial", "shape (4, 4)", "(3, 3)"]),
    (np.diag([2.0, 1, 1, 1]), ["initial", "not a rigid transform"]),
    (np.array([[1.0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]),
     ["initial", "not a rigid transform"]),
    (np.full((4, 4), np.nan), ["the initial guess has non-finite entries"]),  # the library's
])
def test_bad_initial(initial, words):
    with pytest.raises(ValueError) as error:
        register(initial=initial)
    for word in words:
        assert word in str(error.value), error.value


def test_no_overlap_is_a_failed_result_not_an_error():
    """A pair with no overlap is a result a loop can test (as Open3D's fitness 0), not the
    ValueError of a wrong argument."""
    far = TARGET + [100.0, 0, 0]
    r = register(source=far)
    assert r.status == "no_correspondences"
    assert "radius" in r.status_message
    assert r.quality == "failed"
    assert r.fitness == 0.0
    assert r.matched_source_points == 0
    np.testing.assert_array_equal(r.transformation, np.eye(4))  # the initial guess
    registration = ppcr.Registration()
    registration.set_target(TARGET)
    assert registration.align(far).status == "no_correspondences"
    ok = register()
    assert ok.status == "ok" and ok.status_message == ""

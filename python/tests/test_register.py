"""ppcr.register: the same answer as ppcr_cli on the real bunny pair, any dtype and layout, a
known transform recovered, the result's fields, the trace and the per-iteration callback."""
import json
import subprocess

import numpy as np
import pytest

import ppcr
from support import blob, read_ply_xyz, rigid, rotation, transform

# The README's bunny example (ppcr_cli's flags, the same options here).
BUNNY_OPTIONS = dict(radius=0.02, source_voxel=0.002, target_voxel=0.002)
BUNNY_FLAGS = ["--radius", "0.02", "--source-voxel", "0.002", "--target-voxel", "0.002"]


def rotation_error_deg(A, B):
    """Angle of A^-1 B's rotation, degrees."""
    R = A[:3, :3].T @ B[:3, :3]
    return np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1.0, 1.0)))


@pytest.fixture(scope="module")
def bunny(data_dir):
    folder = data_dir / "bunny"
    if not (folder / "bun045.ply").is_file() or not (folder / "bun000.ply").is_file():
        pytest.fail(f"bunny scans not found in {folder}", pytrace=False)
    return folder / "bun045.ply", folder / "bun000.ply"


@pytest.fixture(scope="module")
def cli_bunny(bunny, cli):
    """ppcr_cli's result on the bunny pair (its JSON: the transform with 17 digits)."""
    source, target = bunny
    out = subprocess.run([cli, str(source), str(target), *BUNNY_FLAGS, "--json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def test_bunny_from_numpy_matches_cli(bunny, cli_bunny):
    source, target = (read_ply_xyz(path) for path in bunny)  # float32, as the files hold them
    cli_T = np.array(cli_bunny["transform"])
    for dtype in (np.float64, np.float32):
        r = ppcr.register(source.astype(dtype), target.astype(dtype), **BUNNY_OPTIONS)
        assert np.abs(r.transformation - cli_T).max() <= 1e-9, dtype
        assert r.converged == cli_bunny["converged"]
        assert r.stop_reason == cli_bunny["stop_reason"]
        assert r.iterations == cli_bunny["iterations"]
        assert r.fitness == pytest.approx(cli_bunny["fitness"], abs=1e-12)
        assert r.inlier_rmse == pytest.approx(cli_bunny["inlier_rmse"], abs=1e-12)
        assert r.overlap == pytest.approx(cli_bunny["overlap"], abs=1e-12)
        assert r.close_fraction == pytest.approx(cli_bunny["close_fraction"], abs=1e-12)
        assert r.target_spacing == pytest.approx(cli_bunny["target_spacing"], rel=1e-12)
        assert (r.quality, r.quality_reason) == (cli_bunny["quality"],
                                                 cli_bunny["quality_reason"])
        assert (r.source_points, r.target_points) == (cli_bunny["source_points"],
                                                      cli_bunny["target_points"])
        cli_covariance = np.array(cli_bunny["covariance"])
        np.testing.assert_allclose(r.covariance, cli_covariance, rtol=1e-6,
                                   atol=1e-9 * np.abs(cli_covariance).max())


def test_covariance_one_sigma_as_docs_python_md(bunny):
    """docs/PYTHON.md's worked example: 1-sigma rotation and translation from the covariance."""
    source, target = (ppcr.read_point_cloud(path) for path in bunny)
    r = ppcr.register(source, target, **BUNNY_OPTIONS)
    C = r.covariance
    assert C.shape == (6, 6) and C.dtype == np.float64 and np.array_equal(C, C.T)
    assert np.linalg.eigvalsh(C).min() > 0
    sigma_rotation_deg = np.degrees(np.sqrt(np.linalg.eigvalsh(C[:3, :3]).max()))
    sigma_translation = np.sqrt(np.linalg.eigvalsh(C[3:, 3:]).max())
    # The figures docs/PYTHON.md prints (its error against the pair's truth: 0.048 deg, 4.9e-05 m).
    assert f"{sigma_rotation_deg:.2g} deg, {sigma_translation:.2g} m" == "0.036 deg, 6.5e-05 m"


def test_bunny_read_by_ppcr_matches_cli(bunny, cli_bunny):
    source, target = (ppcr.read_point_cloud(path) for path in bunny)
    r = ppcr.register(source, target, **BUNNY_OPTIONS)
    assert np.abs(r.transformation - np.array(cli_bunny["transform"])).max() <= 1e-9


def test_bunny_close_to_ground_truth(bunny, data_dir):
    source, target = (ppcr.read_point_cloud(path) for path in bunny)
    gt = np.loadtxt(data_dir / "bunny" / "bun045_gt.txt")
    r = ppcr.register(source, target, **BUNNY_OPTIONS)
    assert r.converged
    assert rotation_error_deg(r.transformation, gt) < 1.0
    assert np.linalg.norm(r.transformation[:3, 3] - gt[:3, 3]) < 0.002


@pytest.fixture(scope="module")
def pair():
    """Two samplings of one surface, the source moved by a known transform: target = T source."""
    T = rigid(rotation([0.3, -0.2, 1.0], 12.0), [0.04, -0.03, 0.02])
    target = blob(6000, seed=1)
    source = transform(np.linalg.inv(T), blob(5000, seed=2))
    return source, target, T


def test_known_transform_recovered(pair):
    source, target, T = pair
    r = ppcr.register(source, target, radius=0.1)
    assert r.converged, r
    assert rotation_error_deg(r.transformation, T) < 0.05
    assert np.linalg.norm(r.transformation[:3, 3] - T[:3, 3]) < 1e-3
    # The result maps source into target: the moved source lies on the target's surface.
    moved = transform(r.transformation, source)
    assert np.sqrt(np.mean(np.sum((moved - transform(T, source)) ** 2, axis=1))) < 1e-3
    assert r.fitness > 0.9 and 0 < r.inlier_rmse < 0.02  # about the sampling spacing
    assert r.quality == "good" and r.quality_reason == ""


def test_initial_guess(pair):
    source, target, T = pair
    # Started at the answer, it stays there; started elsewhere, it converges to the same pose.
    near = ppcr.register(source, target, radius=0.1, initial=T)
    assert rotation_error_deg(near.transformation, T) < 0.05
    guess = rigid(rotation([0, 0, 1], 5.0), [0.01, 0, 0])
    far = ppcr.register(source, target, radius=0.1, initial=guess)
    assert rotation_error_deg(far.transformation, T) < 0.05


def test_dtypes_and_layouts_give_the_float64_answer(pair):
    source, target, _ = pair
    reference = ppcr.register(source, target, radius=0.1).transformation
    # float32 clouds are converted exactly: compare with their own float64 copy.
    s32, t32 = source.astype(np.float32), target.astype(np.float32)
    r32 = ppcr.register(s32, t32, radius=0.1).transformation
    assert np.array_equal(r32, ppcr.register(s32.astype(np.float64), t32.astype(np.float64),
                                             radius=0.1).transformation)
    assert rotation_error_deg(r32, reference) < 0.01
    # Non-contiguous (Fortran order, a strided view) and a list of lists: the same points.
    wide = np.zeros((len(source), 6))
    wide[:, ::2] = source
    non_contiguous = [np.asfortranarray(source), wide[:, ::2]]
    assert not any(variant.flags.c_contiguous for variant in non_contiguous)
    for variant in non_contiguous + [source.tolist()]:
        assert np.array_equal(ppcr.register(variant, target, radius=0.1).transformation,
                              reference)
    # Integer clouds (here millimetres) are converted to float64 exactly.
    s_mm, t_mm = np.round(source * 1000).astype(np.int32), np.round(target * 1000).astype(np.int64)
    assert np.array_equal(ppcr.register(s_mm, t_mm, radius=100).transformation,
                          ppcr.register(s_mm.astype(float), t_mm.astype(float),
                                        radius=100).transformation)


def test_result_fields_and_history(pair):
    source, target, _ = pair
    r = ppcr.register(source, target, radius=0.1)
    assert r.transformation.shape == (4, 4) and r.transformation.dtype == np.float64
    assert np.array_equal(r.transformation[3], [0, 0, 0, 1])
    assert isinstance(r.converged, bool) and r.stop_reason == "cost_drop"
    assert r.iterations >= 1 and r.time_ms > 0 and r.information.shape == (6, 6)
    assert (r.source_points, r.target_points) == (len(source), len(target))
    assert 0 < r.overlap <= 1 and r.degenerate_directions == 0  # a closed surface
    h = r.history
    assert set(h) == {"iteration", "coarse", "successful_steps", "unsuccessful_steps",
                      "initial_cost", "final_cost", "cost_drop", "mse_prev", "scale",
                      "correspondences", "matched_source_points", "transformation", "time_ms"}
    assert all(len(column) == r.iterations for column in h.values())
    assert np.array_equal(h["iteration"], np.arange(1, r.iterations + 1))
    assert h["coarse"].dtype == bool and h["transformation"].shape == (r.iterations, 4, 4)
    assert np.array_equal(h["transformation"][-1], r.transformation)
    assert "converged" in repr(r) and "cost_drop" in repr(r)
    quiet = ppcr.register(source, target, radius=0.1, record_history=False)
    assert all(len(column) == 0 for column in quiet.history.values())
    assert np.array_equal(quiet.transformation, r.transformation)


def test_options_reach_the_library(pair):
    source, target, _ = pair
    fixed = ppcr.register(source, target, radius=0.1, criteria="fixed", fixed_iterations=7)
    assert (fixed.iterations, fixed.stop_reason) == (7, "fixed_iterations")
    capped = ppcr.register(source, target, radius=0.1, max_iterations=3)
    assert (capped.iterations, capped.stop_reason, capped.converged) == (3, "max_iterations",
                                                                         False)
    both = ppcr.register(source, target, radius=0.1, criteria=["mse_prev", "cost_drop"])
    assert both.converged
    point = ppcr.register(source, target, radius=0.1, error_model="point")
    assert point.degenerate_directions == -1  # the point model does not assess it
    one = ppcr.register(source, target, radius=0.1, num_threads=1)
    two = ppcr.register(source, target, radius=0.1, num_threads=2)
    assert np.array_equal(one.transformation, two.transformation)
    voxel = ppcr.register(source, target, radius=0.1, source_voxel=0.05, target_voxel=0.05)
    assert voxel.source_points < len(source) and voxel.target_points < len(target)


def test_non_finite_points_dropped_and_counted(pair):
    source, target, _ = pair
    holes = source.copy()
    holes[::10] = np.nan
    r = ppcr.register(holes, target, radius=0.1)
    assert r.source_non_finite == len(source[::10])
    assert r.source_points == len(source) - r.source_non_finite


def test_duplicates_registered_once_and_counted(pair):
    source, target, _ = pair
    copies = np.vstack([source, source[::4], np.zeros((200, 3)), np.zeros((1, 3))])
    r = ppcr.register(copies, target, radius=0.1)
    assert r.source_duplicates == len(source[::4]) + 200
    assert r.source_points == len(source) + 1
    assert r.target_duplicates == 0


def test_on_iteration(pair):
    source, target, _ = pair
    seen = []
    r = ppcr.register(source, target, radius=0.1, on_iteration=seen.append)  # returns None
    assert [record["iteration"] for record in seen] == list(range(1, r.iterations + 1))
    assert np.array_equal(seen[-1]["transformation"], r.transformation)
    assert seen[-1]["final_cost"] == r.history["final_cost"][-1]
    stopped = ppcr.register(source, target, radius=0.1,
                            on_iteration=lambda record: record["iteration"] < 2)
    assert (stopped.iterations, stopped.stop_reason, stopped.converged) == (2, "cancelled", False)

    class Stop(Exception):
        pass

    def raise_at_3(record):
        if record["iteration"] == 3:
            raise Stop("from the callback")

    with pytest.raises(Stop, match="from the callback"):
        ppcr.register(source, target, radius=0.1, on_iteration=raise_at_3)

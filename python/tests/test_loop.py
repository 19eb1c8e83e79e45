"""ppcr.Registration for loops (one target, many sources; scan to scan), and the helpers around
it: write_point_cloud, voxel_downsample, evaluate."""
import numpy as np
import pytest

import ppcr


def surface(n=41):
    """A wavy 1 m x 1 m surface (metres), as the README's example."""
    x, y = np.meshgrid(np.linspace(-0.5, 0.5, n), np.linspace(-0.5, 0.5, n))
    z = 0.1 * np.sin(4 * x) * np.cos(3 * y) + 0.05 * x * y
    return np.column_stack([x.ravel(), y.ravel(), z.ravel()])


def pose(angle, axis, t):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    T[:3, 3] = t
    return T


def moved(points, T):
    return points @ T[:3, :3].T + T[:3, 3]


def test_ten_sources_onto_one_target_equal_ten_one_shot_calls():
    target = surface()
    registration = ppcr.Registration(radius=0.1)
    registration.set_target(target)
    rng = np.random.default_rng(7)
    for i in range(10):
        T_true = pose(rng.uniform(0.02, 0.1), rng.normal(size=3), rng.uniform(-0.03, 0.03, 3))
        source = moved(target, np.linalg.inv(T_true))
        looped = registration.align(source)
        once = ppcr.register(source, target, radius=0.1)
        assert np.array_equal(looped.transformation, once.transformation), i
        assert looped.iterations == once.iterations, i
        errors = ppcr.evaluate(source, looped.transformation, T_true)
        assert errors["rotation_error_deg"] < 1e-3 and errors["translation_error"] < 1e-4, errors


def test_scan_to_scan_equals_a_target_made_from_the_source():
    scans = [moved(surface(), pose(0.03 * k, [0, 0, 1], [0.01 * k, 0, 0])) for k in range(3)]
    chained = ppcr.Registration(radius=0.1)
    chained.set_target(scans[0])
    chained.align(scans[1])
    chained.set_target_to_source()  # scans[1] is the target now
    fresh = ppcr.Registration(radius=0.1)
    fresh.set_target(scans[1])
    a, b = chained.align(scans[2]), fresh.align(scans[2])
    assert np.allclose(a.transformation, b.transformation, rtol=0, atol=1e-12)


def test_registration_errors():
    registration = ppcr.Registration(radius=0.1)
    with pytest.raises(ValueError):
        registration.align(surface())  # no target yet
    with pytest.raises(ValueError, match="radius"):
        ppcr.Registration(radius=-1).set_target(surface())
    with pytest.raises(ValueError, match="target"):
        registration.set_target(np.zeros((5, 2)))


def test_write_read_voxel_evaluate(tmp_path):
    points = surface()
    for name in ("s.ply", "s.pcd", "s.xyz"):
        ppcr.write_point_cloud(tmp_path / name, points)
        assert np.array_equal(ppcr.read_point_cloud(tmp_path / name), points), name
    ppcr.write_point_cloud(str(tmp_path / "s.bin"), points)
    assert np.array_equal(ppcr.read_point_cloud(tmp_path / "s.bin"),
                          points.astype(np.float32).astype(np.float64))
    with pytest.raises(FileNotFoundError):
        ppcr.write_point_cloud(tmp_path / "no" / "dir" / "s.ply", points)
    with pytest.raises(ValueError, match="extension"):
        ppcr.write_point_cloud(tmp_path / "s.las", points)
    # Against numpy: one centroid per occupied cell of the grid anchored at the lower corner.
    filtered = ppcr.voxel_downsample(points, 0.1)
    keys = np.floor((points - points.min(axis=0)) * (1 / 0.1))
    cells, index = np.unique(keys, axis=0, return_inverse=True)
    index = index.ravel()
    centroids = np.zeros((len(cells), 3))
    np.add.at(centroids, index, points)
    centroids /= np.bincount(index)[:, None]
    assert filtered.shape == centroids.shape
    assert np.allclose(np.sort(filtered, axis=0), np.sort(centroids, axis=0), rtol=0, atol=1e-12)
    with pytest.raises(ValueError):
        ppcr.voxel_downsample(points, -1.0)
    T = pose(0.1, [0, 0, 1], [0.2, 0, 0])
    e = ppcr.evaluate(points, T, np.eye(4))
    assert e["rotation_error_deg"] == pytest.approx(np.degrees(0.1))
    assert e["translation_error"] == pytest.approx(0.2)
    assert e["mse"] > 0 and e["benchmark_error"] > 0

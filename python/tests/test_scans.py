"""Scans as sensors write them: a TUM depth image (16-bit PNG) read with the camera's intrinsics,
and a KITTI .bin frame; each registers against a moved copy of itself to 1e-4 degrees."""
import numpy as np
import pytest

import ppcr
from support import rigid, rotation, transform

FREIBURG1 = (517.3, 516.5, 318.6, 255.3)  # ../shared/data/tum_fr1_rpy/README.md


def rotation_error_deg(A, B):
    R = A[:3, :3].T @ B[:3, :3]
    return np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1.0, 1.0)))


@pytest.fixture(scope="module")
def depth_frame(data_dir):
    frames = sorted((data_dir / "tum_fr1_rpy" / "depth").glob("*.png"))
    if len(frames) != 100:
        pytest.fail(f"TUM depth frames not found in {data_dir / 'tum_fr1_rpy'}", pytrace=False)
    return frames[0]


def test_depth_image_back_projected_through_the_intrinsics(depth_frame):
    default = ppcr.read_point_cloud(depth_frame)  # TUM's default camera, depth / 5000
    points = ppcr.read_point_cloud(depth_frame, depth_intrinsics=FREIBURG1)
    assert points.shape == default.shape and 0.65 < len(points) / (640 * 480) < 0.85
    assert np.array_equal(points[:, 2], default[:, 2])
    # Each point projects back to a pixel centre of a 640 x 480 image.
    fx, fy, cx, cy = FREIBURG1
    u = points[:, 0] * fx / points[:, 2] + cx
    v = points[:, 1] * fy / points[:, 2] + cy
    assert np.allclose(u, np.round(u), atol=1e-6) and np.allclose(v, np.round(v), atol=1e-6)
    assert u.min() >= 0 and u.max() <= 639 and v.min() >= 0 and v.max() <= 479
    millimetres = ppcr.read_point_cloud(depth_frame, depth_intrinsics=FREIBURG1, depth_scale=1000)
    assert np.allclose(millimetres, points * 5.0, rtol=1e-12)


def test_depth_camera_arguments_checked(depth_frame):
    with pytest.raises(ValueError, match="4 numbers"):
        ppcr.read_point_cloud(depth_frame, depth_intrinsics=(517.3, 516.5, 318.6))
    with pytest.raises(TypeError, match="depth_intrinsics"):
        ppcr.read_point_cloud(depth_frame, depth_intrinsics="517.3")
    with pytest.raises(ValueError, match="fx = -1"):
        ppcr.read_point_cloud(depth_frame, depth_intrinsics=(-1, 516.5, 318.6, 255.3))
    with pytest.raises(ValueError, match="depth_scale = 0"):
        ppcr.read_point_cloud(depth_frame, depth_scale=0)
    for wrong in ("1000", True):
        with pytest.raises(TypeError, match="depth_scale"):
            ppcr.read_point_cloud(depth_frame, depth_scale=wrong)
    # numpy numbers are numbers, as for every option
    assert len(ppcr.read_point_cloud(depth_frame, depth_scale=np.float32(5000))) > 0


def test_depth_frame_registers_against_a_moved_copy(depth_frame):
    target = ppcr.read_point_cloud(depth_frame, depth_intrinsics=FREIBURG1)
    T = rigid(rotation([0.3, -1.0, 0.2], 2.9), [0.02, -0.01, 0.03])  # source -> target
    source = transform(np.linalg.inv(T), target[::4])  # every 4th point: the test's time
    # The paper's point model: its optimum is the exact copy (the plane model's lies ~1e-3
    # degrees off on quantised depth, tests/io/test_depth_png_real.cpp).
    r = ppcr.register(source, target, error_model="point")
    assert r.status == "ok" and r.quality == "good"
    assert rotation_error_deg(r.transformation, T) < 1e-4
    assert np.linalg.norm(r.transformation[:3, 3] - T[:3, 3]) < 1e-5


def test_kitti_frame_registers_against_a_moved_copy(tmp_path):
    # A street-like frame (ground, two walls, a pole), written and read as a KITTI .bin.
    xs = np.arange(-20, 20.01, 0.25)
    ground = np.array([[x, y, -1.7 + 0.01 * np.sin(x)] for x in xs for y in np.arange(-8, 8.01, 0.25)])
    walls = np.array([p for x in xs for z in np.arange(-1.7, 2.01, 0.25)
                      for p in ([x, 8 + 0.3 * np.sin(0.5 * x), z], [x, -8, z + 0.05 * x])])
    pole = np.array([[5.0, 2.0, z] for z in np.arange(-1.7, 3.0, 0.1)])
    ppcr.write_point_cloud(tmp_path / "000000.bin", np.vstack([ground, walls, pole]))
    target = ppcr.read_point_cloud(tmp_path / "000000.bin")
    T = rigid(rotation([0.1, 0.2, 1.0], 2.9), [0.4, -0.2, 0.05])
    r = ppcr.register(transform(np.linalg.inv(T), target), target, radius=1.0)
    assert r.status == "ok"
    assert rotation_error_deg(r.transformation, T) < 1e-4
    assert np.linalg.norm(r.transformation[:3, 3] - T[:3, 3]) < 1e-4


def test_automatic_leaf_reported(tmp_path):
    # A 12,880-point street frame: the automatic leaf keeps about 10,000 points of each cloud
    # and reports the leaves; 0 (the default) filters nothing.
    xs = np.arange(-20, 20.01, 0.25)
    frame = np.array([[x, y, -1.7 + 0.01 * np.sin(x)] for x in xs for y in np.arange(-8, 8.01, 0.25)]
                     + [[x, 8 + 0.3 * np.sin(0.5 * x), z] for x in xs for z in np.arange(-1.7, 2.01, 0.25)])
    T = rigid(rotation([0.1, 0.2, 1.0], 2.0), [0.3, -0.2, 0.05])
    source = transform(np.linalg.inv(T), frame)
    auto = ppcr.register(source, frame, radius=1.0, source_voxel=ppcr.AUTOMATIC_VOXEL,
                         target_voxel=ppcr.AUTOMATIC_VOXEL)
    assert auto.status == "ok" and auto.source_voxel > 0 and auto.target_voxel > 0
    assert abs(auto.source_points / 10000 - 1) <= 0.15
    assert rotation_error_deg(auto.transformation, T) < 0.05
    plain = ppcr.register(source, frame, radius=1.0)
    assert plain.source_voxel == 0 and plain.source_points > 12000  # unfiltered

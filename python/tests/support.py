"""Helpers of the Python tests: an independent PLY reader and rigid-motion arithmetic."""
import pathlib

import numpy as np


def read_ply_xyz(path):
    """The x y z of a binary little-endian PLY whose vertices hold only float x, y, z (the shared
    scans), read with numpy alone: an input independent of ppcr's readers. float32, (N, 3)."""
    data = pathlib.Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert "format binary_little_endian 1.0" in header, header
    properties = [line.split()[1:] for line in header if line.startswith("property")]
    assert properties == [["float", "x"], ["float", "y"], ["float", "z"]], properties
    count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    return np.frombuffer(data, dtype="<f4", count=3 * count, offset=end).reshape(count, 3)


def rotation(axis, degrees):
    """Rotation matrix about a unit axis (Rodrigues' formula)."""
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    angle = np.radians(degrees)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def rigid(R, t):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = t
    return T


def transform(T, points):
    return points @ T[:3, :3].T + T[:3, 3]


def blob(samples, seed):
    """A closed, bumpy, asymmetric surface about 1 m across (metres), which constrains every
    rigid motion: random samples (a different sampling per seed) of r(direction)."""
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(samples, 3))
    v /= np.linalg.norm(v, axis=1)[:, None]
    x, y, z = v.T
    r = 0.5 * (1 + 0.15 * np.sin(3 * x + 1) * np.cos(2 * y) + 0.1 * z * x + 0.08 * np.cos(5 * z))
    return v * r[:, None]

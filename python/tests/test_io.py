"""ppcr.read_point_cloud: every fixture of ../shared/data/io against its MANIFEST.json (count,
first point, centroid), and the readers' errors: OSError for a file that cannot be read,
ValueError for its content."""
import json
import pathlib

import numpy as np
import pytest

import ppcr


@pytest.fixture(scope="module")
def manifest(data_dir):
    path = data_dir / "io" / "MANIFEST.json"
    if not path.is_file():
        pytest.fail(f"reader fixtures not found: {path}", pytrace=False)
    return path.parent, json.loads(path.read_text())


def test_fixtures_match_manifest(manifest):
    folder, expected = manifest
    tolerance = expected.get("tolerance", 1e-6)
    assert expected["files"]
    for name, facts in expected["files"].items():
        points = ppcr.read_point_cloud(folder / name)  # a pathlib.Path
        assert points.shape == (facts["points"], 3) and points.dtype == np.float64, name
        assert np.allclose(points[0], facts["first"], rtol=0, atol=tolerance), name
        if "centroid" in facts:
            assert np.allclose(points.mean(axis=0), facts["centroid"], rtol=0,
                               atol=tolerance), name
    # A str path reads the same.
    first = next(iter(expected["files"]))
    assert np.array_equal(ppcr.read_point_cloud(str(folder / first)),
                          ppcr.read_point_cloud(folder / first))


def test_round_trip_of_a_text_cloud(tmp_path):
    points = np.random.default_rng(5).normal(size=(100, 3))
    path = tmp_path / "cloud.xyz"
    np.savetxt(path, points, fmt="%.17g")
    assert np.array_equal(ppcr.read_point_cloud(path), points)


def test_reader_errors(tmp_path):
    missing = tmp_path / "none.ply"
    with pytest.raises(FileNotFoundError) as error:
        ppcr.read_point_cloud(missing)
    assert str(error.value).startswith(f"{missing}: cannot open"), error.value
    with pytest.raises(IsADirectoryError) as error:
        ppcr.read_point_cloud(tmp_path)
    assert str(tmp_path) in str(error.value), error.value
    (tmp_path / "empty.ply").write_bytes(b"")
    with pytest.raises(ValueError) as error:
        ppcr.read_point_cloud(tmp_path / "empty.ply")
    assert "empty" in str(error.value), error.value
    bad = tmp_path / "bad.xyz"
    bad.write_text("1 2 3\n4 5 x\n")
    with pytest.raises(ValueError) as error:
        ppcr.read_point_cloud(bad)
    assert str(bad) in str(error.value) and "line 2" in str(error.value), error.value
    with pytest.raises(TypeError):
        ppcr.read_point_cloud(3)

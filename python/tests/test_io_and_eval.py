"""read_point_cloud / write_point_cloud, synthesize, compare, and the stages."""
import numpy as np
import pytest

import detexture
from conftest import run_cli


def test_round_trip_keeps_extras_in_their_types(work):
    P = np.array([[0.0, 0.0, 0.0], [1.0, 0.5, 0.25], [2.0, -1.0, 3.5]])
    N = np.array([[0.0, 0.0, 2.0], [0.0, 1.0, 0.0], [np.nan, 0.0, 0.0]])
    extras = {"red": np.array([0, 128, 255], dtype=np.uint8),
              "intensity": np.array([0.5, 1.5, -2.0], dtype=np.float32),
              "label": np.array([-7, 0, 70000], dtype=np.int32)}
    cloud = detexture.PointCloud(P, N, extras)
    # Normals are normalized as a file's would be; a NaN one becomes zero.
    assert np.array_equal(cloud.normals, [[0, 0, 1], [0, 1, 0], [0, 0, 0]])
    for encoding in ("binary", "ascii", "binary-big-endian"):
        path = work / f"round_{encoding}.ply"
        detexture.write_point_cloud(path, cloud, encoding=encoding)
        back = detexture.read_point_cloud(path)
        assert np.array_equal(back.positions, P)
        assert np.array_equal(back.normals, cloud.normals)
        assert list(back.extras) == ["red", "intensity", "label"]
        for name, values in extras.items():
            assert back.extras[name].dtype == values.dtype
            assert np.array_equal(back.extras[name], values)


def test_file_errors_are_oserror_with_the_cli_message(work):
    missing = work / "no_such_file.ply"
    r = run_cli(missing, "-o", work / "x.ply", check=False)
    assert r.returncode == 3
    with pytest.raises(OSError) as e:
        detexture.read_point_cloud(missing)
    assert "detexture: error: " + str(e.value) == r.stderr.strip()
    with pytest.raises(OSError, match="unknown|extension"):
        detexture.write_point_cloud(work / "x.unknown", detexture.PointCloud(np.zeros((1, 3))))
    with pytest.raises(ValueError):
        detexture.read_point_cloud(missing, format="obj?")
    with pytest.raises(ValueError, match="int64"):
        detexture.PointCloud(np.zeros((2, 3)), extras={"x": np.zeros(2, dtype=np.int64)})


def test_synthesize_and_compare():
    s = detexture.synthesize(shape="plane", texture="none", points=500, ground_truth_points=500)
    assert s.positions.shape == (500, 3) and not s.is_texture.any()
    assert np.all(s.positions[:, 2] == 0.0)  # the plane z = 0, no texture
    same = detexture.compare(s.positions, s.normals, s.ground_truth_positions,
                             s.ground_truth_normals)
    assert same["dmax"] == 0.0 and same["normal_angle_mean_degrees"] == 0.0
    lifted = s.positions + [0.0, 0.0, 0.01]
    up = detexture.compare(lifted, None, s.ground_truth_positions, s.ground_truth_normals)
    assert up["signed_mean"] == pytest.approx(0.01, abs=1e-12)
    assert up["normal_angle_mean_degrees"] is None
    with pytest.raises(ValueError):
        detexture.synthesize(shape="hexagon")


def test_radius_neighborhoods_on_a_line():
    P = np.array([[0.0, 0, 0], [1.0, 0, 0], [3.0, 0, 0]])
    R = detexture.radius_neighborhoods(P, 1.5)
    assert len(R) == 3
    assert list(R[0]) == [0, 1] and list(R[1]) == [1, 0] and list(R[2]) == [2]
    assert list(R.offsets) == [0, 2, 4, 5]
    with pytest.raises(ValueError):
        detexture.radius_neighborhoods(P, -1.0)


def test_estimate_normals_of_a_plane():
    x, y = np.meshgrid(np.linspace(0, 1, 10), np.linspace(0, 1, 10))
    P = np.column_stack([x.ravel(), y.ravel(), np.zeros(100)])
    normals, variation, degenerate = detexture.estimate_normals(P, detexture.knn_neighborhoods(P, 8))
    assert degenerate == 0
    assert np.allclose(np.abs(normals[:, 2]), 1.0) and np.allclose(variation, 0.0)

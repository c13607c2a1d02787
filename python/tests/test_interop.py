"""The Open3D and laspy examples, run where those packages are installed."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

import pnf
from conftest import REPO, angles_deg, noisy_cube


def load_example(name: str):
    spec = importlib.util.spec_from_file_location(name, REPO / "python" / "examples" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_open3d_round_trip_without_copies():
    o3d = pytest.importorskip("open3d", reason="open3d is not installed (pip install open3d); interop not tested")
    example = load_example("open3d_interop")
    cloud, truth = example.noisy_box(points=6000)
    # Open3D's buffers are read in place.
    points_address = np.asarray(cloud.points).ctypes.data
    assert pnf._pnf._view_info(cloud.points)["data"] == points_address
    assert not pnf._pnf._view_info(cloud.normals)["copied"]
    before = example.mean_error_deg(np.asarray(cloud.normals), truth)
    expected = pnf.improve_normals(np.asarray(cloud.points).copy(), np.asarray(cloud.normals).copy(),
                                   backend="reference")
    normals_address = np.asarray(cloud.normals).ctypes.data
    example.improve_open3d_normals(cloud, backend="reference")
    assert isinstance(cloud, o3d.geometry.PointCloud)
    assert np.asarray(cloud.normals).ctypes.data == normals_address  # written in place
    np.testing.assert_array_equal(np.asarray(cloud.normals), expected)
    assert example.mean_error_deg(np.asarray(cloud.normals), truth) < 0.5 * before


def test_laspy_estimate_filter_and_extra_dimensions(tmp_path):
    laspy = pytest.importorskip("laspy", reason="laspy is not installed (pip install laspy); interop not tested")
    example = load_example("laspy_interop")
    points, _, truth = noisy_cube(20, normal_noise=0.0, position_noise=0.003)
    points = points * 10 + [500000.0, 4000000.0, 100.0]  # map-like coordinates, millimetre scale
    header = laspy.LasHeader(point_format=3, version="1.2")
    header.scales = [0.001, 0.001, 0.001]
    header.offsets = [500000.0, 4000000.0, 100.0]
    las = laspy.LasData(header)
    las.x, las.y, las.z = points[:, 0], points[:, 1], points[:, 2]
    las.intensity = np.arange(len(points), dtype=np.uint16)
    source, target = tmp_path / "scan.las", tmp_path / "scan_normals.las"
    las.write(source)

    normals = example.filter_las(str(source), str(target), k=12, backend="reference")
    out = laspy.read(target)
    assert len(out.points) == len(points)
    np.testing.assert_array_equal(np.asarray(out.intensity), np.arange(len(points)))  # kept
    written = np.column_stack([np.asarray(out[name]) for name in example.NORMAL_DIMENSIONS])
    assert written.dtype == np.float32
    np.testing.assert_allclose(written, normals, atol=1e-6)
    # On the faces, away from the edges, the normals are the cube's (up to their sign's rule).
    inner = (np.abs(np.abs((points - [500000.0, 4000000.0, 100.0]) / 10) - 1) < 1e-2).sum(axis=1) == 1
    assert np.median(angles_deg(np.abs(normals[inner]), np.abs(truth[inner]))) < 2.0

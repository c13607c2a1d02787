"""Bad input raises the Python exception its kind calls for, with pnf's message; never a crash."""

from __future__ import annotations

import numpy as np
import pytest

import pnf
from conftest import noisy_cube

P, N, _ = noisy_cube(6)


@pytest.mark.parametrize(
    "points, normals, match",
    [
        (P[:, :2], N, r"points must be an \(N, 3\) array, got shape \(216, 2\)"),
        (P.ravel(), N, r"points must be an \(N, 3\) array"),
        (P, N[:-1], "normals has 215 rows but points has 216"),
        (P.astype(complex), N, "points must hold real numbers"),
        (P.astype(object), N, "points must hold real numbers"),
        (np.array([["a", "b", "c"]]), N[:1], "points must hold real numbers"),
        ([[0, 0, 0], [1, 2]], N[:2], "points must be an"),
    ],
    ids=["two columns", "flat", "sizes", "complex", "object", "strings", "ragged"],
)
def test_bad_arrays_raise_value_error(points, normals, match):
    with pytest.raises(ValueError, match=match):
        pnf.improve_normals(points, normals, backend="reference")


def test_nan_names_the_vertex():
    points = P.copy()
    points[7, 1] = np.nan
    with pytest.raises(ValueError, match="7"):
        pnf.improve_normals(points, N, backend="reference")
    normals = N.copy()
    normals[5] = 0.0
    with pytest.raises(ValueError, match="5"):
        pnf.improve_normals(P, normals, backend="reference")


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"sigma_f": -1.0}, "sigma_f"),
        ({"sigma_g": float("nan")}, "sigma_g"),
        ({"iterations": -2}, "iterations"),
        ({"units": "metres"}, "units"),
        ({"backend": "cuda"}, "backend"),
        ({"auto": True, "sigma_f": 3.0}, "auto=True"),
        ({"progress": 42}, "progress must be callable"),
        ({"radii": np.ones(5)}, "radii has 5 rows"),
        ({"radii": -np.ones(216)}, "radius"),
    ],
)
def test_bad_parameters_raise_value_error(kwargs, match):
    kwargs.setdefault("backend", "reference")
    with pytest.raises(ValueError, match=match):
        pnf.improve_normals(P, N, **kwargs)


def test_a_device_that_is_not_there_raises_device_error():
    with pytest.raises(pnf.DeviceError, match="no-such-device-anywhere") as caught:
        pnf.improve_normals(P, N, device="no-such-device-anywhere")
    assert isinstance(caught.value, RuntimeError)


def test_file_errors(tmp_path):
    with pytest.raises(OSError, match="missing.ply"):
        pnf.read(tmp_path / "missing.ply")
    bad = tmp_path / "bad.ply"
    bad.write_text("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n")
    with pytest.raises(ValueError, match="bad.ply"):
        pnf.read(bad)
    with pytest.raises(ValueError, match="extension"):
        pnf.read(tmp_path / "cloud.obj")
    with pytest.raises(OSError):
        pnf.write(tmp_path / "no" / "such" / "folder" / "out.ply", P, N)
    with pytest.raises(TypeError):
        pnf.read(42)


def test_other_functions_raise_value_error():
    with pytest.raises(ValueError, match="k"):
        pnf.estimate_normals(P, k=1)
    with pytest.raises(ValueError, match="orient"):
        pnf.estimate_normals(P, orient="inward")
    with pytest.raises(ValueError):
        pnf.estimate_normals(P[:2])
    with pytest.raises(ValueError):
        pnf.choose_params(P[:5], N[:5])
    with pytest.raises(ValueError, match="width"):
        pnf.render(P, N, width=0)
    with pytest.raises(ValueError, match="mode"):
        pnf.render(P, N, mode="xray")
    with pytest.raises(ValueError):
        pnf.render(P, N, mode="error")  # needs reference normals

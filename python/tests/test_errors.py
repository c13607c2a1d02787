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


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: pnf.improve_normals(P, N, backend="reference", max_seconds="5"), "max_seconds must be a number"),
        (lambda: pnf.improve_normals(P, N, backend="reference", stop_change_deg=[1]), "stop_change_deg must be"),
        (lambda: pnf.improve_normals(P, N, backend="reference", sigma_f="4"), "sigma_f must be a number"),
        (lambda: pnf.improve_normals(P, N, backend="reference", mean_radius="1"), "mean_radius must be a number"),
        (lambda: pnf.estimate_normals(P, viewpoint=None), "viewpoint must be three numbers"),
        (lambda: pnf.render(P, N, light=(1, "a", 2)), "light must be a number"),
    ],
)
def test_arguments_of_the_wrong_type_raise_type_error_naming_them(call, match):
    # pybind11's own error named no argument and printed every one, the arrays in full.
    with pytest.raises(TypeError, match=match) as caught:
        call()
    assert len(str(caught.value)) < 200


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: pnf.estimate_normals(P, viewpoint=(0, 0)), "viewpoint must be three numbers, got 2"),
        (lambda: pnf.render(P, N, light=(1, 2)), "light must be three numbers, got 2"),
        (lambda: pnf.render(P, N, frame=((0, 0, 0),)), "frame must be"),
    ],
)
def test_vectors_of_the_wrong_length_raise_value_error_naming_them(call, match):
    with pytest.raises(ValueError, match=match):
        call()


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


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"iterations": 2.7}, r"^iterations must be a whole number, got 2\.7$"),
        ({"iterations": 10**10}, r"^iterations = 10000000000 is out of range \(-2147483648 to 2147483647\)$"),
        ({"iterations": "4"}, "iterations must be a whole number"),
        ({"mean_radius": 0}, "mean_radius = 0: must be finite and > 0"),
        ({"mean_radius": -1.5}, "mean_radius = -1.5"),
        ({"mean_radius": float("nan")}, "mean_radius = nan"),
    ],
)
def test_counts_and_mean_radius_get_a_short_clear_error(kwargs, match):
    # A count is a whole number that fits a C int (not silently truncated, not a TypeError that
    # prints the arrays); mean_radius <= 0 is an error, as the README says (None: from the data).
    with pytest.raises(ValueError, match=match) as caught:
        pnf.improve_normals(P, N, backend="reference", **kwargs)
    assert len(str(caught.value)) < 120


def test_a_whole_float_is_a_count_and_k_is_checked_too():
    np.testing.assert_array_equal(pnf.improve_normals(P, N, backend="reference", iterations=2.0),
                                  pnf.improve_normals(P, N, backend="reference", iterations=2))
    with pytest.raises(ValueError, match="k must be a whole number, got 7.5"):
        pnf.estimate_normals(P, k=7.5)


def test_options_are_keyword_only_after_the_data(tmp_path):
    # As improve_normals: the arrays (or the path) positional, everything else by name.
    with pytest.raises(TypeError):
        pnf.estimate_normals(P, 8)
    with pytest.raises(TypeError):
        pnf.choose_params(P, N, "cpu")
    pnf.write(tmp_path / "cloud.ply", P, N)
    with pytest.raises(TypeError):
        pnf.read(tmp_path / "cloud.ply", False)
    assert len(pnf.read(tmp_path / "cloud.ply", check_normals=False)) == len(P)

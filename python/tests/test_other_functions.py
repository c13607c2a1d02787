"""estimate_normals, choose_params, devices, render."""

from __future__ import annotations

import numpy as np

import pnf
from conftest import angles_deg, noisy_cube


def sphere(n: int = 2000, seed: int = 3) -> np.ndarray:
    # Fibonacci sphere: even, deterministic.
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    r = np.sqrt(1 - z * z)
    phi = np.pi * (1 + 5**0.5) * i
    return np.c_[r * np.cos(phi), r * np.sin(phi), z]


def test_estimate_normals_on_a_sphere_point_outward():
    points = sphere()
    for orient in ("mst", "outward"):
        normals = pnf.estimate_normals(points, k=12, orient=orient)
        assert normals.shape == points.shape and normals.dtype == np.float64
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-9)
        assert angles_deg(normals, points).max() < 5.0, orient
    inward = pnf.estimate_normals(points, orient="viewpoint", viewpoint=(0, 0, 0))
    assert (np.einsum("ij,ij->i", inward, points) < 0).all()


def test_estimate_k_counts_the_point_itself_as_pcl_and_open3d_do():
    # Each normal is the PCA normal of the k nearest points, the point itself included (PCL's
    # setKSearch, Open3D's KDTreeSearchParamKNN), found here by brute force.
    rng = np.random.default_rng(5)
    points = rng.normal(size=(300, 3))
    points /= np.linalg.norm(points, axis=1, keepdims=True)
    points += rng.normal(0.0, 0.01, points.shape)
    k = 5
    normals = pnf.estimate_normals(points, k=k, orient="outward")
    distances = np.linalg.norm(points[:, None, :] - points[None, :, :], axis=2)
    for i in range(len(points)):
        nearest = points[np.argsort(distances[i])[:k]]
        centred = nearest - nearest.mean(axis=0)
        expected = np.linalg.eigh(centred.T @ centred)[1][:, 0]
        assert abs(normals[i] @ expected) > 1 - 1e-9, i


def test_estimate_accepts_float32_and_gives_float32_back():
    points = sphere().astype(np.float32)
    normals = pnf.estimate_normals(points)
    assert normals.dtype == np.float32
    # The same fits as on the widened values, rounded to float32.
    np.testing.assert_array_equal(normals, pnf.estimate_normals(points.astype(np.float64)).astype(np.float32))
    assert pnf.estimate_normals(points.astype(np.float64)).dtype == np.float64


def test_choose_params_reports_what_it_measured():
    points, normals, _ = noisy_cube(20)
    choice = pnf.choose_params(points, normals)
    assert choice.sigma_f > 0 and choice.sigma_g > 0 and choice.iterations >= 0
    assert choice.units == "radius" and choice.mean_radius == choice.estimate.mean_radius
    spacing = 2 / 19
    assert 0.8 * spacing < choice.estimate.area_spacing < 1.25 * spacing
    assert choice.estimate.points == len(points) and choice.estimate.normal_noise_deg > 0
    assert choice.estimate.feature_share > 0.05  # a cube has edges
    assert choice.estimate.crease_length > 0.15 and choice.estimate.crease_sharpness > 0
    assert -1 <= choice.estimate.normal_position_coupling <= 1
    assert "sigma_f" in choice.rule
    assert set(choice.kwargs) == {"sigma_f", "sigma_g", "iterations", "units", "mean_radius", "stop_change_deg"}
    without = pnf.choose_params(points)
    assert without.estimate.normal_noise_deg == -1
    assert without.estimate.normal_noise_neighbours_deg == -1
    assert without.estimate.normal_noise_chords_deg == -1
    assert choice.estimate.normal_noise_neighbours_deg >= 0
    assert choice.estimate.normal_noise_chords_deg >= 0


def test_devices():
    found = pnf.devices()
    assert isinstance(found, list)
    assert sum(d.selected for d in found) <= 1
    for d in found:
        assert d.type in ("cpu", "gpu", "accelerator", "other")
        assert d.selector == f"{d.platform_index}:{d.device_index}"
        assert d.device_name in repr(d)
    assert not any(d.selected for d in pnf.devices("no-such-device-anywhere"))


def test_render_returns_an_rgb_image():
    points, normals, truth = noisy_cube(20)
    image = pnf.render(points, normals, width=120, height=90, azimuth=30, elevation=20)
    assert image.shape == (90, 120, 3) and image.dtype == np.uint8
    assert (image != 255).any() and (image == 255).any()  # a model on a white background
    colours = pnf.render(points, truth, width=120, height=90, mode="normals", azimuth=30, elevation=20)
    assert not np.array_equal(colours, image)
    error = pnf.render(points, normals, width=160, height=90, mode="error", reference_normals=truth)
    assert error.shape == (90, 160, 3)
    framed = pnf.render(points, normals, width=64, height=64, frame=((-2, -2, -2), (2, 2, 2)))
    assert framed.shape == (64, 64, 3)


def test_render_reads_float32_and_strided_arrays_as_their_values():
    # The arrays are read in place, at their own type and strides: a float32 copy, and columns of
    # a wider array, draw the same picture as packed doubles of the same values.
    points, normals, truth = noisy_cube(20)
    points32 = points.astype(np.float32)
    normals32 = normals.astype(np.float32)
    packed = pnf.render(points32.astype(np.float64), normals32.astype(np.float64), width=96, height=72,
                        mode="error", reference_normals=truth, azimuth=30, elevation=20)
    wide = np.zeros((len(points), 8), dtype=np.float32)
    wide[:, 0:3] = points32
    wide[:, 4:7] = normals32
    strided = pnf.render(wide[:, 0:3], wide[:, 4:7], width=96, height=72, mode="error",
                         reference_normals=truth, azimuth=30, elevation=20)
    assert np.array_equal(strided, pnf.render(points32, normals32, width=96, height=72, mode="error",
                                              reference_normals=truth, azimuth=30, elevation=20))
    assert np.array_equal(strided, packed)

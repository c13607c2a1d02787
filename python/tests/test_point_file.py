"""pnf.read / pnf.write / pnf.PointFile: lossless, numpy in and out."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import pnf
from conftest import noisy_cube

# A PLY with what pnf does not use: comments, obj_info, a uchar colour and an int label per
# vertex, a face element with a list property, and float normals.
HEADER = """ply
format ascii 1.0
comment made by hand for the pnf Python tests
obj_info scanner none
element vertex {n}
property float x
property float y
property float z
property uchar red
property float nx
property float ny
property float nz
property int label
element face 2
property list uchar int vertex_indices
property uchar flags
end_header
"""


def write_extra_ply(path: pathlib.Path, points: np.ndarray, normals: np.ndarray) -> list[str]:
    lines = HEADER.format(n=len(points)).splitlines()
    for i, (p, n) in enumerate(zip(points, normals)):
        lines.append(f"{p[0]:.6g} {p[1]:.6g} {p[2]:.6g} {i % 256} {n[0]:.6g} {n[1]:.6g} {n[2]:.6g} {i * 7 - 30}")
    lines += ["3 0 1 2 5", "4 3 4 5 6 250"]
    path.write_text("\n".join(lines) + "\n")
    return lines


def test_read_gives_points_and_normals_as_float64(tmp_path):
    points, normals, _ = noisy_cube(6)
    path = tmp_path / "extra.ply"
    write_extra_ply(path, points, normals)
    f = pnf.read(str(path))
    assert len(f) == len(points) and f.format == "ply" and f.encoding == "ascii"
    assert f.points.dtype == np.float64 and f.points.shape == points.shape
    np.testing.assert_allclose(f.points, points, atol=1e-5)
    np.testing.assert_allclose(f.normals, normals, atol=1e-5)
    assert f.radii is None
    assert [e["name"] for e in f.elements] == ["vertex", "face"]
    assert ("vertex_indices", "list uchar int") in f.elements[1]["properties"]
    assert f.comments == ["comment made by hand for the pnf Python tests", "obj_info scanner none"]


def test_everything_but_the_normals_survives_filtering(tmp_path):
    points, normals, _ = noisy_cube(6)
    source = tmp_path / "extra.ply"
    lines = write_extra_ply(source, points, normals)
    f = pnf.read(source)

    # Unchanged, in its own encoding: byte for byte.
    f.write(tmp_path / "same.ply", ascii=True)
    assert (tmp_path / "same.ply").read_text() == source.read_text()

    new = pnf.improve_normals(f.points, f.normals, backend="reference")
    f.normals = new
    pnf.write(tmp_path / "filtered.ply", f, ascii=True)
    out = (tmp_path / "filtered.ply").read_text().splitlines()
    header_end = lines.index("end_header") + 1
    assert out[:header_end] == lines[:header_end]
    assert out[-2:] == lines[-2:]  # the faces
    for i, (before, after) in enumerate(zip(lines[header_end:-2], out[header_end:-2])):
        b, a = before.split(), after.split()
        assert a[:4] == b[:4] and a[7] == b[7], f"vertex {i}: {before!r} -> {after!r}"
    np.testing.assert_allclose(pnf.read(tmp_path / "filtered.ply").normals, new, atol=1e-6)  # stored as float

    # Binary and back: the same elements and values.
    pnf.write(tmp_path / "filtered_bin.ply", f)
    again = pnf.read(tmp_path / "filtered_bin.ply")
    assert again.encoding == "binary_little_endian" and again.elements == f.elements
    np.testing.assert_array_equal(again.normals, f.normals)


def test_write_points_and_normals_is_exact(tmp_path):
    points, normals, _ = noisy_cube(5)
    radii = np.full(len(points), 0.25)
    for name in ("cloud.ply", "cloud.xyzn"):
        pnf.write(tmp_path / name, points, normals, radii=radii if name.endswith("ply") else None)
        back = pnf.read(tmp_path / name)
        np.testing.assert_array_equal(back.points, points)
        np.testing.assert_array_equal(back.normals, normals)
    np.testing.assert_array_equal(pnf.read(tmp_path / "cloud.ply").radii, radii)


def test_zero_points_with_normals_keep_their_normal_properties(tmp_path):
    # A filter's output on an empty selection: the file still says it carries normals.
    for name in ("empty.ply", "empty.pcd"):
        pnf.write(tmp_path / name, np.zeros((0, 3)), np.zeros((0, 3)))
        back = pnf.read(tmp_path / name)
        assert back.normals is not None and back.normals.shape == (0, 3), name
    pnf.write(tmp_path / "bare.ply", np.zeros((0, 3)))
    assert pnf.read(tmp_path / "bare.ply").normals is None


def test_write_with_new_normals_leaves_the_file_object_alone(tmp_path):
    points, normals, _ = noisy_cube(5)
    f = pnf.PointFile(points, normals)
    pnf.write(tmp_path / "flipped.ply", f, -normals)
    np.testing.assert_array_equal(f.normals, normals)
    np.testing.assert_array_equal(pnf.read(tmp_path / "flipped.ply").normals, -normals)


def test_points_without_normals(tmp_path):
    points, _, _ = noisy_cube(5)
    pnf.write(tmp_path / "bare.xyz", points)
    f = pnf.read(tmp_path / "bare.xyz")
    assert f.normals is None
    f.normals = pnf.estimate_normals(f.points)
    assert f.normals.shape == points.shape


def test_setting_bad_normals_raises(tmp_path):
    points, normals, _ = noisy_cube(5)
    f = pnf.PointFile(points, normals)
    with pytest.raises(ValueError):
        f.normals = normals[:-1]
    bad = normals.copy()
    bad[3] = 0.0
    with pytest.raises(ValueError, match="3"):
        f.normals = bad


def test_nan_normals_are_left_out_unless_asked_for_and_can_be_replaced(tmp_path):
    # PCL's NormalEstimation leaves NaN normals on points with too few neighbours: such points
    # are left out of .points and .normals; a normal only partly NaN is an error.
    points, normals, _ = noisy_cube(6)
    normals = normals.copy()
    normals[5, 0] = np.nan
    write_extra_ply(tmp_path / "partly_nan.ply", points, normals)
    with pytest.raises(ValueError, match="vertex 5.*NaN.*pnf estimate"):
        pnf.read(tmp_path / "partly_nan.ply")
    normals[5, 0] = 0.0
    normals[3] = np.nan
    path = tmp_path / "nan_normal.ply"
    write_extra_ply(path, points, normals)
    kept = pnf.read(path)
    assert kept.without_normals == 1 and len(kept.points) == len(points) - 1
    f = pnf.read(path, check_normals=False)
    assert np.isnan(f.normals[3]).all() and np.isfinite(np.delete(f.normals, 3, axis=0)).all()
    f.normals = pnf.estimate_normals(f.points, orient="outward")
    f.write(tmp_path / "fixed.ply", ascii=True)
    assert np.isfinite(pnf.read(tmp_path / "fixed.ply").normals).all()


def write_pcl_pcd(path: pathlib.Path, points: np.ndarray, normals: np.ndarray, without: set, invalid: set) -> None:
    """An ascii PCD as PCL writes one: NaN normals (and curvature) on the rows `without`, NaN
    everything on the rows `invalid`."""
    lines = [
        "# .PCD v0.7 - Point Cloud Data file format", "VERSION 0.7",
        "FIELDS x y z normal_x normal_y normal_z curvature", "SIZE 4 4 4 4 4 4 4", "TYPE F F F F F F F",
        "COUNT 1 1 1 1 1 1 1", f"WIDTH {len(points)}", "HEIGHT 1", "VIEWPOINT 0 0 0 1 0 0 0",
        f"POINTS {len(points)}", "DATA ascii",
    ]
    for i, (p, n) in enumerate(zip(points, normals)):
        if i in invalid:
            lines.append("nan nan nan nan nan nan nan")
        elif i in without:
            lines.append(f"{p[0]:.9g} {p[1]:.9g} {p[2]:.9g} nan nan nan nan")
        else:
            lines.append(f"{p[0]:.9g} {p[1]:.9g} {p[2]:.9g} {n[0]:.9g} {n[1]:.9g} {n[2]:.9g} 0.01")
    path.write_text("\n".join(lines) + "\n")


def test_pcl_nan_normals_are_kept_as_they_were(tmp_path):
    """PCL's NormalEstimation leaves NaN normals on points with too few neighbours: read() keeps
    them out of .points and .normals (counted by without_normals), improve_normals runs on the
    rest, and setting .normals (one row per point of .points) writes them back with NaN normals."""
    points, normals, _ = noisy_cube(6)
    without, invalid = {3, 40, 100}, {7}
    path = tmp_path / "pcl.pcd"
    write_pcl_pcd(path, points, normals, without, invalid)
    f = pnf.read(path)
    kept = [i for i in range(len(points)) if i not in without | invalid]
    assert len(f) == len(points) and f.without_normals == 3 and len(f.points) == len(kept)
    np.testing.assert_allclose(f.points, points[kept], atol=1e-6)
    improved = pnf.improve_normals(f.points, f.normals, backend="reference")
    f.normals = improved
    pnf.write(tmp_path / "out.pcd", f)
    back = pnf.read(tmp_path / "out.pcd")
    assert back.without_normals == 3 and len(back) == len(points)
    np.testing.assert_allclose(back.normals, improved, atol=1e-6)
    everything = pnf.read(tmp_path / "out.pcd", check_normals=False)
    assert everything.without_normals == 0 and len(everything.points) == len(points) - 1
    rows = [i for i in range(len(points)) if i not in invalid]
    nan_rows = np.isnan(everything.normals).all(axis=1)
    assert [rows[i] for i in np.flatnonzero(nan_rows)] == sorted(without)


def test_format_names_a_pcd_file_pcd(tmp_path):
    points, normals, _ = noisy_cube(4)
    write_pcl_pcd(tmp_path / "cloud.pcd", points, normals, set(), set())
    f = pnf.read(tmp_path / "cloud.pcd")
    assert f.format == "pcd"
    assert repr(f).startswith("<pnf.PointFile pcd ")


def test_help_shows_the_docstrings_and_write_needs_no_ascii(tmp_path):
    import pydoc

    text = pydoc.render_doc(pnf.PointFile, renderer=pydoc.plaintext)
    assert "kept whole: every element, property, comment and value" in text
    assert "Setting takes one row per row of" in text
    assert "write(path, *, ascii=False)" in text
    assert "NaN normals (as PCL's NormalEstimation leaves them)" in text
    points, normals, _ = noisy_cube(4)
    f = pnf.PointFile(points, normals)
    f.write(tmp_path / "plain.ply")
    assert pnf.read(tmp_path / "plain.ply").encoding == "binary_little_endian"
    f.write(tmp_path / "text.ply", ascii=True)
    assert pnf.read(tmp_path / "text.ply").encoding == "ascii"


def test_normals_of_a_pcd_with_invalid_points_take_one_row_per_point(tmp_path):
    # An organised scan's NaN pixels are not among f.points; setting f.normals takes one row per
    # row of f.points, and the NaN pixels get NaN normals.
    points, normals, _ = noisy_cube(6)
    write_pcl_pcd(tmp_path / "scan.pcd", points, normals, set(), {0, 10, 11})
    f = pnf.read(tmp_path / "scan.pcd")
    assert len(f) == len(points) and len(f.points) == len(points) - 3
    with pytest.raises(ValueError, match=f"normals has {len(points)} rows but points has {len(points) - 3}"):
        f.normals = normals
    f.normals = -np.delete(normals, [0, 10, 11], axis=0)
    f.write(tmp_path / "out.pcd")
    back = pnf.read(tmp_path / "out.pcd", check_normals=False)
    np.testing.assert_allclose(back.normals, -np.delete(normals, [0, 10, 11], axis=0), atol=1e-6)


def test_points_normals_and_radii_are_read_only_copies(tmp_path):
    # Each access makes a new array from the file: writing into one would be silently lost, so
    # numpy refuses it; the normals change only by assigning a whole array.
    points, normals, _ = noisy_cube(4)
    f = pnf.PointFile(points, normals, np.full(len(points), 0.1))
    for name in ("points", "normals", "radii"):
        array = getattr(f, name)
        assert not array.flags.writeable, name
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 7.0
        assert (getattr(f, name)[0] != 7.0).all(), name
    edited = f.normals.copy()
    edited[0] = [0.0, 0.0, 1.0]
    f.normals = edited
    np.testing.assert_array_equal(f.normals[0], [0.0, 0.0, 1.0])
    f.write(tmp_path / "edited.ply")
    np.testing.assert_array_equal(pnf.read(tmp_path / "edited.ply").normals[0], [0.0, 0.0, 1.0])
    assert "read-only" in type(f).points.__doc__ and "read-only" in type(f).normals.__doc__

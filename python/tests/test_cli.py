"""The `pnf` command that `pip install .` puts beside this Python, and the options it shares with
the module: one parser for backend/device/units, the same defaults, the same refusals."""

from __future__ import annotations

import inspect
import re
import subprocess

import numpy as np
import pytest

import pnf
from pnf import _pnf
from conftest import noisy_cube


def run(cli, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(cli), *args], capture_output=True, text=True, timeout=300)


def test_pip_installs_the_pnf_command(installed_cli, tmp_path):
    helped = run(installed_cli, "--help")
    assert helped.returncode == 0, helped.stderr
    assert "filter" in helped.stdout and "Exit codes" in helped.stdout
    points, normals, truth = noisy_cube(8)
    pnf.write(tmp_path / "in.ply", points, normals)
    done = run(installed_cli, "filter", str(tmp_path / "in.ply"), str(tmp_path / "out.ply"), "--backend", "reference")
    assert done.returncode == 0, done.stderr
    assert "pnf filter: 384 points" in done.stderr
    out = pnf.read(tmp_path / "out.ply")
    np.testing.assert_array_equal(out.points, points)
    np.testing.assert_allclose(np.linalg.norm(out.normals, axis=1), 1.0, atol=1e-6)


def test_defaults_are_the_librarys(cli):
    # improve_normals' and estimate_normals' signatures, and `pnf filter --help`, show
    # pnf::FilterParams{} and pnf::EstimateParams{}, written once in C++.
    signature = inspect.signature(pnf.improve_normals).parameters
    for name in ("sigma_f", "sigma_g", "iterations", "units"):
        assert signature[name].default == _pnf.FILTER_DEFAULTS[name], name
    estimate = inspect.signature(pnf.estimate_normals).parameters
    assert estimate["k"].default == _pnf.ESTIMATE_DEFAULTS["k"]
    assert estimate["orient"].default == _pnf.ESTIMATE_DEFAULTS["orient"]
    helped = run(cli, "filter", "--help").stdout
    for flag, name in (("--sigma-f", "sigma_f"), ("--sigma-g", "sigma_g"), ("--iterations", "iterations"),
                       ("--units", "units")):
        shown = re.search(re.escape(flag) + r" [A-Z:{},a-z]*=(\S+)", helped)
        assert shown, f"{flag} shows no default in\n{helped}"
        value = _pnf.FILTER_DEFAULTS[name]
        assert shown.group(1) == (value if isinstance(value, str) else f"{value:g}"), flag


@pytest.mark.parametrize("device", ["gpu", "pocl", "opencl:cpu", "0:0"])
def test_reference_backend_beside_an_opencl_device_is_refused_alike(cli, tmp_path, device):
    # One parser in the library (pnf::parse_backend_and_device): the same pair is refused by both,
    # with the same message, naming both.
    points, normals, _ = noisy_cube(4)
    with pytest.raises(ValueError) as caught:
        pnf.improve_normals(points, normals, backend="reference", device=device)
    message = str(caught.value)
    assert "backend 'reference'" in message and f"device '{device}'" in message
    with pytest.raises(ValueError, match=re.escape(message)):
        pnf.choose_params(points, normals, backend="reference", device=device)
    pnf.write(tmp_path / "in.ply", points, normals)
    done = run(cli, "filter", str(tmp_path / "in.ply"), str(tmp_path / "out.ply"), "--backend", "reference",
               "--device", device)
    assert done.returncode == 2, done.stderr
    assert message in done.stderr
    assert not (tmp_path / "out.ply").exists()


def test_units_and_backend_words_are_refused_alike(cli, tmp_path):
    points, normals, _ = noisy_cube(4)
    with pytest.raises(ValueError, match="units 'metres': must be 'radius' or 'absolute'"):
        pnf.improve_normals(points, normals, backend="reference", units="metres")
    with pytest.raises(ValueError, match="backend 'cuda': must be 'opencl' or 'reference'"):
        pnf.improve_normals(points, normals, backend="cuda")
    pnf.write(tmp_path / "in.ply", points, normals)
    for flags in (["--units", "metres"], ["--backend", "cuda"]):
        done = run(cli, "filter", str(tmp_path / "in.ply"), str(tmp_path / "out.ply"), *flags)
        assert done.returncode == 2, (flags, done.stderr)
        assert flags[1] in done.stderr


@pytest.mark.parametrize("value", ["0", "-1.5", "nan"])
def test_a_mean_radius_of_zero_or_less_is_an_error_in_both(cli, tmp_path, value):
    # The README: values <= 0 are an error; leaving it out (None, no --radius) estimates it.
    points, normals, _ = noisy_cube(4)
    with pytest.raises(ValueError, match="mean_radius"):
        pnf.improve_normals(points, normals, backend="reference", mean_radius=float(value))
    pnf.write(tmp_path / "in.ply", points, normals)
    done = run(cli, "filter", str(tmp_path / "in.ply"), str(tmp_path / "out.ply"), "--backend", "reference",
               "--radius", value)
    assert done.returncode == 2, done.stderr
    assert f"--radius: must be finite and > 0, got {value}" in done.stderr
    assert not (tmp_path / "out.ply").exists()

"""Shared clouds and helpers for the tests of the Python module."""

from __future__ import annotations

import os
import pathlib
import sysconfig

import numpy as np
import pytest

import pnf

REPO = pathlib.Path(__file__).resolve().parents[2]


def noisy_cube(points_per_edge: int = 16, normal_noise: float = 0.15, position_noise: float = 0.01, seed: int = 1):
    """A unit cube's six faces sampled on grids (spacing 2 / (points_per_edge - 1)), positions
    jittered along the normal and normals tilted at random: (points, noisy normals, true normals)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(-1.0, 1.0, points_per_edge)
    u, v = (a.ravel() for a in np.meshgrid(t, t))
    points, truth = [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            p = np.empty((u.size, 3))
            p[:, axis] = sign
            p[:, (axis + 1) % 3] = u
            p[:, (axis + 2) % 3] = v
            n = np.zeros_like(p)
            n[:, axis] = sign
            points.append(p)
            truth.append(n)
    points = np.concatenate(points)
    truth = np.concatenate(truth)
    points = points + truth * rng.normal(0.0, position_noise, (len(points), 1))
    normals = truth + rng.normal(0.0, normal_noise, points.shape)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return points, normals, truth


def angles_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle between matching rows of two (N, 3) arrays, in degrees (atan2: exact near 0)."""
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    dot = np.einsum("ij,ij->i", a, b)
    return np.degrees(np.arctan2(cross, dot))


def opencl_available() -> bool:
    try:
        return any(d.selected for d in pnf.devices())
    except pnf.DeviceError:
        return False


def backend_param(backend: str) -> str:
    """The backend, or a skip (a failure when PNF_DEVICE asks for a device) without OpenCL."""
    if backend == "opencl" and not opencl_available():
        message = "no OpenCL device found (pnf.devices() selects none)"
        if os.environ.get("PNF_DEVICE"):
            pytest.fail(f"PNF_DEVICE={os.environ['PNF_DEVICE']} is set but {message}")
        pytest.skip(message)
    return backend


@pytest.fixture(params=["reference", "opencl"])
def backend(request) -> str:
    return backend_param(request.param)


@pytest.fixture
def cube():
    return noisy_cube()


@pytest.fixture
def installed_cli() -> pathlib.Path:
    """The `pnf` command that `pip install .` put beside this Python (its scripts folder, such
    as venv/bin); a failure when it is not there, since the install is meant to carry it."""
    path = pathlib.Path(sysconfig.get_path("scripts")) / "pnf"
    if not path.is_file():
        pytest.fail(f"no pnf command at {path}: `pip install .` should install it with the module")
    return path


@pytest.fixture
def cli(installed_cli) -> pathlib.Path:
    """The pnf command-line tool the parity tests compare with: $PNF_CLI, else the installed one
    (built from the same sources in the same `pip install .` as the module)."""
    path = pathlib.Path(os.environ["PNF_CLI"]) if os.environ.get("PNF_CLI") else installed_cli
    if not path.is_file():
        pytest.fail(f"PNF_CLI={path} is not a file")
    return path

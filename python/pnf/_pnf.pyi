# Type stubs of the extension module pnf._pnf. The functions are called through the package
# pnf (python/pnf/__init__.py, which carries their defaults and docstrings); the classes and
# exceptions are used as they are.
from __future__ import annotations

import os
from typing import Any, Callable, Optional, Sequence, Tuple, Union

import numpy as np

_Path = Union[str, os.PathLike[str]]

class DeviceError(RuntimeError):
    """No OpenCL platform or no matching device, or a kernel that failed to build or run."""

class Cancelled(RuntimeError):
    """The progress callback returned False."""

class DataEstimate:
    """What choose_params measured (auto_params.hpp); lengths in model units."""
    @property
    def points(self) -> int: ...
    @property
    def samples(self) -> int: ...
    @property
    def mean_radius(self) -> float:
        """pnf's one mean surfel radius (the radius property's mean, else the estimate)."""
    @property
    def radius_source(self) -> str: ...
    @property
    def area_spacing(self) -> float:
        """sqrt(area per point): the unit of the --auto rule, not the mean radius."""
    @property
    def position_noise(self) -> float: ...
    @property
    def position_noise_area_spacings(self) -> float: ...
    @property
    def normal_noise_deg(self) -> float:
        """RMS angle of the input normals to fitted quadrics; -1 without normals."""
    @property
    def normal_noise_neighbours_deg(self) -> float:
        """The input normals' own noise from their 16 nearest points' normals; -1 without normals."""
    @property
    def normal_noise_chords_deg(self) -> float:
        """The same from the chords to the 3 nearest points (detail does not enter; position noise does)."""
    @property
    def fit_neighbours(self) -> int: ...
    @property
    def fit_radius(self) -> float: ...
    @property
    def feature_share(self) -> float: ...
    @property
    def crease_length(self) -> float: ...
    @property
    def crease_sharpness(self) -> float: ...
    @property
    def normal_crease_length(self) -> float: ...
    @property
    def curved_share(self) -> float: ...
    @property
    def normal_error_correlation(self) -> float: ...
    @property
    def normal_position_coupling(self) -> float: ...

class AutoChoice:
    """The parameters `pnf filter --auto` picks, and what it measured."""
    @property
    def sigma_f(self) -> float: ...
    @property
    def sigma_g(self) -> float: ...
    @property
    def iterations(self) -> int: ...
    @property
    def stop_change_deg(self) -> float: ...
    @property
    def units(self) -> str: ...
    @property
    def mean_radius(self) -> float: ...
    @property
    def estimate(self) -> DataEstimate: ...
    @property
    def rule(self) -> str: ...
    @property
    def kwargs(self) -> dict[str, Any]:
        """Keyword arguments for improve_normals that reproduce auto=True."""

class DeviceInfo:
    """One OpenCL device as the driver reports it (device.hpp)."""
    @property
    def platform_index(self) -> int: ...
    @property
    def device_index(self) -> int: ...
    @property
    def platform_name(self) -> str: ...
    @property
    def platform_vendor(self) -> str: ...
    @property
    def device_name(self) -> str: ...
    @property
    def device_vendor(self) -> str: ...
    @property
    def type(self) -> str:
        """"cpu", "gpu", "accelerator" or "other"."""
    @property
    def version(self) -> str: ...
    @property
    def driver_version(self) -> str: ...
    @property
    def selected(self) -> bool: ...
    @property
    def selector(self) -> str:
        """"P:D", the selector that picks exactly this device."""

class PointFile:
    """The contents of a point file, kept whole: every element, property, comment and value.

    PointFile(points, normals=None, radii=None) makes a new one (double x y z [nx ny nz] [radius]);
    pnf.read(path) reads one. len(f) counts every row of the file; f.points and f.normals hold the
    points pnf works on, which in a .pcd or .ply can be fewer: rows with NaN coordinates (PCL's
    invalid pixels) and rows with NaN normals (f.without_normals) stay in the file, in their
    places, but are not among them.
    """
    def __init__(self, points: Any, normals: Optional[Any] = None, radii: Optional[Any] = None) -> None: ...
    def __len__(self) -> int: ...
    @property
    def points(self) -> np.ndarray:
        """(M, 3) float64 positions of the points (M = len(f) less the rows left out, see the class),
        in file order: a new, read-only array on each access (the file keeps its own types), so
        f.points[i] = ... raises ValueError instead of being lost; the positions of a PointFile are
        not changed in place (make a new one: PointFile(points, normals))."""
    @property
    def normals(self) -> Optional[np.ndarray]:
        """(M, 3) float64 normals of the same points, or None: a new, read-only array on each access,
        so f.normals[i] = ... raises ValueError instead of being lost; to change them, assign a whole
        array (n = f.normals.copy(); n[i] = ...; f.normals = n). Setting takes one row per row of
        .points (not len(f)), stores them in the file's declared type (float stays float), adds
        float nx ny nz to a PLY (normal_x normal_y normal_z to a PCD) that had none, and gives the
        rows left out NaN normals."""
    @normals.setter
    def normals(self, value: Any) -> None: ...
    @property
    def without_normals(self) -> int:
        """Points with positions but NaN normals (as PCL's NormalEstimation leaves them), left out
        of points and normals and written back with NaN normals; 0 with check_normals=False."""
    @property
    def radii(self) -> Optional[np.ndarray]:
        """(M,) float64 values of the vertex property `radius` for the points of .points, or None: a
        new, read-only array on each access."""
    @property
    def format(self) -> str:
        """"ply", "pcd", "xyz", "xyzn" or "pwn": what the file was read from."""
    @property
    def encoding(self) -> str:
        """"ascii", "binary_little_endian" or "binary_big_endian"."""
    @property
    def elements(self) -> list[dict[str, Any]]:
        """Each element as {"name", "count", "properties": [(name, type), ...]}."""
    @property
    def comments(self) -> list[str]:
        """The header's comment and obj_info lines."""
    def write(self, path: _Path, *, ascii: bool = False) -> None:
        """Writes the file, in the format its extension names, with everything it carries. ascii:
        PLY only, ascii instead of binary little endian (a PCD keeps its DATA encoding)."""
    def copy(self) -> PointFile: ...

def improve_normals(
    points: Any, normals: Any, sigma_f: float, sigma_g: float, iterations: int, units: str,
    mean_radius: Optional[float], auto: bool, device: Optional[str], backend: str,
    progress: Optional[Callable[..., Optional[bool]]], progress_stages: bool, radii: Optional[Any],
    stop_change_deg: Optional[float], out: Optional[Any], max_seconds: Optional[float],
) -> Any: ...
def choose_params(points: Any, normals: Optional[Any], device: Optional[str], backend: str) -> AutoChoice: ...
def estimate_normals(points: Any, k: int, orient: str, viewpoint: Tuple[float, float, float]) -> np.ndarray: ...
def devices(selector: Optional[str]) -> list[DeviceInfo]: ...
def render(
    points: Any, normals: Any, radii: Optional[Any], width: int, height: int, azimuth: float, elevation: float,
    light: Tuple[float, float, float], mode: str, reference_normals: Optional[Any], error_max: float,
    radius_scale: float, frame: Optional[Tuple[Sequence[float], Sequence[float]]], threads: int,
) -> np.ndarray: ...
def read(path: _Path, check_normals: bool) -> PointFile: ...
def _view_info(array: Any) -> dict[str, Any]:
    """What the binding makes of an array (address, dtype, strides, copied); for tests."""

FILTER_DEFAULTS: dict[str, Any]
"""pnf::FilterParams{}: sigma_f, sigma_g, iterations, units, stop_change_deg, mean_radius."""
ESTIMATE_DEFAULTS: dict[str, Any]
"""pnf::EstimateParams{}: k and orient."""

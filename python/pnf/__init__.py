"""pnf: clean point normals with sharp features kept (Jones, Durand and Zwicker 2004).

numpy in, numpy out. Arrays of points and normals are (N, 3), float32 or float64, in any
layout: C order, Fortran order, a slice such as ``a[:, 3:6]`` of a wider array, a negative step.
Those are read in place, without a copy. Anything else numpy can turn into real numbers (lists,
integer or float16 arrays, byte-swapped, unaligned or broadcast arrays) is first copied into a
new float64 array. Results are new C-ordered arrays of the input's dtype: float32 when the
array they stand for (the normals for improve_normals, the points for estimate_normals) is
float32, else float64 (uint8 for images).

improve_normals(..., out=array) writes the result into an array of the caller's (for example
an Open3D cloud's own normals) instead of a new one.

The GIL is released while the library runs, so other Python threads go on; the arrays passed in
must not be changed by them meanwhile.

Errors: bad shapes, dtypes, NaN and bad parameters raise ValueError with pnf's message; a
parameter that is not a number where one is wanted TypeError naming it; file problems OSError;
device problems DeviceError (a RuntimeError); a progress callback that returns a false value
(False, numpy's False; None goes on) raises Cancelled (a RuntimeError), and Ctrl-C (within about
0.2 s, within a pass too) KeyboardInterrupt.
"""

from __future__ import annotations

import inspect
import math
import numbers
import operator
import os
from typing import Any, Callable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _pnf
from ._pnf import AutoChoice, Cancelled, DataEstimate, DeviceError, DeviceInfo, PointFile

__all__ = [
    "improve_normals",
    "choose_params",
    "estimate_normals",
    "read",
    "write",
    "devices",
    "render",
    "PointFile",
    "AutoChoice",
    "DataEstimate",
    "DeviceInfo",
    "DeviceError",
    "Cancelled",
]
__version__ = "0.1.0"

ArrayLike = Any  # an (N, 3) or (N,) array, or anything numpy.asarray accepts
PathLike = Union[str, "os.PathLike[str]"]

# The library's defaults (pnf::FilterParams{}, pnf::EstimateParams{}), the same ones `pnf filter
# --help` shows: the signatures below take them from there instead of writing them again.
_FILTER = _pnf.FILTER_DEFAULTS
_ESTIMATE = _pnf.ESTIMATE_DEFAULTS

# The range of the C int that counts (iterations, k, pixels, threads) are passed on as.
_INT_RANGE = (-(2**31), 2**31 - 1)


def _whole(name: str, value: Any) -> int:
    """`value` as an int, or ValueError naming `name`: a count must be a whole number (2.0 is, 2.7
    is not) that fits a C int. Its own range (iterations >= 0, k >= 3, ...) the library checks."""
    try:
        whole = operator.index(value)
    except TypeError:
        if not (isinstance(value, numbers.Real) and math.isfinite(value) and float(value).is_integer()):
            raise ValueError(f"{name} must be a whole number, got {value!r}") from None
        whole = int(value)
    if not _INT_RANGE[0] <= whole <= _INT_RANGE[1]:
        raise ValueError(f"{name} = {whole} is out of range ({_INT_RANGE[0]} to {_INT_RANGE[1]})")
    return whole


def _real(name: str, value: Any) -> float:
    """`value` as a float, or TypeError naming `name` (pybind11's own error would print every
    argument, arrays included, and name none). A string is not a number here."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number, got {value!r}") from None


def _optional_real(name: str, value: Any) -> Optional[float]:
    return None if value is None else _real(name, value)


def _vec3(name: str, value: Any) -> Tuple[float, float, float]:
    """`value` as three floats, or TypeError / ValueError naming `name`."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be three numbers, got {value!r}")
    try:
        items = list(value)
    except TypeError:
        raise TypeError(f"{name} must be three numbers, got {value!r}") from None
    if len(items) != 3:
        raise ValueError(f"{name} must be three numbers, got {len(items)}: {value!r}")
    return (_real(name, items[0]), _real(name, items[1]), _real(name, items[2]))


def _takes_stages(progress: Any) -> bool:
    """Whether a progress callable takes the keywords stage and fraction (or **kwargs), and so
    wants every report rather than the finished passes only."""
    if progress is None:
        return False
    try:
        parameters = inspect.signature(progress).parameters.values()
    except (TypeError, ValueError):  # a builtin without a signature: the three-argument form
        return False
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters):
        return True
    named = {p.name for p in parameters
             if p.kind in (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY)}
    return {"stage", "fraction"} <= named


def improve_normals(
    points: ArrayLike,
    normals: ArrayLike,
    *,
    sigma_f: float = _FILTER["sigma_f"],
    sigma_g: float = _FILTER["sigma_g"],
    iterations: int = _FILTER["iterations"],
    units: str = _FILTER["units"],
    mean_radius: Optional[float] = None,
    auto: bool = False,
    device: Optional[str] = None,
    backend: str = "opencl",
    progress: Optional[Callable[..., Optional[bool]]] = None,
    radii: Optional[ArrayLike] = None,
    stop_change_deg: Optional[float] = None,
    out: Optional[ArrayLike] = None,
    max_seconds: Optional[float] = None,
) -> Any:
    """Improves the normals of a point cloud; returns the new (N, 3) unit normals, float32 when
    `normals` is float32, else float64.

    points, normals: (N, 3) arrays (float32 or float64 read in place, see the module's doc);
        normals are oriented and need not be unit length.
    Defaults are the library's (pnf::FilterParams, the paper's settings), as the signature shows.

    sigma_f: width of the spatial Gaussian; neighbours reach 2 sigma_f.
    sigma_g: width of the feature Gaussian on the distance to a neighbour's tangent plane;
        smaller keeps edges sharper.
    iterations: passes, each using the previous pass's normals: a whole number >= 0.
    units: "radius" (sigmas are multiples of the mean surfel radius) or "absolute" (model units).
    mean_radius: the mean surfel radius in model units, finite and > 0; None: the mean of
        `radii` when given, else estimated from the points (the median distance to the 4
        nearest).
    auto: choose sigma_f, sigma_g and the passes from the data, as ``pnf filter --auto``: the
        rule's setting (see choose_params) and, where the data call for them, a few others
        (docs/auto.md), their passes each judged against the surface fitted to the positions
        (or by Stein's risk estimate), the best kept (the input normals when no pass beats
        them); then sigma_f, sigma_g, iterations, units and mean_radius must be left at their
        defaults.
    device: where to run, as pnf::Device::parse reads it: an OpenCL selector ("cpu", "gpu",
        "accelerator", "P:D" as devices() shows, or part of a name such as "pocl"), the same
        prefixed ("opencl:gpu"), or "reference"; None: the PNF_DEVICE variable, else the first
        GPU, else the first CPU.
    backend: "opencl" (float32 kernels, on `device`) or "reference" (double-precision C++ on
        all cores, no OpenCL needed; `device` must then be None or "reference", else ValueError
        naming both). backend and device are read by the library's one parser, the CLI's too
        (pnf::parse_backend_and_device), so --backend and --device take and refuse the same.
    progress: called as progress(pass_done, passes, seconds) after each pass; returning False
        cancels the run (Cancelled is raised). A callable that takes the keywords stage and
        fraction (or **kwargs) is called at every report instead, about every 0.2 s: as
        progress(passes_done, passes, seconds, stage=..., fraction=...), where stage is
        "lists" (building the neighbour lists), "estimate" (auto=True's look at the data),
        "filtering" (within pass passes_done + 1) or "pass" (pass passes_done just ended), seconds
        the time spent in that stage (for "pass", that pass's time) and fraction the share of
        the stage done, in [0, 1]. Ctrl-C cancels within about 0.2 s in every stage.
    radii: optional (N,) surfel radii.
    stop_change_deg: end the passes once the normals change less than this on average
        (degrees); None: off, or the rule's 0.01 with auto=True.
    out: an (N, 3) float32 or float64 array (or buffer, such as an Open3D cloud's normals) to
        write the result into instead of a new array, and return; it must be writable and may
        be `normals` itself (they are read before anything is written), not `points`.
    max_seconds: refuse (ValueError, with the numbers) a run estimated to take longer, from a
        probe that times the device on a sample; None: the library's default (10 minutes);
        0: no limit.

    Raises ValueError (bad parameters or data), DeviceError, Cancelled, KeyboardInterrupt.
    """
    radius = _optional_real("mean_radius", mean_radius)
    if radius is not None and not (math.isfinite(radius) and radius > 0):
        # The library reads 0 as "from the data"; here None says that, so 0 is a mistake.
        raise ValueError(f"invalid filter parameter mean_radius = {mean_radius}: must be finite and > 0 "
                         "(None: from the data)")
    return _pnf.improve_normals(
        points, normals, _real("sigma_f", sigma_f), _real("sigma_g", sigma_g), _whole("iterations", iterations),
        units, radius, bool(auto), device, backend, progress, _takes_stages(progress), radii,
        _optional_real("stop_change_deg", stop_change_deg), out, _optional_real("max_seconds", max_seconds),
    )


def choose_params(
    points: ArrayLike, normals: Optional[ArrayLike] = None, *, device: Optional[str] = None, backend: str = "opencl"
) -> AutoChoice:
    """The rule's setting ``pnf filter --auto`` starts from for this cloud, and what it measured.

    auto=True (improve_normals) then runs that setting pass by pass, judging each pass against
    the surface fitted to the positions, and keeps the best pass, or the input normals when no
    pass beats them by more than the judge's own error (docs/auto.md); so the passes it keeps are
    known only once it has filtered. `device` and `backend` are no longer needed here (the
    choice no longer runs the filter): their form is checked (a backend name, a selector's
    syntax), but no device is looked up.

    Needs N >= 16 points, and enough for a surface fit (a random patch of 20 points has one about
    half the time, of 25 in 195 of 200 tries; else ValueError). Returns an AutoChoice: sigma_f, sigma_g, iterations (the rule's, an
    upper bound of what auto=True keeps is 8 or more), stop_change_deg, units, mean_radius (pnf's
    one mean radius, as `pnf info` reports it), rule (one line of text), estimate (a
    DataEstimate: mean_radius, area_spacing, position_noise, normal_noise_deg, feature_share,
    curved_share, ...), and kwargs, a dict of the rule's setting for improve_normals.
    """
    return _pnf.choose_params(points, normals, device, backend)


def estimate_normals(
    points: ArrayLike,
    *,
    k: int = _ESTIMATE["k"],
    orient: str = _ESTIMATE["orient"],
    viewpoint: Sequence[float] = (0.0, 0.0, 0.0),
) -> np.ndarray:
    """Oriented unit normals for points that have none: a PCA fit over each point's k nearest
    points, the point itself included (as PCL's setKSearch and Open3D's KDTreeSearchParamKNN
    count them; k larger than N means all N), oriented by `orient`: "mst" (minimum spanning tree
    propagation, Hoppe 1992), "outward" (away from the centroid) or "viewpoint" (toward
    `viewpoint`). Needs N >= 3 and k >= 3. Returns an (N, 3) array, float32 for float32 points,
    else float64. float32/float64 points are read in place.
    Ctrl-C interrupts it within about 0.2 s (KeyboardInterrupt).
    """
    return _pnf.estimate_normals(points, _whole("k", k), orient, _vec3("viewpoint", viewpoint))


def read(path: PathLike, *, check_normals: bool = True) -> PointFile:
    """Reads a point file (.ply in any encoding, .pcd, .xyz, .xyzn, .pwn) losslessly: the
    PointFile keeps every element, property, comment and value, and writes them back unchanged.

    Points without normals: in a .pcd or .ply, a point whose normal is NaN (as PCL's
    NormalEstimation leaves one with too few neighbours) is kept in its place but left out of
    f.points and f.normals, as PCL's NaN points are; setting f.normals (one row per row of
    f.points) writes NaN normals back into both kinds. f.without_normals counts them.

    check_normals=False reads the file's normals as they are (NaN, infinite or zero ones
    included), for a caller that replaces them all, e.g. with estimate_normals(f.points).

    Raises OSError when the file cannot be read, ValueError when it is malformed.
    """
    return _pnf.read(path, bool(check_normals))


def write(
    path: PathLike,
    file_or_points: Union[PointFile, ArrayLike],
    normals: Optional[ArrayLike] = None,
    *,
    radii: Optional[ArrayLike] = None,
    ascii: bool = False,
) -> None:
    """Writes a point file; the format follows the extension.

    write(path, file): writes a PointFile (from read, perhaps with new normals) with everything
        it carries. `normals`, when given, replace the file's normals in the written file only.
    write(path, points, normals=None, radii=None): writes a new file of double x y z
        [nx ny nz] [radius].
    ascii: PLY only, write ascii instead of binary little endian.
    The file is written to a temporary name and renamed into place. Raises OSError on failure.
    """
    if isinstance(file_or_points, PointFile):
        file = file_or_points
        if normals is not None:
            file = file.copy()
            file.normals = normals
        if radii is not None:
            raise ValueError("radii cannot be replaced in an existing PointFile")
    else:
        file = PointFile(file_or_points, normals, radii)
    file.write(path, ascii=bool(ascii))


def devices(selector: Optional[str] = None) -> list[DeviceInfo]:
    """Every OpenCL device, with `selected` set on the one `selector` (or PNF_DEVICE, or the
    default rule) picks. An empty list when there is no OpenCL platform."""
    return _pnf.devices(selector)


def render(
    points: ArrayLike,
    normals: ArrayLike,
    *,
    radii: Optional[ArrayLike] = None,
    width: int = 640,
    height: int = 480,
    azimuth: float = 0.0,
    elevation: float = 0.0,
    light: Sequence[float] = (-0.5, 0.6, 1.0),
    mode: str = "shaded",
    reference_normals: Optional[ArrayLike] = None,
    error_max: float = 30.0,
    radius_scale: float = 1.2,
    frame: Optional[Tuple[Sequence[float], Sequence[float]]] = None,
    threads: int = 0,
) -> np.ndarray:
    """Draws the cloud as lit surfels (orthographic camera, white background); returns an
    (height, width, 3) uint8 RGB image, rows top to bottom.

    mode: "shaded" (Blinn-Phong grey), "normals" (colour n * 0.5 + 0.5) or "error" (angle to
        reference_normals on a viridis scale up to error_max degrees, with a colour bar).
    azimuth, elevation: view direction in degrees (+y up; 0, 0 looks from +z).
    light: direction toward the light in camera coordinates.
    frame: ((xmin, ymin, zmin), (xmax, ymax, zmax)) the camera frames; None: the cloud's box.
    The inputs are currently copied once (render_points takes a PointCloud).
    """
    frame_arg = None
    if frame is not None:
        if isinstance(frame, (str, bytes)) or len(frame) != 2:
            raise ValueError(f"frame must be ((xmin, ymin, zmin), (xmax, ymax, zmax)), got {frame!r}")
        frame_arg = (_vec3("frame's minimum", frame[0]), _vec3("frame's maximum", frame[1]))
    return _pnf.render(
        points, normals, radii, _whole("width", width), _whole("height", height), _real("azimuth", azimuth),
        _real("elevation", elevation), _vec3("light", light), mode, reference_normals, _real("error_max", error_max),
        _real("radius_scale", radius_scale), frame_arg, _whole("threads", threads),
    )

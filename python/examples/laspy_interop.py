"""laspy and pnf: a LAS scan in, normals estimated and filtered, written back as extra dimensions.

    python python/examples/laspy_interop.py IN.las OUT.las [--k 16]

LAS stores coordinates as scaled integers, so they are turned into one (N, 3) float64 array
(that copy is laspy's scaling); pnf then reads it in place. The normals go out as three float32
extra dimensions normal_x, normal_y, normal_z, next to every dimension the file had.
"""

from __future__ import annotations

import argparse
import sys

import laspy
import numpy as np

import pnf

NORMAL_DIMENSIONS = ("normal_x", "normal_y", "normal_z")


def las_points(las: laspy.LasData) -> np.ndarray:
    """The scaled x y z of every point as an (N, 3) float64 array."""
    return np.column_stack([np.asarray(las.x), np.asarray(las.y), np.asarray(las.z)])


def filter_las(source: str, target: str, k: int = 16, **filter_args) -> np.ndarray:
    """Reads `source`, estimates (PCA, MST-oriented) and filters normals, writes `target` with
    them as extra dimensions; returns the normals."""
    las = laspy.read(source)
    points = las_points(las)
    normals = pnf.improve_normals(points, pnf.estimate_normals(points, k=k), **filter_args)
    missing = [name for name in NORMAL_DIMENSIONS if name not in las.point_format.extra_dimension_names]
    las.add_extra_dims([laspy.ExtraBytesParams(name=name, type=np.float32) for name in missing])
    for axis, name in enumerate(NORMAL_DIMENSIONS):
        las[name] = normals[:, axis].astype(np.float32)
    las.write(target)
    return normals


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source")
    parser.add_argument("target")
    parser.add_argument("--k", type=int, default=16, help="points in each PCA fit, the point itself included (default 16)")
    args = parser.parse_args(argv[1:])
    normals = filter_las(args.source, args.target, k=args.k)
    print(f"{len(normals)} points: normals written to {args.target} as {', '.join(NORMAL_DIMENSIONS)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

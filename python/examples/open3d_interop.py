"""Open3D and pnf: filter an Open3D point cloud's normals in place, with no copies.

Open3D's points and normals are (N, 3) float64 buffers that pnf reads where they are; with
out=cloud.normals the new normals are written straight back into the cloud's own buffer.

    python python/examples/open3d_interop.py [IN.ply OUT.ply]

Without arguments it makes a noisy box, filters it and prints the error before and after.
"""

from __future__ import annotations

import sys

import numpy as np
import open3d as o3d

import pnf


def improve_open3d_normals(cloud: o3d.geometry.PointCloud, **filter_args) -> o3d.geometry.PointCloud:
    """Replaces cloud.normals by pnf's improved normals (the cloud needs normals: Open3D's
    cloud.estimate_normals() and orient_normals_consistent_tangent_plane(), or pnf's)."""
    if not cloud.has_normals():
        cloud.normals = o3d.utility.Vector3dVector(pnf.estimate_normals(cloud.points))
    pnf.improve_normals(cloud.points, cloud.normals, out=cloud.normals, **filter_args)
    return cloud


def noisy_box(points: int = 20000, noise_deg: float = 10.0, seed: int = 0):
    """A 2 x 1 x 1 box sampled by Open3D, with noisy normals; returns (cloud, true normals)."""
    mesh = o3d.geometry.TriangleMesh.create_box(2.0, 1.0, 1.0)
    mesh.compute_triangle_normals()
    cloud = mesh.sample_points_uniformly(points, use_triangle_normal=True)
    truth = np.asarray(cloud.normals).copy()
    rng = np.random.default_rng(seed)
    noisy = truth + rng.normal(0.0, np.radians(noise_deg), truth.shape)
    cloud.normals = o3d.utility.Vector3dVector(noisy / np.linalg.norm(noisy, axis=1, keepdims=True))
    return cloud, truth


def mean_error_deg(normals: np.ndarray, truth: np.ndarray) -> float:
    return float(np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", normals, truth), -1, 1))).mean())


def main(argv: list[str]) -> int:
    if len(argv) == 3:
        cloud = o3d.io.read_point_cloud(argv[1])
        improve_open3d_normals(cloud)
        o3d.io.write_point_cloud(argv[2], cloud)
        return 0
    cloud, truth = noisy_box()
    before = mean_error_deg(np.asarray(cloud.normals), truth)
    improve_open3d_normals(cloud)
    after = mean_error_deg(np.asarray(cloud.normals), truth)
    print(f"{len(cloud.points)} points: mean normal error {before:.2f} -> {after:.2f} degrees")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

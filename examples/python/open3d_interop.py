"""Open3D in, detexture, Open3D out.

    /usr/bin/python3 examples/python/open3d_interop.py INPUT.ply OUTPUT.ply

Reads a cloud with Open3D, removes its texture with detexture and hands the
result back as an open3d.geometry.PointCloud, coloured by the height of the
texture removed (blue: a dent filled, red: a bump taken off).
"""
import sys

import numpy as np
import open3d as o3d

import detexture


def remove_texture(pcd: o3d.geometry.PointCloud, **params) -> o3d.geometry.PointCloud:
    points = np.asarray(pcd.points)  # a view of Open3D's memory: no copy on this side
    normals = np.asarray(pcd.normals) if pcd.has_normals() else None
    result = detexture.remove_texture(points, normals, **params)
    out = o3d.geometry.PointCloud()
    out.points = o3d.utility.Vector3dVector(result.positions)
    out.normals = o3d.utility.Vector3dVector(result.normals)
    h = result.texture_height
    scale = max(float(np.abs(h).max()), 1e-12)
    t = (h / scale + 1.0) / 2.0  # 0 .. 1
    out.colors = o3d.utility.Vector3dVector(np.column_stack([t, 0.2 * np.ones_like(t), 1.0 - t]))
    return out


def main():
    source, target = sys.argv[1], sys.argv[2]
    pcd = o3d.io.read_point_cloud(source)
    out = remove_texture(pcd, radius="0.02d", threads=0)
    o3d.io.write_point_cloud(target, out)
    moved = np.linalg.norm(np.asarray(out.points) - np.asarray(pcd.points), axis=1)
    print(f"{len(out.points)} points, mean move {moved.mean():.6g}, wrote {target}")


if __name__ == "__main__":
    main()

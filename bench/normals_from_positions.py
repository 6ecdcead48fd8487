#!/usr/bin/env python3
"""Would output normals re-estimated from the output positions be better?

    bench/normals_from_positions.py BUILD WORK CASE [CASE ...] [--k 30] [--method detexture]

For each case of a quality-suite work folder (bench/quality or
bench/quality_real, after a run), reads WORK/CASE.METHOD.ply, replaces its
normals by the PCA normals of the K nearest output positions (oriented by the
filtered normals) and measures both against WORK/CASE.gt.ply with
`BUILD/detexture compare`. Prints the mean normal error of each. Needs
Debian's python3-numpy and python3-scipy (/usr/bin/python3). An experiment
of issue 9, not kept as the method (see bench/quality_real_notes.md).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tiling_diff import read_ply  # noqa: E402


def write_ply(path, P, N):
    a = np.zeros(len(P), dtype=[(k, "<f8") for k in ("x", "y", "z", "nx", "ny", "nz")])
    a["x"], a["y"], a["z"] = P.T
    a["nx"], a["ny"], a["nz"] = N.T
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(P)}\n" +
              "".join(f"property double {k}\n" for k in ("x", "y", "z", "nx", "ny", "nz")) +
              "end_header\n")
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(a.tobytes())


def normal_error(build, path, truth):
    p = subprocess.run([os.path.join(build, "detexture"), "compare", path, truth, "--json"],
                       capture_output=True, text=True, check=True)
    return json.loads(p.stdout)["normal_angle_mean_degrees"]


def pca_normals(P, N, k):
    _, idx = cKDTree(P).query(P, k)
    Q = P[idx] - P[idx].mean(axis=1, keepdims=True)
    _, V = np.linalg.eigh(np.einsum("nki,nkj->nij", Q, Q))
    M = V[:, :, 0]
    return M * np.where((M * N).sum(axis=1) < 0, -1.0, 1.0)[:, None]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("work")
    ap.add_argument("cases", nargs="+")
    ap.add_argument("--k", type=int, default=30)
    ap.add_argument("--method", default="detexture")
    a = ap.parse_args()
    print(f"| case | normal error °: {a.method} | PCA of the {a.k} nearest output positions |")
    print("|---|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for case in a.cases:
            out = os.path.join(a.work, f"{case}.{a.method}.ply")
            truth = os.path.join(a.work, f"{case}.gt.ply")
            P, N = read_ply(out)
            redone = os.path.join(tmp, "pca.ply")
            write_ply(redone, P, pca_normals(P, N, a.k))
            print(f"| {case} | {normal_error(a.build, out, truth):.2f} | "
                  f"{normal_error(a.build, redone, truth):.2f} |", flush=True)


if __name__ == "__main__":
    main()

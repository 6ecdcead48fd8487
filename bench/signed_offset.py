#!/usr/bin/env python3
"""Where does an output sit relative to the underlying surface, as a whole?

    bench/signed_offset.py GT.ply RESULT.ply [RESULT.ply ...]

For each result cloud, the signed distance of every point to the ground truth
(point to plane at the nearest ground-truth sample, along its normal, as
`detexture compare` measures it) and its mean, median, 1st and 99th
percentiles, min and max. A median well away from 0 is an offset of the whole
output, not texture left: session 31 found the outputs of dense scales on
the envelope of the scales' tops this way (median +0.0039 to +0.0043 for
scales 0.005 high; bench/quality_real_notes.md), e.g.

    bench/signed_offset.py W/wide/dwarf-scales.gt.ply W/wide/dwarf-scales.in.ply \\
        W/wide/dwarf-scales.rule.ply

with W the work folder of `bench/spot_check.sh`. Needs Debian's python3-numpy
and python3-scipy (/usr/bin/python3).

    bench/signed_offset.py --write GT.ply RESULT.ply [RESULT.ply ...]

also writes each RESULT as RESULT.signed.ply (binary PLY: its positions and
normals, and the signed distance as the property signed_distance), to be drawn
with `detexture render ... --color-by signed_distance` (session 43's picture,
bench/README.md).
"""
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tiling_diff import read_ply  # noqa: E402


def write_signed(path, P, N, d):
    """P, N and d as a binary little-endian PLY with the property signed_distance."""
    out = path[:-4] + ".signed.ply" if path.endswith(".ply") else path + ".signed.ply"
    names = ["x", "y", "z"] + (["nx", "ny", "nz"] if N is not None else []) + ["signed_distance"]
    columns = [P] + ([N] if N is not None else []) + [d[:, None]]
    data = np.ascontiguousarray(np.hstack(columns), dtype="<f8")
    header = "ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % len(P)
    header += "".join(f"property double {n}\n" for n in names) + "end_header\n"
    with open(out, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(data.tobytes())
    return out


def main():
    args = sys.argv[1:]
    write = "--write" in args
    if write:
        args.remove("--write")
    if len(args) < 2:
        sys.exit(__doc__)
    G, GN = read_ply(args[0])
    if GN is None:
        sys.exit(f"{args[0]}: the ground truth needs normals")
    tree = cKDTree(G)
    for path in args[1:]:
        P, N = read_ply(path)
        _, j = tree.query(P)
        d = np.einsum("ij,ij->i", P - G[j], GN[j])
        p1, p50, p99 = np.percentile(d, [1, 50, 99])
        print(f"{path}: mean {d.mean():+.5f} median {p50:+.5f} p1 {p1:+.5f} p99 {p99:+.5f} "
              f"min {d.min():+.5f} max {d.max():+.5f}")
        if write:
            print(f"  wrote {write_signed(path, P, N, d)}")


if __name__ == "__main__":
    main()

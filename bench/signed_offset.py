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
"""
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tiling_diff import read_ply  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    G, GN = read_ply(sys.argv[1])
    if GN is None:
        sys.exit(f"{sys.argv[1]}: the ground truth needs normals")
    tree = cKDTree(G)
    for path in sys.argv[2:]:
        P, _ = read_ply(path)
        _, j = tree.query(P)
        d = np.einsum("ij,ij->i", P - G[j], GN[j])
        p1, p50, p99 = np.percentile(d, [1, 50, 99])
        print(f"{path}: mean {d.mean():+.5f} median {p50:+.5f} p1 {p1:+.5f} p99 {p99:+.5f} "
              f"min {d.min():+.5f} max {d.max():+.5f}")


if __name__ == "__main__":
    main()

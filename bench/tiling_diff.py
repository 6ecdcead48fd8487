#!/usr/bin/python3
"""bench/tiling_diff.py A.ply B.ply [--radius R]: point-by-point difference of two
outputs of detexture on the same input (same order), e.g. a tiled run against
the whole-cloud run. Prints JSON: points, bitwise-equal points (positions and
normals), max and RMS position difference (and over R when --radius is
given), largest normal angle, and the share of points differing by more
than 1e-9 and 1e-6 (in the cloud's units).

Reads binary little-endian or ASCII PLY with float or double x y z nx ny nz
(what detexture writes); other vertex properties are skipped."""
import json
import sys

import numpy as np

TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2",
         "int16": "i2", "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4",
         "uint": "u4", "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8",
         "float64": "f8"}


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt, count, props, in_vertex = None, 0, [], False
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            in_vertex = w[1] == "vertex"
            if in_vertex:
                count = int(w[2])
        elif w[0] == "property" and in_vertex:
            if w[1] == "list":
                sys.exit(f"{path}: list properties in vertex are not supported")
            props.append((w[2], TYPES[w[1]]))
    if fmt == "ascii":
        rows = np.loadtxt(data[end:].decode("ascii").splitlines()[:count], ndmin=2)
        cols = {name: rows[:, i] for i, (name, _) in enumerate(props)}
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        dt = np.dtype([(name, order + t) for name, t in props])
        arr = np.frombuffer(data, dtype=dt, count=count, offset=end)
        cols = {name: arr[name].astype(np.float64) for name, _ in props}
    P = np.stack([cols["x"], cols["y"], cols["z"]], axis=1)
    N = np.stack([cols["nx"], cols["ny"], cols["nz"]], axis=1) if "nx" in cols else None
    return P, N


def main():
    args = sys.argv[1:]
    radius = None
    if "--radius" in args:
        i = args.index("--radius")
        radius = float(args[i + 1])
        del args[i:i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    PA, NA = read_ply(args[0])
    PB, NB = read_ply(args[1])
    if PA.shape != PB.shape:
        sys.exit("the clouds have different sizes")
    d = np.linalg.norm(PA - PB, axis=1)
    same = np.all(PA == PB, axis=1)
    out = {"points": int(len(d)), "max_position_difference": float(d.max()),
           "rms_position_difference": float(np.sqrt(np.mean(d * d))),
           "share_above_1e-9": float(np.mean(d > 1e-9)),
           "share_above_1e-6": float(np.mean(d > 1e-6))}
    if NA is not None and NB is not None:
        same &= np.all(NA == NB, axis=1)
        c = np.clip(np.sum(NA * NB, axis=1), -1.0, 1.0)
        ang = np.degrees(np.arccos(c))
        out["max_normal_angle_deg"] = float(ang.max())
        out["share_normal_above_1deg"] = float(np.mean(ang > 1.0))
    out["bitwise_equal_points"] = int(same.sum())
    if radius:
        out["max_position_difference_over_r"] = float(d.max() / radius)
        out["rms_position_difference_over_r"] = out["rms_position_difference"] / radius
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()

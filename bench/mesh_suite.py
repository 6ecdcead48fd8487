#!/usr/bin/env python3
"""The real-shape suite's meshes as textured meshes (issue 13).

    bench/mesh_suite.py BUILD [--peers-build PEERS_BUILD] [--work DIR] [--cases a,b] [--write] [--reuse]

For every mesh case of bench/quality_suite.py's REAL_SUITE:
  1. bench/peers/prepare_mesh makes the base mesh, as for bench/quality_real,
     but Loop-subdivided further (one level at a time) until the vertex
     spacing is at most R/4, so that the mesh's own vertices can carry the
     texture (stopping before 400,000 vertices);
  2. `detexture synth --base-mesh BASE --at-vertices --no-normals` textures the
     mesh's vertices and keeps its faces (a scanned mesh: no normals), with
     the case's texture; the ground truth is the untextured base;
  3. detexture runs three times with the suite's rule (-r 1.5R --sigma-s 1.5R):
     `--mesh cloud` (the paper: vertices as an unconnected cloud, PCA normals),
     `--mesh faces --mesh-path-limit 0` (Euclidean R_i) and `--mesh faces`
     (default: normals from the faces, R_i along the mesh, fold repair);
  4. `detexture compare` against the ground truth, the fold and flip counts
     from --stats, and a picture (`detexture render`: input, paper, faces).

Noise does not apply to --at-vertices meshes: the noisy engine case runs
clean. BUILD holds detexture; PEERS_BUILD (default BUILD) holds
bench/peers/prepare_mesh (cmake -DDETEXTURE_BUILD_PEERS=ON). --write puts the
table into bench/RESULTS.md between <!-- mesh:begin --> and <!-- mesh:end -->.
"""
import argparse
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import quality_suite as qs  # noqa: E402

MAX_VERTICES = 400_000
REUSE = False  # --reuse: take any existing output as made by the current command
SPACINGS_PER_R = 4.0


def run(cmd, log=None, check=True):
    p = subprocess.run(["nice", "-n", "10"] + cmd, capture_output=True, text=True)
    if log:
        with open(log, "w") as f:
            f.write(" ".join(cmd) + "\n" + p.stdout + p.stderr)
    if check and p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()[-400:]}")
    return p


def ply_vertices(path):
    with open(path, "rb") as f:
        for line in f.read(4096).split(b"\n"):
            if line.startswith(b"element vertex"):
                return int(line.split()[2])
    raise RuntimeError(f"{path}: no vertex count")


def prepare(peers, mesh, size, work):
    """The base mesh, subdivided until the spacing is at most R/4."""
    level = mesh.subdivide
    while True:
        out = os.path.join(work, f"{mesh.name}.sub{level}.ply")
        if not os.path.exists(out):
            cmd = [os.path.join(peers, "bench", "peers", "prepare_mesh"),
                   os.path.join(qs.ASSIMP_MODELS, mesh.model), out,
                   "--components", mesh.components, "--subdivide", str(level)]
            p = run(cmd, out[:-4] + ".log")
            with open(out[:-4] + ".area", "w") as f:
                f.write([l for l in p.stdout.splitlines() if l.startswith("area:")][-1].split()[1])
        area = float(open(out[:-4] + ".area").read())
        n = ply_vertices(out)
        spacing = math.sqrt(area / n)
        if spacing <= size / SPACINGS_PER_R or 4 * n > MAX_VERTICES:
            return out, level, n, spacing
        level += 1


def made_by(cmd, out):
    """Whether out exists and was made by cmd with the same detexture binary (a rerun of the
    report after an interrupted run reuses it)."""
    key = out + ".key.json"
    if REUSE and os.path.exists(out):
        return True
    if not (os.path.exists(out) and os.path.exists(key)):
        return False
    return json.load(open(key)) == {"command": cmd, "binary": os.path.getmtime(cmd[0])}


def store_made_by(cmd, out):
    with open(out + ".key.json", "w") as f:
        json.dump({"command": cmd, "binary": os.path.getmtime(cmd[0])}, f)


def compare(build, result, truth):
    p = run([os.path.join(build, "detexture"), "compare", result, truth, "--json"])
    return json.loads(p.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("--peers-build")
    ap.add_argument("--work")
    ap.add_argument("--cases")
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--reuse", action="store_true",
                    help="reuse existing outputs in the work folder whatever made them")
    a = ap.parse_args()
    global REUSE
    REUSE = a.reuse
    build = os.path.abspath(a.build)
    peers = os.path.abspath(a.peers_build or a.build)
    work = os.path.abspath(a.work or os.path.join(build, "bench-mesh"))
    os.makedirs(os.path.join(work, "pictures"), exist_ok=True)
    det = os.path.join(build, "detexture")
    cases = [c for c in qs.REAL_SUITE if c.mesh is not None]
    if a.cases:
        cases = [c for c in cases if c.name in a.cases.split(",")]
    rows = []
    for case in cases:
        base, level, n, spacing = prepare(peers, case.mesh, case.size, work)
        stem = os.path.join(work, case.name)
        synth = [det, "synth", "--base-mesh", base, "--at-vertices", "--no-normals",
                 "--texture", case.texture, "--layout", case.layout, "--size", qs.fmt(case.size),
                 "--amplitude", qs.fmt(case.amplitude), "--ground-truth-points",
                 str(qs.GROUND_TRUTH_POINTS), "--seed", str(qs.SEED), "-o", stem + ".ply",
                 "--ground-truth", stem + ".gt.ply"]
        if case.mixed_signs:
            synth.append("--mixed-signs")
        if not made_by(synth, stem + ".ply"):
            run(synth, stem + ".synth.log")
            store_made_by(synth, stem + ".ply")
        r = qs.RADIUS_FACTOR * case.size
        results = {"input": (stem + ".ply", None)}
        for mode in ("cloud", "euclidean", "faces"):
            out = f"{stem}.{mode}.ply"
            cmd = [det, stem + ".ply", "-o", out, "-r", qs.fmt(r), "--sigma-s", qs.fmt(r),
                   "--mesh", "cloud" if mode == "cloud" else "faces", "--stats",
                   out[:-4] + ".json", "-f", "-q"]
            if mode == "euclidean":
                cmd += ["--mesh-path-limit", "0"]
            if not made_by(cmd, out):
                run(cmd, out[:-4] + ".log")
                store_made_by(cmd, out)
            results[mode] = (out, json.load(open(out[:-4] + ".json")))
        errors = {k: compare(build, path, stem + ".gt.ply") for k, (path, _) in results.items()}
        picture = os.path.join(work, "pictures", case.name + ".png")
        run([det, "render", stem + ".ply", results["cloud"][0], results["faces"][0], "-o", picture,
             "--up", case.mesh.up, "--label", "input", "paper (--mesh cloud)", "faces (default)",
             "-f", "-q", "--size", "1500x500"], check=False)
        rows.append((case, level, n, spacing, r, synth, results, errors))
        print(f"{case.name}: done", file=sys.stderr)
    text = report(rows)
    print(text)
    if a.write:
        path = os.path.join(HERE, "RESULTS.md")
        old = open(path).read()
        begin, end = "<!-- mesh:begin -->", "<!-- mesh:end -->"
        block = f"{begin}\n{text}{end}\n"
        if begin in old:
            old = old[:old.index(begin)] + block + old[old.index(end) + len(end) + 1:]
        else:
            old = old.rstrip("\n") + "\n\n" + block
        open(path, "w").write(old)


def share(k, of):
    return f"{100.0 * k / of:.2f}%" if of else "-"


def report(rows):
    out = ["## Textured meshes (`bench/mesh_suite.py`, issue 13)", "",
           "The real-shape suite's meshes with the texture on their own vertices and their faces "
           "kept (`synth --at-vertices --no-normals`: a scanned mesh without normals), filtered "
           "as a cloud (`--mesh cloud`, the paper) and as a mesh (`--mesh faces`, the default: "
           "normals from the faces, R_i cut to the vertices an edge path reaches within r, "
           "fold repair; the row `--mesh-path-limit 0` keeps R_i Euclidean). Ground-truth errors as for the clouds "
           "(`detexture compare`, relative to the diagonal d; residual texture = standard "
           "deviation of the signed distance, the texture and noise left); folded = interior edges whose "
           "dihedral angle exceeds 60°; flipped = triangles whose normal turned more than 90° "
           "from the input's; p99 = 99th-percentile dihedral angle. Rerun: "
           "`bench/mesh_suite.py BUILD --peers-build PEERS_BUILD --write`. Pictures (not "
           "committed): `pictures/CASE.png` in the work folder (input, paper, faces).", ""]
    for case, level, n, spacing, r, synth, results, errors in rows:
        out.append(f"### {case.name}")
        out.append("")
        out.append(f"{case.mesh.what}; {case.texture} R = {qs.fmt(case.size)}, A = "
                   f"{qs.fmt(case.amplitude)}. Base: `prepare_mesh {case.mesh.model} "
                   f"--components {case.mesh.components} --subdivide {level}` ({n} vertices, "
                   f"spacing {spacing:.4f} = R / {case.size / spacing:.1f}); detexture `-r "
                   f"{qs.fmt(r)} --sigma-s {qs.fmt(r)}`." +
                   (" The suite's noise is left out (at-vertices meshes are clean)."
                    if case.noise > 0 else ""))
        out.append("")
        out.append("| mesh | Dmean | Dmax | residual texture | normal error ° | folded | flipped | "
                   "p99 dihedral ° | vertices held | seconds |")
        out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for key, label in (("input", "input"), ("cloud", "paper (`--mesh cloud`)"),
                           ("euclidean", "faces, Euclidean R_i (`--mesh-path-limit 0`)"),
                           ("faces", "faces (default)")):
            e = errors[key]
            stats = results[key][1]
            if stats is None:
                f = results["faces"][1]["mesh"]["input"]
                edges = results["faces"][1]["mesh"]["edges"]
                tris = results["faces"][1]["mesh"]["triangles"]
                folded, flipped, p99, held, secs = (f["folded_edges"], 0, f["p99_dihedral_deg"],
                                                    "-", "-")
            else:
                m = stats["mesh"]
                edges, tris = m["edges"], m["triangles"]
                f = m["output"]
                folded, flipped, p99 = f["folded_edges"], f["flipped_triangles"], f["p99_dihedral_deg"]
                held = m["vertices_held"] if key != "cloud" else "-"
                secs = f"{stats['seconds']['total']:.1f}"
            angle = ("-" if e["normal_angle_mean_degrees"] is None
                     else f"{e['normal_angle_mean_degrees']:.1f}")
            out.append(f"| {label} | {e['dmean_relative']:.5f} | {e['dmax_relative']:.5f} | "
                       f"{e['signed_std_relative']:.5f} | {angle} | {share(folded, edges)} | "
                       f"{share(flipped, tris)} | {p99:.1f} | {held} | {secs} |")
        out.append("")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    main()

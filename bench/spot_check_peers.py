#!/usr/bin/python3
"""The five tuned peers on bench/spot_check.sh's wider check (30 unseen cases).

    bench/spot_check_peers.py BUILD_DIR WIDE_DIR [--jobs J]

WIDE_DIR is the `wide/` folder spot_check.sh fills: for each case NAME its
input NAME.in.ply (synth's header comment holds the relief's size R), the
ground truth NAME.gt.ply, synth's log NAME.synth.log (the base area),
detexture's result with the suites' rule, NAME.rule.ply, and the comparisons
of the input and of that result with the ground truth, NAME.in.json and
NAME.rule.json (`detexture compare --json`). Each peer runs with
the real suite's tuned parameters (bench/peer_params_real.json), scaled to
the case's R and density exactly as bench/quality_real does
(quality_suite.peer_args), one thread each, J runs at a time (2). Outputs
NAME.PEER.ply are reused when their input, program and options are unchanged
(the suites' cache, keyed on content). Prints one line per case and a
summary: detexture's mean rank among itself and the peers on residual
texture and on normal error (1 = best of 6), the cases where it is best on
both, and how often each peer beats it. No parameter was chosen on these
models, so the ranks say how the suites' results carry over.
"""
import argparse
import json
import os
import re
import sys
import time
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import quality_suite as qs  # noqa: E402

PEERS = ["cgal-bilateral", "cgal-jet", "pcl-mls", "meshlab-rimls", "cgal-wlop"]
METRICS = [("signed_std", "residual texture"), ("normal_angle_mean_degrees", "normal error")]


def case_of(wide, name):
    """A quality_suite.Case with the R and base area spot_check.sh used."""
    with open(os.path.join(wide, name + ".in.ply"), "rb") as f:
        header = f.read(4096).decode("latin1")
    size = float(re.search(r"\bsize=([0-9.eE+-]+)", header).group(1))
    with open(os.path.join(wide, name + ".synth.log")) as f:
        m = re.search(r"base area ([0-9.eE+-]+) diagonal ([0-9.eE+-]+)", f.read())
    qs.BASE_GEOMETRY[name] = (float(m.group(1)), float(m.group(2)))
    return qs.Case(name, "mesh", name.rsplit("-", 1)[1], "", size, 0.0)


def run_peer(build, wide, case, peer, params):
    name = case.name
    out = os.path.join(wide, f"{name}.{peer}.ply")
    program = qs.peer_program(build, peer)
    threads = None if peer == "meshlab-rimls" else 1
    cmd = [program, os.path.join(wide, name + ".in.ply"), out] + qs.peer_args(
        peer, params, case, qs.POINTS, threads)
    if qs.cached_peer_run(cmd, out) is None:
        t0 = time.monotonic()
        ok, _, message = qs.run(cmd, out[:-4] + ".log", timeout=1800)
        if not ok:
            raise RuntimeError(f"{peer} on {name} failed: {message} (see {out[:-4]}.log)")
        qs.store_peer_run(cmd, out, time.monotonic() - t0)
    return qs.compare(build, out, os.path.join(wide, name + ".gt.ply"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build")
    ap.add_argument("wide")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    if not os.path.isdir(args.wide):
        sys.exit(f"spot_check_peers: {args.wide} is not a folder: give spot_check.sh's WORK_DIR/wide")
    names = sorted(f[:-len(".rule.ply")] for f in os.listdir(args.wide) if f.endswith(".rule.ply"))
    if not names:
        sys.exit(f"spot_check_peers: no NAME.rule.ply in {args.wide}: run bench/spot_check.sh first")
    params = qs.load_peer_params(qs.SUITES["real"])
    missing = [p for p in PEERS if p not in params or qs.peer_program(build, p) is None]
    if missing:
        sys.exit(f"spot_check_peers: peers not built or not tuned: {', '.join(missing)} "
                 "(cmake -DDETEXTURE_BUILD_PEERS=ON; MeshLab RIMLS needs meshlabserver)")
    cases = {name: case_of(args.wide, name) for name in names}
    jobs = [(name, peer) for name in names for peer in PEERS]
    with ThreadPoolExecutor(args.jobs) as ex:
        results = list(ex.map(
            lambda j: run_peer(build, args.wide, cases[j[0]], j[1], params[j[1]]["params"]), jobs))
    metrics = {(name, peer): m for (name, peer), m in zip(jobs, results)}
    for name in names:
        for run in ("in", "rule"):  # written by spot_check.sh with NAME.rule.ply
            with open(os.path.join(args.wide, f"{name}.{run}.json")) as f:
                metrics[(name, run)] = json.load(f)
    ranks = {key: [] for key, _ in METRICS}
    beaten = {p: [0, 0] for p in PEERS}
    both = []
    print("case: detexture's value (rank of 6) and the best peer's, per metric; Dmax / input's")
    for name in names:
        line = f"{name:<17}"
        best_all = True
        for k, (key, label) in enumerate(METRICS):
            mine = metrics[(name, "rule")][key]
            better = [p for p in PEERS if metrics[(name, p)][key] < mine]
            for p in better:
                beaten[p][k] += 1
            rank = 1 + len(better)
            ranks[key].append(rank)
            best_all &= rank == 1
            best = min(PEERS, key=lambda p: metrics[(name, p)][key])
            line += f"  {label} {mine:.5g} (r{rank}; {best} {metrics[(name, best)][key]:.5g})"
        dmax_in = metrics[(name, "in")]["dmax"]
        line += "  Dmax x%.2f (peers' lowest x%.2f)" % (
            metrics[(name, "rule")]["dmax"] / dmax_in,
            min(metrics[(name, p)]["dmax"] for p in PEERS) / dmax_in)
        if best_all:
            both.append(name)
        print(line)
    n = len(names)
    print(f"{n} cases: detexture's mean rank among itself and {len(PEERS)} peers: residual "
          f"texture {sum(ranks['signed_std']) / n:.2f}, normal error "
          f"{sum(ranks['normal_angle_mean_degrees']) / n:.2f}; best on both in {len(both)}")
    print("cases where each peer beats detexture (residual texture, normal error): " +
          ", ".join(f"{p} {a}, {b}" for p, (a, b) in beaten.items()))


if __name__ == "__main__":
    main()

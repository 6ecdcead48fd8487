#!/usr/bin/env python3
"""Overhead of the Python module against the command line, end to end.

    nice -n 10 /usr/bin/python3 bench/python_overhead.py --cli build/detexture \
        --cloud sphere1m.ply --runs 5 --threads 2

Each run times, interleaved, in fresh processes and on the same files:
  cli:    detexture CLOUD -o out.ply -r RADIUS -j THREADS -q --force
  python: /usr/bin/python3 -c "read_point_cloud, remove_texture, write_point_cloud"
(interpreter start and `import detexture` included), and prints the median
wall times and their ratio. PYTHONPATH selects the module (build/python).
"""
import argparse
import os
import statistics
import subprocess
import sys
import time

PYTHON_JOB = """
import sys, detexture
cloud = detexture.read_point_cloud(sys.argv[1])
r = detexture.remove_texture(cloud, radius=sys.argv[3], threads=int(sys.argv[4]))
detexture.write_point_cloud(sys.argv[2], detexture.detextured_cloud(cloud, r))
"""


def timed(cmd, env=None):
    start = time.perf_counter()
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cli", required=True)
    ap.add_argument("--cloud", required=True)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--radius", default="0.02d")
    ap.add_argument("--work", default="/tmp")
    a = ap.parse_args()
    out_cli = os.path.join(a.work, "overhead_cli.ply")
    out_py = os.path.join(a.work, "overhead_py.ply")
    cli, py = [], []
    for k in range(a.runs):
        cli.append(timed([a.cli, a.cloud, "-o", out_cli, "-r", a.radius, "-j", str(a.threads),
                          "-q", "--force"]))
        py.append(timed([sys.executable, "-c", PYTHON_JOB, a.cloud, out_py, a.radius,
                         str(a.threads)]))
        print(f"run {k + 1}: cli {cli[-1]:.2f} s, python {py[-1]:.2f} s", flush=True)
    same = open(out_cli, "rb").read() == open(out_py, "rb").read()
    mc, mp = statistics.median(cli), statistics.median(py)
    print(f"median of {a.runs}: cli {mc:.2f} s, python {mp:.2f} s, "
          f"python/cli = {mp / mc:.3f} ({100 * (mp / mc - 1):+.1f}%); outputs identical: {same}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""End to end at scale (issue 5, item 3): `limn interpolate` on igea and its
Loop refinements up to 8.6M vertices, every stage timed and the peak memory
measured.

    python3 perf/scale_bench.py [--build build] [--max-size 9e6] [--method auto]

For each size it runs the CLI under GNU time's peak resident set size (ru_maxrss
of the child, read through os.wait4) and prints, per stage (load, topology,
stencil, solve, write) the seconds and ns per vertex — linear stages keep ns
per vertex flat as the size grows 64x — and the peak memory in bytes per
vertex. Meshes are made with `limn subdivide` into out/perf-meshes/.
"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_args import scale_parser  # noqa: E402
from series_throughput import SIZES, mesh  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STAGES = ["load", "topology", "stencil", "solve", "write"]


def run_with_peak(cmd):
    """Runs cmd; returns (exit status, peak RSS in bytes) of the child."""
    proc = subprocess.Popen(cmd)
    _, status, usage = os.wait4(proc.pid, 0)
    return os.waitstatus_to_exitcode(status), usage.ru_maxrss * 1024


def main():
    ap = scale_parser(__doc__)
    ap.add_argument("--method", default="auto")
    a = ap.parse_args()
    limn = os.path.join(a.build, "limn")
    print("| size | vertices | products | " + " | ".join(f"{s} s (ns/v)" for s in STAGES) +
          " | total s | peak MB | peak B / vertex |")
    print("|---|---:|---:|" + "---:|" * (len(STAGES) + 3))
    with tempfile.TemporaryDirectory(prefix="limn_scale_") as tmp:
        for label, levels in SIZES:
            if 134345 * 4 ** levels > a.max_size:
                break
            path = mesh(a.build, a.meshes, levels)
            rep = os.path.join(tmp, "r.json")
            rc, peak = run_with_peak([limn, "interpolate", path, "-o",
                                      os.path.join(tmp, "p.ply"), "--method", a.method,
                                      "--report", rep, "-q"])
            if rc != 0:
                sys.exit(f"limn interpolate {path} failed ({rc})")
            r = json.load(open(rep))
            n, sec = r["vertices"], r["seconds"]
            cells = " | ".join(f"{sec[s]:.2f} ({sec[s] / n * 1e9:.0f})" for s in STAGES)
            print(f"| {label} | {n} | {r['products']:g} | {cells} | {sec['total']:.2f} "
                  f"| {peak / 1e6:.0f} | {peak / n:.0f} |", flush=True)


if __name__ == "__main__":
    main()

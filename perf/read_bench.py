#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Mesh reading in one run (issue 13.1): limn_mesh_read's general readers
and fast paths (build/perf/read_bench, meshes compared bit for bit) and
trimesh.load of the same file as the anchor, on igea refined twice by Loop
(2.1M vertices) written as scanners write it (binary little endian, float32
x y z, `uchar int` face lists) and, with --text, as limn writes OBJ, OFF and
ASCII PLY.

  python3 perf/read_bench.py [--python VENV/bin/python] [--repeat 5] [--text]
                             [--threads 1,2] [--work DIR]

--python: an interpreter with trimesh and numpy (pip install trimesh numpy);
without one the anchor is left out."""
import argparse
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TRIMESH = """
import sys, time, trimesh
for process in (True, False):
    best = 1e300
    for _ in range(int(sys.argv[2])):
        t = time.perf_counter()
        m = trimesh.load(sys.argv[1], process=process)
        best = min(best, time.perf_counter() - t)
    print("trimesh.load(process=%s): %.3f s, %.1f M vertices/s (%d vertices, best of %s)"
          % (process, best, len(m.vertices) / best * 1e-6, len(m.vertices), sys.argv[2]))
"""

def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--mesh", default=os.path.join(ROOT, "..", "shared", "meshes", "large",
                                                   "igea.ply"))
    ap.add_argument("--levels", type=int, default=2)
    ap.add_argument("--work", default="/tmp/limn_read_bench")
    ap.add_argument("--python", default=sys.executable)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--text", action="store_true", help="also OBJ, OFF and ASCII PLY")
    ap.add_argument("--threads", default="", help="host thread counts, e.g. 1,2")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    refined = os.path.join(a.work, "refined_l%d.ply" % a.levels)
    scanner = os.path.join(a.work, "scanner_l%d_f32.ply" % a.levels)
    if not os.path.exists(refined):
        subprocess.run([os.path.join(a.build, "limn"), "subdivide", "--levels", str(a.levels),
                        a.mesh, "-o", refined, "-q"], check=True)
    bench = os.path.join(a.build, "perf", "read_bench")
    if not os.path.exists(scanner):
        subprocess.run([bench, "--scanner", refined, scanner], check=True)
    files = [scanner]
    for ext, fmt in (("obj", "obj"), ("off", "off"), ("ascii.ply", "ply-ascii")) if a.text else ():
        path = os.path.join(a.work, "refined_l%d.%s" % (a.levels, ext))
        if not os.path.exists(path):
            subprocess.run([os.path.join(a.build, "limn"), "subdivide", "--levels", "0", refined,
                            "-o", path, "--format", fmt, "-q"], check=True)
        files.append(path)
    for path in files:
        measure(a, bench, path)


def measure(a, bench, path):
    print("file: %s (%.1f MB)" % (path, os.path.getsize(path) / 1e6), flush=True)
    best = 1e300
    for _ in range(a.repeat):  # the floor: the file's bytes from the page cache
        t = time.perf_counter()
        with open(path, "rb") as f:
            f.read()
        best = min(best, time.perf_counter() - t)
    print("floor (read the file into memory): %.3f s" % best, flush=True)
    for threads in a.threads.split(",") if a.threads else [""]:
        if threads:
            print("host threads: %s" % threads, flush=True)
        subprocess.run([bench, path, str(a.repeat)] + ([threads] if threads else []), check=True)
    r = subprocess.run([a.python, "-c", TRIMESH, path, str(a.repeat)])
    if r.returncode:
        print("trimesh.load: not measured (no trimesh for %s)" % a.python)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Denoise and morph throughput (issue 5, item 5), the series toolkit's two
heavy users of the stencil product.

    python3 perf/series_throughput.py [--build build] [--max-size 9e6] [--stream-gbs X]

On igea and its Loop refinements (out/perf-meshes/, made by perf/run_suite.py
or here with `limn subdivide`): `limn denoise` (m = 2, K = 3: 9 products) and
`limn morph` from the mesh to its denoised copy (4 frames, m = 2: 3 products
a frame after the first), both on PoCL with 2 threads. It prints vertices per
second of the compute phase (report key seconds.compute: the products and
their updates on the device, without I/O, topology or stencils), ns per
vertex per product and, given the STREAM triad rate, the fraction of it the
compute phase moves (the series step streams the CSR table, one gather of x,
x_next and the accumulator: 12 B a nonzero + 4 B a row + 4 x 32 B a row).
Prints a markdown table; returns rows to run_suite.py.
"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_args import scale_parser  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIZES = [("igea 134k", 0), ("igea 537k", 1), ("igea 2.1M", 2), ("igea 8.6M", 3)]


def mesh(build, meshes, levels):
    base = os.path.join(meshes, "large", "igea.ply")
    if levels == 0:
        return base
    out = os.path.join(ROOT, "out", "perf-meshes", f"igea_L{levels}.ply")
    if not os.path.exists(out):
        os.makedirs(os.path.dirname(out), exist_ok=True)
        subprocess.run([os.path.join(build, "limn"), "subdivide", base, "-o", out, "--scheme",
                        "loop", "--levels", str(levels), "-q"], check=True)
    return out


def measure(build, meshes, max_size, stream_gbs=None, threads=2):
    limn = os.path.join(build, "limn")
    env = dict(os.environ, POCL_MAX_PTHREAD_COUNT=str(threads))
    rows = []
    with tempfile.TemporaryDirectory(prefix="limn_series_") as tmp:
        for label, levels in SIZES:
            if 134345 * 4 ** levels > max_size:
                break
            path = mesh(build, meshes, levels)
            den = os.path.join(tmp, "den.ply")
            for op, cmd in (
                ("denoise", [limn, "denoise", path, "-o", den, "--m", "2", "--steps", "3"]),
                ("morph", [limn, "morph", path, den, "-o", os.path.join(tmp, "f%02d.ply"),
                           "--frames", "4", "--m", "2"]),
            ):
                rep = os.path.join(tmp, "r.json")
                subprocess.run(cmd + ["--report", rep, "-q"], check=True, env=env)
                r = json.load(open(rep))
                n, nnz, prods = r["vertices"], r["stencil_nonzeros"], r["products"]
                sec = r["seconds"]["compute"]
                bytes_per_product = 12 * nnz + 4 * n + 4 * 32 * n
                gbs = bytes_per_product * prods / sec / 1e9 if sec > 0 else 0.0
                rows.append({"size": label, "op": op, "vertices": n, "products": prods,
                             "compute_s": sec, "mvertices_per_s": n / sec / 1e6,
                             "ns_per_vertex_product": sec / prods / n * 1e9, "gb_per_s": gbs,
                             "triad_fraction": gbs / stream_gbs if stream_gbs else ""})
    return rows


def print_table(rows, stream_gbs=None):
    print("| size | operation | products | compute s | M vertices / s | ns / vertex / product "
          "| GB/s | of triad |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        frac = f"{100 * r['triad_fraction']:.0f}%" if r["triad_fraction"] != "" else ""
        print(f"| {r['size']} | {r['op']} | {r['products']} | {r['compute_s']:.3f} "
              f"| {r['mvertices_per_s']:.1f} | {r['ns_per_vertex_product']:.1f} "
              f"| {r['gb_per_s']:.1f} | {frac} |")


def main():
    ap = scale_parser(__doc__)
    ap.add_argument("--stream-gbs", type=float, default=None,
                    help="STREAM triad GB/s (2 threads) to compare with")
    a = ap.parse_args()
    if not os.path.exists(os.path.join(a.build, "limn")):
        sys.exit(f"{a.build}/limn is missing: bash scripts/build.sh")
    print_table(measure(a.build, a.meshes, a.max_size, a.stream_gbs), a.stream_gbs)


if __name__ == "__main__":
    main()

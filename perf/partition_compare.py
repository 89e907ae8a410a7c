#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Partition: PT-Scotch and the Hilbert curve (distributed) against METIS (serial), 2, 4, 8 parts.

    bash scripts/build.sh -DLIMN_BUILD_PERF=ON && python3 perf/partition_compare.py

Runs perf/partition_compare under `mpirun -np P` (P = the part count; Open
MPI oversubscribed when P exceeds the cores) on the shared large and medium
meshes (or --mesh ...) and prints a Markdown table per mesh and part count:
edge cut, imbalance (largest part / mean) and seconds of each, and the ratio
of the cuts. METIS's seconds are rank 0's graph build and METIS; PT-Scotch's
are the whole collective call (edge exchange, graph, partition, halo of the
parts), the slowest rank's, with P ranks sharing the machine's cores. Wall
seconds and, in parentheses, CPU seconds of the process (PT-Scotch: the
busiest rank's; Open MPI's waiting in collectives counts as CPU too), and the
wall seconds of PT-Scotch's call spent on the edge exchange and adjacency.
--strategy picks PT-Scotch's (quality, the library's choice; default; speed).
The curve (mpi_sfc.c, the distributed pipeline's default): its cut, imbalance
and seconds (wall and CPU, the slowest and busiest rank's) beside them. Last,
the partition that would move no face (each rank's file slice of the faces,
each vertex to the lowest slice among its faces; not built): its cut against
METIS's and its imbalance, which say how spatial the file's face order is,
and the share of the faces that leave the rank reading them under the curve
(a face whose corners are not all in the reading rank's part is sent on).
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import perf_args  # noqa: E402


def runs(exe, meshes, parts, strategy):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    rows = []
    for p in parts:
        cmd = ["mpirun", "--oversubscribe", "--bind-to", "none", "-np", str(p), exe,
               "--strategy", strategy] + meshes
        out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
        rows += [json.loads(line) for line in out.splitlines() if line.startswith("{")]
    return rows


def main():
    ap = perf_args.scale_parser(__doc__)
    ap.add_argument("--parts", default="2,4,8")
    ap.add_argument("--strategy", default="quality", choices=["quality", "default", "speed"])
    ap.add_argument("--mesh", action="append", help="a mesh file (repeatable)")
    a = ap.parse_args()
    meshes = a.mesh or [os.path.join(a.meshes, sub, f)
                        for sub in ("large", "medium")
                        for f in sorted(os.listdir(os.path.join(a.meshes, sub)))
                        if f.endswith((".ply", ".obj", ".off"))]
    exe = os.path.join(a.build, "perf", "partition_compare")
    rows = runs(exe, meshes, [int(x) for x in a.parts.split(",")], a.strategy)
    rows.sort(key=lambda r: (r["mesh"], r["parts"]))
    print(f"PT-Scotch strategy: {a.strategy}\n")
    print("| mesh | vertices | parts | METIS cut | PT-Scotch cut | curve cut | Scotch / METIS "
          "| curve / METIS | METIS imbalance | PT-Scotch imbalance | curve imbalance "
          "| METIS s (CPU) | PT-Scotch s (CPU) | curve s (CPU) | face slices cut / METIS "
          "(imbalance) | faces sent on (curve) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        mc = r["metis_cut"]
        ratio = r["scotch_cut"] / mc if mc else float("nan")
        sratio = r["sfc_cut"] / mc if mc else float("nan")
        name = os.path.relpath(os.path.realpath(r["mesh"]), os.path.realpath(a.meshes))
        print(f"| {r['mesh'] if name.startswith('..') else name} "
              f"| {r['vertices']:,} | {r['parts']} | {mc:,} | {r['scotch_cut']:,} "
              f"| {r['sfc_cut']:,} | {ratio:.2f} | {sratio:.2f} "
              f"| {r['metis_imbalance']:.3f} | {r['scotch_imbalance']:.3f} "
              f"| {r['sfc_imbalance']:.3f} "
              f"| {r['metis_seconds']:.3f} ({r['metis_cpu']:.3f}) "
              f"| {r['scotch_seconds']:.3f} ({r['scotch_cpu']:.3f}) "
              f"| {r['sfc_seconds']:.3f} ({r['sfc_cpu']:.3f}) "
              f"| {r['slices_cut'] / mc if mc else float('nan'):.2f} "
              f"({r['slices_imbalance']:.3f}) | {100 * r['sfc_faces_travel']:.1f}% |")

if __name__ == "__main__":
    main()

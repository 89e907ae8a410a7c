#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""CPU time under named functions, split by what each calls directly.

Reads `perf record --call-graph fp` files (a build with frame pointers:
-DCMAKE_C_FLAGS="-fno-omit-frame-pointer -mno-omit-leaf-frame-pointer"), one
per run of the same command. For each function named with -f, every sample
whose stack holds it is counted under the frame just below it ("(self)" when
the sample is in the function itself), and the counts are given as ms a run
at the sampling rate. Inlined static functions count as their caller's self.
docs/mpi.md "Set-up, 2026-12-06 (session 22)" was measured with it:

    perf record -F 8000 --call-graph fp -o r1.data limn interpolate F -o O
    python3 perf/perf_callers.py --hz 8000 r1.data r2.data r3.data \\
        -f limn_mpi_mesh_repair -f mpi_local_mesh_build
"""
import argparse
import collections
import subprocess
import sys


def stacks(path):
    """Each sample's stack, outermost frame first."""
    out = subprocess.run(["perf", "script", "-i", path, "-F", "ip,sym"],
                         capture_output=True, text=True, check=True).stdout
    for block in out.split("\n\n"):
        frames = []
        for line in block.strip().split("\n"):
            parts = line.split(None, 1)
            if parts:
                frames.append(parts[1].split("+")[0] if len(parts) > 1 else "?")
        if frames:
            yield frames[::-1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="+", help="perf.data files, one per run")
    ap.add_argument("-f", "--function", action="append", required=True,
                    help="a function to split (repeatable)")
    ap.add_argument("--hz", type=float, required=True, help="perf record's -F")
    ap.add_argument("--top", type=int, default=14, help="callees shown per function")
    args = ap.parse_args()
    below = {f: collections.Counter() for f in args.function}
    for path in args.files:
        for chain in stacks(path):
            for f in args.function:
                if f in chain:
                    i = chain.index(f)
                    below[f][chain[i + 1] if i + 1 < len(chain) else "(self)"] += 1
    ms = 1000.0 / args.hz / len(args.files)
    for f in args.function:
        print(f"== {f}: {sum(below[f].values()) * ms:.1f} ms a run")
        for callee, n in below[f].most_common(args.top):
            print(f"   {n * ms:8.1f} ms  {callee}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

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

With --stages the set-up's CPU is split instead: every sample under one of
the --within functions (default: the set-up of `limn interpolate`, one
process's or a rank's) counts under the innermost --stages function on its
stack, "(other)" when none, and a sample in a page fault counts under
"(page faults)" whatever its stage, so CPU work and fresh memory are apart.
docs/mpi.md "Set-up CPU by stage (session 29)":

    python3 perf/perf_callers.py --hz 8000 r1.data r2.data --stages \\
        topology_build,stencil_build,ply_read,slice_ply_read,mpi_sfc_partition
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


# `limn interpolate`'s set-up: one process's load and operator, a rank's
# sliced read (read, partition, distribution, repair) and local rows
SETUP = "cli_load_mesh,operator_build_ex,read_sliced,mpi_mesh_build_rows"


def stage_split(files, stages, within, hz):
    """ms a run of the set-up by innermost stage, page faults apart."""
    count = collections.Counter()
    for path in files:
        for chain in stacks(path):
            if not any(f.split(".")[0] in within for f in chain):
                continue
            if "asm_exc_page_fault" in chain or chain[-1] == "clear_page_erms":
                count["(page faults)"] += 1
                continue
            count[next((f for f in reversed(chain) if f.split(".")[0] in stages), "(other)")] += 1
    ms = 1000.0 / hz / len(files)
    print(f"set-up {sum(count.values()) * ms:.0f} ms a run: " +
          ", ".join(f"{k} {n * ms:.0f}" for k, n in count.most_common()))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="+", help="perf.data files, one per run")
    ap.add_argument("-f", "--function", action="append",
                    help="a function to split (repeatable)")
    ap.add_argument("--stages", help="comma-separated stages: split the set-up's CPU by them")
    ap.add_argument("--within", default=SETUP,
                    help=f"--stages: the set-up's outermost functions (default {SETUP})")
    ap.add_argument("--hz", type=float, required=True, help="perf record's -F")
    ap.add_argument("--top", type=int, default=14, help="callees shown per function")
    args = ap.parse_args()
    if args.stages:
        stage_split(args.files, set(args.stages.split(",")), set(args.within.split(",")),
                    args.hz)
        return 0
    if not args.function:
        ap.error("-f or --stages is needed")
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

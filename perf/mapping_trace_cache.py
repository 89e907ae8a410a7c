#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""What a freed-block cache would save a rank, from its mapping trace
(docs/mpi.md "Set-up, 2026-12-07 (session 28)"). Record rank 0's large
mappings with their callers, then replay them:

    mpirun -np 2 --bind-to core sh -c 'if [ $OMPI_COMM_WORLD_RANK = 0 ]; then
        exec strace -k -e trace=mmap,munmap -o /tmp/rank0.trace build/limn interpolate
        /tmp/limn_read_bench/scanner_l2_f32.ply -o /tmp/out.ply --precision double -q; fi;
        exec build/limn interpolate /tmp/limn_read_bench/scanner_l2_f32.ply -o /tmp/out.ply
        --precision double -q'
    python3 perf/mapping_trace_cache.py /tmp/rank0.trace

Anonymous mappings of 4 MiB or more are counted, less the MPI and PoCL
threads' stacks and malloc arenas. The set-up ends at the first mapping made
under the solve (mpi_interpolate_rows, PoCL, or the results' blocks). Three
replays: as traced; with a cache that keeps each freed block while the live
and kept bytes stay under the high-water mark of live bytes so far, serving
a request from the smallest kept block large enough; and the same with the
largest kept block grown (mremap) when none is. Prints MiB mapped fresh in
the run and in the set-up, and the high-water mark. Mapped, not resident,
bytes: perf/freed_block_cache.sh measures the real thing.

    python3 perf/mapping_trace_cache.py /tmp/rank0.trace \
        --scope mpi_sfc_partition,topology_build

replays instead a pool scoped to one stretch of the run (docs/mpi.md "Set-up
at the VM's own page-reporting order (session 30)"): from the first mapping
made under FIRST to the first made under LAST every freed block is kept for
the later requests (no bound: all are released at LAST, before the peak the
topology and stencils make, so the peak cannot rise); outside it nothing is.
"""
import argparse
import re

MAP = re.compile(r"^mmap\((\S+), (\d+), [^)]*MAP_ANONYMOUS[^)]*\) = (0x[0-9a-f]+)")
UNMAP = re.compile(r"^munmap\((0x[0-9a-f]+), (\d+)\)")
FRAME = re.compile(r"\(([A-Za-z_][A-Za-z0-9_.]*)\+")
BIG = 4 << 20
NOT_LIMN = ("pthread_create", "new_heap", "arena_get2")
SOLVE = ("mpi_interpolate_rows", "pocl", "results_to_blocks")


def events(path):
    """(+/-, address, bytes, caller frames) of the large mappings."""
    lines = open(path).read().split("\n")
    out, live, i = [], {}, 0
    while i < len(lines):
        line, j, frames = lines[i], i + 1, []
        while j < len(lines) and lines[j].startswith(" >"):
            m = FRAME.search(lines[j])
            if m:
                frames.append(m.group(1))
            j += 1
        m = MAP.search(line)
        if m and int(m.group(2)) >= BIG and not any(f in s for s in frames for f in NOT_LIMN):
            live[m.group(3)] = int(m.group(2))
            out.append(("+", m.group(3), live[m.group(3)], frames))
        m = UNMAP.search(line)
        if m and m.group(1) in live:
            out.append(("-", m.group(1), live.pop(m.group(1)), frames))
        i = j
    return out


def replay(ev, setup_end, mode, scope=None):
    """MiB mapped fresh (run, set-up) and the live high-water mark; mode 0
    as traced, 1 best-fit reuse, 2 best fit or the largest kept grown;
    scope (first, last): reuse only for events [first, last), unbounded."""
    cache, live, cur, high, fresh, fresh_setup = [], {}, 0, 0, 0, 0
    for k, (sign, addr, size, _) in enumerate(ev):
        pooled = mode and (scope is None or scope[0] <= k < scope[1])
        if scope is not None and k == scope[1]:
            cache.clear()
        if sign == "-":
            cur -= live.pop(addr)
            if pooled:
                cache.append(size)
            continue
        block = None
        if pooled:
            fits = [c for c in cache if c >= size]
            if fits:
                block = min(fits)
            elif cache and mode == 2:
                block = max(cache)
        if block is not None:
            cache.remove(block)
        new = size if block is None else max(0, size - block)
        fresh += new
        fresh_setup += new if k < setup_end else 0
        live[addr] = size
        cur += size
        high = max(high, cur)
        while scope is None and cache and cur + sum(cache) > high:
            cache.remove(min(cache))
    return fresh >> 20, fresh_setup >> 20, high >> 20


def first_under(ev, names, what):
    """The index of the first mapping made under one of names (a frame of
    that name, or its compiler's clone: name.constprop.0)."""
    k = next((k for k, e in enumerate(ev) if e[0] == "+" and any(f.split(".")[0] in names
                                                                   for f in e[3])), None)
    if k is None:
        raise SystemExit(f"no mapping of 4 MiB or more under {what} in the trace")
    return k


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("trace", help="strace -k output of one rank (see the docstring)")
    ap.add_argument("--scope", metavar="FIRST,LAST",
                    help="pool freed blocks only from the first mapping under function FIRST "
                         "to the first under LAST, releasing them there")
    args = ap.parse_args()
    ev = events(args.trace)
    setup_end = next((k for k, e in enumerate(ev) if any(s in f for f in e[3] for s in SOLVE)),
                     len(ev))
    scope = None
    if args.scope:
        names = args.scope.split(",")
        if len(names) != 2 or not all(names):
            ap.error("--scope takes two function names: FIRST,LAST")
        scope = (first_under(ev, [names[0]], names[0]), first_under(ev, [names[1]], names[1]))
        if scope[0] >= scope[1]:
            ap.error(f"--scope: the first mapping under {names[0]} comes after {names[1]}'s")
    for mode, name in enumerate(("as traced", "pool, best fit", "pool, best fit or grown")
                                if scope else
                                ("as traced", "cache, best fit", "cache, best fit or grown")):
        run, setup, high = replay(ev, setup_end, mode, scope)
        print(f"{name:26s}: {run:5d} MiB mapped in the run, {setup:5d} in the set-up; "
              f"live high-water {high} MiB")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The whole job side by side, in one run, on the 2.1M and 8.6M float32 PLYs.

igea refined twice (2.1M vertices) and three times (8.6M), written as scanners
write it (binary little endian, float32 x y z, `uchar int` face lists): limn's
stages (`limn interpolate --report`), `limn info` and `limn subdivide --levels 1`
wall times, `trimesh.load(process=False)` (with --python), OpenSubdiv's
TopologyRefinerFactory creation (perf/osd_refine, 0 levels) and its limit
stencil table (perf/osd_iteration, where it finishes within --osd-timeout),
and the floor: reading the file from the page cache, and the solve loop's
bytes over the triad `limn bench` measures on the same device.

Beside each of issue 13's targets it prints the floor this machine allows,
measured in the same run: bytes a stage must write to fresh memory over the
first-touch rate (perf/first_touch: a memset of newly mapped pages, the
faster of 4 KiB pages and pages advised for transparent huge pages, as limn's
large blocks are), file bytes over the page-cache read rate, the loop's
bytes over the triad, an output's bytes written and fsync'ed in the
output's directory (limn's outputs are durable before their rename). A
target below its floor cannot be met here without touching less fresh
memory or writing less (docs/performance.md "The whole job, end to end").

  python3 perf/end_to_end.py [--python VENV/bin/python] [--json out.json] [--only 2.1M]
                             [--repeat 3]

Needs a build with -DLIMN_BUILD_PERF=ON for the OpenSubdiv rows (left out
with a note otherwise); --python: an interpreter with trimesh and numpy
(pip install trimesh numpy). The 8.6M file needs ~6 GB of RAM."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TRIMESH = "import sys, time, trimesh\nt = time.perf_counter()\n" \
          "m = trimesh.load(sys.argv[1], process=False)\n" \
          "print(time.perf_counter() - t, len(m.vertices))\n"


def wall(cmd, timeout=3600):
    t = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       timeout=timeout)
    return time.perf_counter() - t, r


def make_inputs(a):
    """The scanner-layout PLYs, made the way perf/read_bench.py makes them."""
    limn, conv = os.path.join(a.build, "limn"), os.path.join(a.build, "perf", "read_bench")
    files = {}
    for name, levels, path in (("2.1M", 2, "/tmp/limn_read_bench/scanner_l2_f32.ply"),
                               ("8.6M", 3, "/tmp/limn_e2e/scanner_l3_f32.ply")):
        if a.only and name not in a.only:
            continue
        if not os.path.exists(path):
            os.makedirs(os.path.dirname(path), exist_ok=True)
            refined = os.path.join(os.path.dirname(path), "igea_l%d.ply" % levels)
            if not os.path.exists(refined):
                subprocess.run([limn, "subdivide", "--levels", str(levels), a.mesh, "-o",
                                refined, "-q"], check=True)
            subprocess.run([conv, "--scanner", refined, path], check=True)
        files[name] = path
    return files


def floor_read(path):
    best = 1e300
    for _ in range(3):
        t = time.perf_counter()
        with open(path, "rb") as f:
            while f.read(1 << 24):
                pass
        best = min(best, time.perf_counter() - t)
    return best


def floor_write(directory, nbytes):
    """Seconds to write nbytes to a new file in directory and fsync it, best of
    two: limn syncs every output before its rename (docs/cli.md, the Outputs bullet),
    so no write of that file can take less on this disk."""
    block = os.urandom(1 << 24)
    path, best = os.path.join(directory, "floor_write.bin"), 1e300
    for _ in range(2):
        t = time.perf_counter()
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        try:
            left = nbytes
            while left > 0:
                left -= os.write(fd, block[:min(left, len(block))])
            os.fsync(fd)
        finally:
            os.close(fd)
        best = min(best, time.perf_counter() - t)
        os.remove(path)
    return best


def ply_counts(path):
    """Vertex and face counts from a PLY header."""
    counts = {}
    with open(path, "rb") as f:
        for line in f:
            w = line.split()
            if w[:1] == [b"element"]:
                counts[w[1].decode()] = int(w[2])
            if w[:1] == [b"end_header"]:
                break
    return counts.get("vertex", 0), counts.get("face", 0)


def first_touch(a):
    """Fresh-memory and touched-memory write rates (bytes/s), or None."""
    exe = os.path.join(a.build, "perf", "first_touch")
    if not os.path.exists(exe):
        return None
    j = json.loads(subprocess.run([exe], stdout=subprocess.PIPE, text=True,
                                  check=True).stdout)
    # limn's large blocks are advised for transparent huge pages
    # (host/base/large_alloc.c): their fresh bytes come at the advised rate,
    # where it is the faster
    huge = j.get("huge_first_touch_gb_per_s", 0.0) * 1e9
    return {"first_touch": max(j["first_touch_gb_per_s"] * 1e9, huge),
            "first_touch_small_pages": j["first_touch_gb_per_s"] * 1e9,
            "first_touch_huge_pages": huge,
            "touched": j["touched_gb_per_s"] * 1e9}


def mesh_bytes(vertices, faces, corners):
    """A limn mesh in memory: double positions, uint32 face offsets and indices."""
    return 24 * vertices + 4 * (faces + 1) + 4 * faces * corners


def floors(row, report, rates):
    """The floor of each target's figure, seconds (module docstring)."""
    n, nf, nnz = report["vertices"], report["faces"], report["stencil_nonzeros"]
    corners = 3 if report["scheme"] == "loop" else 4
    touch = rates["first_touch"]
    read = row["floor_read"]
    faces = mesh_bytes(0, nf, corners)
    # the solve outside its loop: M and P as 4 doubles a row, the float
    # weights of a mixed solve, and the control mesh's faces (its positions
    # are P's memory)
    setup = 64 * n + (4 * nnz if report.get("products_float") else 0) + faces
    row["fresh_bytes"] = {"solve_setup": setup, "mesh": mesh_bytes(n, nf, corners),
                          "table": 12 * nnz + 4 * (n + 1)}
    out_n, out_f = row["subdivide1_counts"]
    subdivide = mesh_bytes(n, nf, corners) + mesh_bytes(out_n, out_f, corners)
    fresh = row["fresh_bytes"]
    return {"solve_setup": setup / touch,
            "interpolate": read + row["floor_loop"] + (fresh["mesh"] + fresh["table"] + setup)
            / touch + row["floor_write_interpolate"],
            "info": read + fresh["mesh"] / touch,
            "subdivide1": read + subdivide / touch + row["floor_write_subdivide1"]}


def limn_rows(a, path, tmp):
    limn = os.path.join(a.build, "limn")
    rep, out = os.path.join(tmp, "r.json"), os.path.join(tmp, "o.ply")
    t, r = wall([limn, "interpolate", path, "-o", out, "--report", rep, "-q"])
    if r.returncode:
        sys.exit("limn interpolate failed: " + r.stderr)
    j = json.load(open(rep))
    out_bytes = os.path.getsize(out)
    row = {"vertices": j["vertices"], "interpolate_wall": t, "seconds": j["seconds"],
           "peak_bytes_per_vertex": j["peak_rss_bytes"] / j["vertices"],
           "method": j["method"], "products": j["products"],
           "products_float": j.get("products_float", 0), "stencil_nonzeros": j["stencil_nonzeros"],
           "output_file_bytes": out_bytes}
    # the two sides of the info target, limn info and trimesh.load, as the
    # median of --repeat runs each: this VM's fresh memory makes one run vary
    row["info_walls"] = [wall([limn, "info", path])[0] for _ in range(a.repeat)]
    row["info_wall"] = statistics.median(row["info_walls"])
    row["subdivide1_wall"], _ = wall([limn, "subdivide", path, "-o", out, "--levels", "1", "-q"])
    row["subdivide1_counts"] = ply_counts(out)
    row["subdivide1_file_bytes"] = os.path.getsize(out)
    os.remove(out)
    return row, j


def anchors(a, path, row):
    if a.python:
        loads = []
        for _ in range(a.repeat):
            r = subprocess.run([a.python, "-c", TRIMESH, path], stdout=subprocess.PIPE, text=True)
            if r.returncode == 0:
                loads.append(float(r.stdout.split()[0]))
        row["trimesh_loads"] = loads
        row["trimesh_load"] = statistics.median(loads) if loads else None
    perf = os.path.join(a.build, "perf")
    for key, cmd in (("osd_refiner", [os.path.join(perf, "osd_refine"), path, "0", "loop"]),
                     ("osd_stencils", [os.path.join(perf, "osd_iteration"), path, "loop"])):
        if not os.path.exists(cmd[0]):
            row[key] = None
            continue
        try:
            _, r = wall(cmd, timeout=a.osd_timeout)
            j = json.loads(r.stdout.strip().splitlines()[-1]) if r.returncode == 0 else {}
            row[key] = j.get("seconds_topology", j.get("seconds_stencils"))
        except (subprocess.TimeoutExpired, ValueError, IndexError):
            row[key] = None  # did not finish within --osd-timeout


def loop_floor(a, report, tmp):
    """Bytes the loop moves over the triad limn bench measures on this device."""
    js = os.path.join(tmp, "b.json")
    subprocess.run([os.path.join(a.build, "limn"), "bench", "--vertices", "20k", "-q",
                    "--json", js], check=True)
    triad = json.load(open(js))["triad"]["gb_per_s"]
    sys.path.insert(0, os.path.join(ROOT, "perf"))
    from run_suite import solve_bytes  # the one byte model (docs/performance.md)
    return solve_bytes(report) / (triad * 1e9), triad


def fmt(v):
    return "–" if v is None else "%.2f" % v


def target_rows(r):
    """(target, figure, bound, floor) per issue-13 target; None where not measured."""
    s, fl, tm = r["seconds"], r.get("floors") or {}, r.get("trimesh_load")
    times = lambda k: None if tm is None else k * tm
    return [("solve outside the loop <= 0.25 x loop", s["solve"] - s["iterations"],
             0.25 * s["iterations"], fl.get("solve_setup")),
            ("interpolate end to end <= 1.5 x trimesh.load", r["interpolate_wall"], times(1.5),
             fl.get("interpolate")),
            ("limn info <= 2 x trimesh.load", r["info_wall"], times(2), fl.get("info")),
            ("subdivide --levels 1 <= 2 x trimesh.load", r["subdivide1_wall"], times(2),
             fl.get("subdivide1")),
            ("peak bytes a vertex <= 350 (Loop)", r["peak_bytes_per_vertex"], 350.0, None)]


def verdict(figure, bound, floor):
    if bound is None:
        return "not measured"
    met = "met" if figure <= bound else "missed"
    if floor is not None and floor > bound:
        met += ": the floor exceeds the target by %.1fx" % (floor / bound)
    return met


def print_targets(rows):
    for name, r in rows.items():
        print("\n%s: target | figure | target value | floor on this machine | verdict" % name)
        print("|---|---:|---:|---:|---|")
        for label, figure, bound, floor in target_rows(r):
            print("| %s | %s | %s | %s | %s |" % (label, fmt(figure), fmt(bound), fmt(floor),
                                                  verdict(figure, bound, floor)))
        print("limn info runs: %s s; trimesh.load runs: %s s (the medians above)"
              % (", ".join("%.2f" % x for x in r["info_walls"]),
                 ", ".join("%.2f" % x for x in r.get("trimesh_loads", [])) or "–"))
        t = r.get("rates")
        if t:
            print("first touch %.2f GB/s (4 KiB pages %.2f, huge pages %.2f), touched %.2f "
                  "GB/s, page cache read %.2f GB/s, triad %.2f GB/s"
                  % (t["first_touch"] / 1e9, t["first_touch_small_pages"] / 1e9,
                     t["first_touch_huge_pages"] / 1e9, t["touched"] / 1e9,
                     r["file_bytes"] / r["floor_read"] / 1e9, r["triad_gb_per_s"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--mesh", default=os.path.join(ROOT, "..", "shared", "meshes", "large",
                                                   "igea.ply"))
    ap.add_argument("--python", help="an interpreter with trimesh and numpy")
    ap.add_argument("--json", help="also write every figure here")
    ap.add_argument("--only", nargs="*", help="2.1M and/or 8.6M (default both)")
    ap.add_argument("--osd-timeout", type=float, default=300)
    ap.add_argument("--repeat", type=int, default=3,
                    help="runs of limn info and of trimesh.load, the median kept (default 3)")
    a = ap.parse_args()
    rows = {}
    with tempfile.TemporaryDirectory(prefix="limn_e2e_") as tmp:
        for name, path in make_inputs(a).items():
            row, report = limn_rows(a, path, tmp)
            row["floor_read"] = floor_read(path)
            row["floor_loop"], row["triad_gb_per_s"] = loop_floor(a, report, tmp)
            row["file_bytes"] = os.path.getsize(path)
            row["floor_write_interpolate"] = floor_write(tmp, row["output_file_bytes"])
            row["floor_write_subdivide1"] = floor_write(tmp, row["subdivide1_file_bytes"])
            row["rates"] = first_touch(a)
            row["floors"] = floors(row, report, row["rates"]) if row["rates"] else None
            anchors(a, path, row)
            rows[name] = row
    s = lambda r, k: r["seconds"].get(k)
    lines = [("limn interpolate, end to end", lambda r: r["interpolate_wall"]),
             ("  load (read + repair)", lambda r: s(r, "load")),
             ("  topology", lambda r: s(r, "topology")), ("  stencil", lambda r: s(r, "stencil")),
             ("  solve", lambda r: s(r, "solve")), ("  of which the loop", lambda r: s(r, "iterations")),
             ("  OpenCL set-up", lambda r: s(r, "opencl_setup")), ("  write", lambda r: s(r, "write")),
             ("peak bytes a vertex", lambda r: r["peak_bytes_per_vertex"]),
             ("limn info", lambda r: r["info_wall"]),
             ("limn subdivide --levels 1", lambda r: r["subdivide1_wall"]),
             ("trimesh.load(process=False)", lambda r: r.get("trimesh_load")),
             ("OpenSubdiv TopologyRefinerFactory", lambda r: r.get("osd_refiner")),
             ("OpenSubdiv limit stencil table", lambda r: r.get("osd_stencils")),
             ("floor: read the file (page cache)", lambda r: r["floor_read"]),
             ("floor: loop bytes / triad", lambda r: r["floor_loop"]),
             ("floor: solve outside the loop (fresh bytes / first touch)",
              lambda r: (r.get("floors") or {}).get("solve_setup")),
             ("floor: write + fsync interpolate's output", lambda r: r["floor_write_interpolate"]),
             ("floor: write + fsync subdivide's output", lambda r: r["floor_write_subdivide1"])]
    names = list(rows)
    print("| seconds | " + " | ".join("%s (%d vertices)" % (n, rows[n]["vertices"]) for n in names) + " |")
    print("|---|" + "---:|" * len(names))
    for label, get in lines:
        print("| %s | %s |" % (label, " | ".join(fmt(get(rows[n])) for n in names)))
    print_targets(rows)
    if not a.python:
        print("\ntrimesh.load: not measured (give --python VENV/bin/python with trimesh)")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()

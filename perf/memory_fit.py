#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""limn interpolate's memory estimate against measured peaks, and the
coefficients a fit to those peaks gives (host/solve/interpolate_estimate.c,
docs/robustness.md "Memory"). Makes the meshes by refining shared ones, runs
`limn interpolate --report` for each method and precision on each backend,
and reads `estimated_bytes` and `peak_rss_bytes` from each report:

    bash scripts/build.sh -DLIMN_BUILD_PERF=ON
    python3 perf/memory_fit.py              # the seven meshes of the fit (~40 min)
    python3 perf/memory_fit.py --quick      # two meshes under 0.6M vertices (~2 min)

Prints one row a run (peak / estimate: at most 1 means the estimate held) and
per method class the least (B a vertex, B an entry >= 12) with
1.1 (a V + c entries) + 96 MiB above every peak, the rule the table in
interpolate_estimate.c was fitted by. The entries are V + sum over faces of
d (d - 2): the meshes are refined, so all triangles (Loop) or all quads
(Catmull-Clark). Writes out/memory_fit.csv. Peaks depend on the machine's
allocator and OpenCL runtime: refit where those differ.
"""
import csv
import itertools
import json
import os
import re
import subprocess
import sys
import tempfile

from perf_args import ROOT, scale_parser

MIB = 1 << 20
RUNTIME = 96 * MIB
MARGIN = 1.1
MIN_ENTRY_BYTES = 12.0
FLOAT_MIN_VERTICES = 200000  # SOLVE_FLOAT_MIN_VERTICES: auto runs float from here

# name: (shared mesh, levels, written as)
CASES = {
    "igea2_f32": ("large/igea.ply", 2, "scanner"),
    "igea2_obj": ("large/igea.ply", 2, "obj"),
    "bob4": ("medium/bob_quad.obj", 4, "ply"),
    "fertility5": ("medium/fertility.off", 5, "ply"),
    "spot5": ("small/spot_quadrangulated.obj", 5, "ply"),
    "bunny3_holes": ("medium/bun_zipper.ply", 3, "ply"),
    "igea3_f32": ("large/igea.ply", 3, "scanner"),
}
QUICK = {
    "igea1_f32": ("large/igea.ply", 1, "scanner"),
    "bob3": ("medium/bob_quad.obj", 3, "ply"),
}
# (method, precision) as given on the command line
CONFIGS = [("auto", "auto"), ("auto", "double"), ("paper", "auto"), ("paper", "double"),
           ("weighted", "auto"), ("weighted", "double"), ("cg", "auto"), ("sgs", "auto")]
CLASSES = ["chebyshev double", "chebyshev float", "paper/weighted double",
           "paper/weighted float", "cg", "sgs"]
ESTIMATE_SOURCE = os.path.join(ROOT, "host", "solve", "interpolate_estimate.c")


def current_table():
    """interpolate_estimate.c's {B a vertex, B an entry} rows, in CLASSES' order."""
    with open(ESTIMATE_SOURCE) as f:
        text = f.read()
    body = text[text.index("fitted[6][2] = {"):]
    body = body[:body.index("};")]
    rows = re.findall(r"\{([0-9.]+), ([0-9.]+)\}", body)
    if len(rows) != len(CLASSES):
        sys.exit(f"cannot read the table of {ESTIMATE_SOURCE}")
    return [(float(x), float(y)) for x, y in rows]


def estimate_class(method, precision, vertices):
    """The row of interpolate_estimate.c's table a run is estimated by."""
    if method in ("cg", "sgs"):
        return CLASSES.index(method)
    single = precision == "float" or (precision == "auto" and vertices >= FLOAT_MIN_VERTICES)
    return 2 * (method in ("paper", "weighted")) + single


def make_mesh(a, limn, work, name, case):
    source, levels, kind = case
    out = os.path.join(work, name + (".obj" if kind == "obj" else ".ply"))
    if os.path.exists(out):
        return out
    refined = out if kind != "scanner" else os.path.join(work, name + "_double.ply")
    subprocess.run([limn, "subdivide", os.path.join(a.meshes, source), "--levels",
                    str(levels), "-o", refined, "-q"], check=True)
    if kind == "scanner":  # float32 positions, uchar int lists, as scanners write
        subprocess.run([os.path.join(a.build, "perf", "read_bench"), "--scanner", refined,
                        out], check=True)
        os.remove(refined)
    return out


def run(limn, mesh, work, method, precision, device):
    report = os.path.join(work, "report.json")
    cmd = [limn, "interpolate", mesh, "-o", os.path.join(work, "control.ply"), "-q",
           "--report", report, "--method", method, "--precision", precision,
           "--device", device, "--max-memory", "1T"]
    subprocess.run(cmd, check=True)
    with open(report) as f:
        r = json.load(f)
    per_face = 3 if r["scheme"] == "loop" else 8  # d (d - 2): triangles or quads
    entries = r["vertices"] + per_face * r["faces"]
    return r, entries


def fit(points):
    """The least (a, c) by sum of predictions with MARGIN (a V + c E) + RUNTIME
    >= peak at every (V, E, peak), c >= MIN_ENTRY_BYTES, a >= 0: a linear
    program in two unknowns, solved at the corners of its region."""
    lines = [(v, e, (p - RUNTIME) / MARGIN) for v, e, p in points]  # a v + c e >= rhs
    lines += [(0.0, 1.0, MIN_ENTRY_BYTES), (1.0, 0.0, 0.0)]

    def feasible(a, c):
        return all(a * v + c * e >= rhs * (1 - 1e-12) - 1e-6 for v, e, rhs in lines)

    sv = sum(v for v, _, _ in points)
    se = sum(e for _, e, _ in points)
    best = None
    for (v1, e1, r1), (v2, e2, r2) in itertools.combinations(lines, 2):
        det = v1 * e2 - v2 * e1
        if abs(det) < 1e-9 * max(1.0, abs(v1 * e2)):
            continue
        a_ = (r1 * e2 - r2 * e1) / det
        c_ = (v1 * r2 - v2 * r1) / det
        if a_ >= 0 and c_ >= 0 and feasible(a_, c_):
            cost = a_ * sv + c_ * se
            if best is None or cost < best[0]:
                best = (cost, a_, c_)
    return (best[1], best[2]) if best else None


def main():
    ap = scale_parser(__doc__)
    ap.add_argument("--quick", action="store_true",
                    help="two small meshes (a smoke test of the script, not a fit)")
    ap.add_argument("--cases", help="comma-separated names of CASES")
    ap.add_argument("--devices", default="opencl,reference")
    ap.add_argument("--work", help="keep the meshes here (default: a temporary folder)")
    ap.add_argument("--csv", default=os.path.join(ROOT, "out", "memory_fit.csv"))
    a = ap.parse_args()
    limn = os.path.join(a.build, "limn")
    if not os.path.exists(os.path.join(a.build, "perf", "read_bench")):
        sys.exit("perf/read_bench is missing: bash scripts/build.sh -DLIMN_BUILD_PERF=ON")
    cases = QUICK if a.quick else CASES
    if a.cases is not None:
        every = {**CASES, **QUICK}
        names = [n for n in a.cases.split(",") if n]
        unknown = [n for n in names if n not in every]
        if unknown or not names:
            sys.exit(f"--cases {a.cases!r}: " + (f"no case named {', '.join(unknown)}; "
                                                 if unknown else "no case given; ")
                     + f"the cases are {', '.join(every)}")
        cases = {n: every[n] for n in names}
    devices = [d for d in a.devices.split(",") if d]
    if not devices or any(d != "reference" and d.split(":")[0] != "opencl" for d in devices):
        sys.exit(f"--devices {a.devices!r}: give limn's --device specs (reference, opencl, "
                 "opencl:P.D, opencl:NAME), comma-separated")
    work = a.work or tempfile.mkdtemp(prefix="limn_memory_fit_")
    os.makedirs(work, exist_ok=True)
    rows = []
    print("| mesh | vertices | entries | method | precision | device | class | peak MiB "
          "| estimate MiB | peak / estimate |")
    print("|---|---:|---:|---|---|---|---|---:|---:|---:|")
    for name, case in cases.items():
        mesh = make_mesh(a, limn, work, name, case)
        for device in devices:
            for method, precision in CONFIGS:
                r, entries = run(limn, mesh, work, method, precision, device)
                k = estimate_class(method, precision, r["vertices"])
                peak, est = r["peak_rss_bytes"], r["estimated_bytes"]
                rows.append(dict(mesh=name, vertices=r["vertices"], entries=entries,
                                 method=method, precision=precision, device=device,
                                 ran=f'{r["method"]} {r["precision"]}', cls=CLASSES[k],
                                 peak=peak, estimate=est))
                print(f"| {name} | {r['vertices']} | {entries} | {method} | {precision} | "
                      f"{device} | {CLASSES[k]} | {peak / MIB:.0f} | {est / MIB:.0f} | "
                      f"{peak / est:.2f} |", flush=True)
    os.makedirs(os.path.dirname(a.csv), exist_ok=True)
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("\n| class | runs | peak / estimate | B a vertex, B an entry: now | fitted here |")
    print("|---|---:|---|---|---|")
    held, current = True, current_table()
    for k, cls in enumerate(CLASSES):
        mine = [x for x in rows if x["cls"] == cls]
        if not mine:
            continue
        ratios = [x["peak"] / x["estimate"] for x in mine]
        held &= max(ratios) <= 1.0
        got = fit([(x["vertices"], x["entries"], x["peak"]) for x in mine])
        fitted = f"{got[0]:.0f}, {got[1]:.0f}" if got else "-"
        print(f"| {cls} | {len(mine)} | {min(ratios):.2f}-{max(ratios):.2f} | "
              f"{current[k][0]:.0f}, {current[k][1]:.0f} | {fitted} |")
    print(f"\n{len(rows)} runs, csv in {a.csv}; the estimate "
          + ("held on every run" if held else "fell BELOW a measured peak"))
    return 0 if held else 1


if __name__ == "__main__":
    sys.exit(main())

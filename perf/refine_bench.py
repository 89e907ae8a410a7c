#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Uniform refinement: limn subdivide vs OpenSubdiv's Far refinement of the
same mesh, side by side in one run (each in its own process, so peak memory is
per implementation), plus limn's level-by-level tables against one composed
("factorised") table. Needs a build with -DLIMN_BUILD_PERF=ON:

    bash scripts/build.sh -DLIMN_BUILD_PERF=ON
    python3 perf/refine_bench.py [--cases igea2,igea3,bob3,bob4] [--limit]

Writes out/refine_bench.csv. Timings are wall-clock: compare ratios.
"""
import argparse
import json
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = {
    "igea2": ("large/igea.ply", 2, "loop"),
    "igea3": ("large/igea.ply", 3, "loop"),
    "bob3": ("medium/bob_quad.obj", 3, "catmark"),
    "bob4": ("medium/bob_quad.obj", 4, "catmark"),
}


def run_json(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(r.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--meshes", default=os.environ.get(
        "LIMN_SHARED_MESHES", os.path.join(ROOT, "..", "shared", "meshes")))
    ap.add_argument("--cases", default="igea2,igea3,bob3,bob4")
    ap.add_argument("--device", default="opencl")
    ap.add_argument("--csv", default=os.path.join(ROOT, "out", "refine_bench.csv"))
    a = ap.parse_args()
    limn = os.path.join(a.build, "limn")
    osd = os.path.join(a.build, "perf", "osd_refine")
    factor = os.path.join(a.build, "perf", "refine_factor")
    tmp = tempfile.mkdtemp(prefix="limn_refine_")
    rows = []
    for name in a.cases.split(","):
        rel, levels, scheme = CASES[name]
        mesh = os.path.join(a.meshes, rel)
        rep = os.path.join(tmp, "r.json")
        subprocess.run([limn, "subdivide", mesh, "-o", os.path.join(tmp, "s.ply"), "-q",
                        "--levels", str(levels), "--scheme", scheme, "--device", a.device,
                        "--report", rep], check=True)
        with open(rep) as f:
            lj = json.load(f)
        oj = run_json([osd, mesh, str(levels), scheme])
        fj = run_json([factor, mesh, str(levels), scheme])
        rows.append((rel, levels, scheme, lj, oj, fj))

    print("| mesh | scheme | levels | output vertices | limn s (plan + apply) | OpenSubdiv s "
          "(refine + interpolate) | limn peak MiB | OpenSubdiv peak MiB | limn estimate MiB |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for rel, levels, scheme, lj, oj, fj in rows:
        ls = lj["seconds"]["plan"] + lj["seconds"]["apply"]
        print(f"| {rel} | {scheme} | {levels} | {lj['output_vertices']:,} | {ls:.3f} "
              f"| {oj['seconds_total']:.3f} | {lj['peak_rss_bytes'] / 2**20:.0f} "
              f"| {oj['peak_rss_bytes'] / 2**20:.0f} | {lj['estimated_bytes'] / 2**20:.0f} |")
    print()
    print("| mesh | levels | per-level tables: entries | composed table: entries | ratio "
          "| compose s | apply s, per-level (device) | apply s, composed (host) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for rel, levels, scheme, lj, oj, fj in rows:
        a_, b_ = fj["level_by_level"], fj["factorised"]
        print(f"| {rel} | {levels} | {a_['entries']:,} | {b_['entries']:,} "
              f"| {b_['entries'] / a_['entries']:.2f} | {b_['seconds_compose']:.3f} "
              f"| {a_['seconds_apply']:.3f} | {b_['seconds_apply_host']:.3f} |")
    os.makedirs(os.path.dirname(a.csv), exist_ok=True)
    with open(a.csv, "w") as f:
        f.write("mesh,scheme,levels,output_vertices,limn_seconds,osd_seconds,limn_peak_bytes,"
                "osd_peak_bytes,limn_estimate_bytes,level_entries,composed_entries\n")
        for rel, levels, scheme, lj, oj, fj in rows:
            f.write(f"{rel},{scheme},{levels},{lj['output_vertices']},"
                    f"{lj['seconds']['plan'] + lj['seconds']['apply']},{oj['seconds_total']},"
                    f"{lj['peak_rss_bytes']},{oj['peak_rss_bytes']},{lj['estimated_bytes']},"
                    f"{fj['level_by_level']['entries']},{fj['factorised']['entries']}\n")


if __name__ == "__main__":
    main()

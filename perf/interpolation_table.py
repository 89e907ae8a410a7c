#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Seed 003 Table 1, for limn: interpolate every shared small and medium mesh
and print vertices, scheme, iterations, max/mean relative error and seconds per
iteration, as a markdown table (and a CSV beside it).

    python3 perf/interpolation_table.py [--limn build/limn] [--device opencl]
        [--alpha 0] [--csv out/interpolation_table.csv]

Catmull-Clark (alpha as given) on every mesh, Loop as well on triangle meshes.
Meshes limn refuses are listed with the reason. Timings are wall-clock on
whatever machine runs it: compare ratios, not absolutes.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--limn", default=os.path.join(ROOT, "build", "limn"))
    ap.add_argument("--meshes", default=os.environ.get(
        "LIMN_SHARED_MESHES", os.path.join(ROOT, "..", "shared", "meshes")))
    ap.add_argument("--device", default="opencl")
    ap.add_argument("--alpha", default="0")
    ap.add_argument("--tol", default="1e-6")
    ap.add_argument("--csv", default=os.path.join(ROOT, "out", "interpolation_table.csv"))
    a = ap.parse_args()
    rows = []
    tmp = tempfile.mkdtemp(prefix="limn_table_")
    for sub in ("small", "medium"):
        d = os.path.join(a.meshes, sub)
        for name in sorted(os.listdir(d)):
            path = os.path.join(d, name)
            info = subprocess.run([a.limn, "info", path, "--json"], capture_output=True, text=True)
            if info.returncode != 0:
                rows.append((f"{sub}/{name}", None, None, info.stderr.strip()))
                continue
            tri = json.loads(info.stdout)["auto_scheme"] == "loop"
            for scheme in (["catmark", "loop"] if tri else ["catmark"]):
                rep = os.path.join(tmp, "r.json")
                cmd = [a.limn, "interpolate", path, "-o", os.path.join(tmp, "p.ply"), "-q",
                       "--scheme", scheme, "--alpha", a.alpha, "--tol", a.tol,
                       "--device", a.device, "--report", rep]
                r = subprocess.run(cmd, capture_output=True, text=True)
                if r.returncode != 0:
                    rows.append((f"{sub}/{name}", scheme, None, r.stderr.strip()))
                    continue
                with open(rep) as f:
                    rows.append((f"{sub}/{name}", scheme, json.load(f), None))
    print(f"| mesh | vertices | scheme | alpha | iterations | max rel. error | mean rel. error "
          f"| s / iteration | device |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---|")
    os.makedirs(os.path.dirname(a.csv), exist_ok=True)
    with open(a.csv, "w") as out:
        out.write("mesh,vertices,scheme,alpha,iterations,max_rel_error,mean_rel_error,"
                  "seconds_per_iteration,device\n")
        for mesh, scheme, j, err in rows:
            if j is None:
                print(f"| {mesh} | | {scheme or ''} | | refused: {err} | | | | |")
                continue
            per = j["seconds"]["solve"] / (j["iterations"] + 1)
            dev = j["device"].split(" [")[0][:24]
            print(f"| {mesh} | {j['vertices']} | {j['scheme']} | {j['alpha']:g} | {j['iterations']} "
                  f"| {j['max_rel_error']:.2e} | {j['mean_rel_error']:.2e} | {per:.2e} | {dev} |")
            out.write(f"{mesh},{j['vertices']},{j['scheme']},{j['alpha']},{j['iterations']},"
                      f"{j['max_rel_error']},{j['mean_rel_error']},{per},{j['device']}\n")
    print(f"\n(CSV: {a.csv})", file=sys.stderr)


if __name__ == "__main__":
    main()

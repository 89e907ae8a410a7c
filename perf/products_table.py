#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Stencil products to a tolerance, every method, on the shared medium meshes:
the table of README "Solvers" and issue 5's products target (3x fewer than the
paper's iteration for Loop, 4x for Catmull-Clark).

    bash scripts/build.sh
    python3 perf/products_table.py [--limn build/limn] [--tol 1e-6]

Runs `limn interpolate MESH -o OUT --scheme S --method M --precision double
--report r.json` and reads the report's `products` (units of one full A x;
a block's or a sweep's share counted as such) and `seconds.solve`. Needs no
Python modules beyond the standard library. Solve times are from whatever
machine runs it: compare within one run.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("LIMN_SHARED_MESHES", os.path.join(ROOT, "..", "shared", "meshes"))
MESHES = [("armadillo_43k.obj", "loop"), ("bunny_closed.off", "loop"), ("fertility.off", "loop"),
          ("horse.ply", "loop"), ("bun_zipper.ply", "loop"), ("beast.obj", "catmark"),
          ("blub_quadrangulated.obj", "catmark"), ("bob_quad.obj", "catmark"),
          ("horse.ply", "catmark")]
METHODS = ["paper", "weighted", "chebyshev", "cg", "sgs"]
TARGET = {"loop": 3.0, "catmark": 4.0}


def solve(limn, tmp, path, scheme, method, tol):
    rep = os.path.join(tmp, "r.json")
    subprocess.run([limn, "interpolate", path, "-o", os.path.join(tmp, "p.ply"), "-q",
                    "--scheme", scheme, "--method", method, "--precision", "double",
                    "--tol", str(tol), "--report", rep], check=True,
                   stderr=subprocess.DEVNULL)
    with open(rep) as f:
        j = json.load(f)
    return j["products"], j["seconds"]["solve"], j["max_rel_error"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--limn", default=os.path.join(ROOT, "build", "limn"))
    ap.add_argument("--tol", type=float, default=1e-6)
    a = ap.parse_args()
    if not os.path.isdir(os.path.join(SHARED, "medium")):
        sys.exit(f"{SHARED}/medium is missing: the shared meshes sit beside the repository")
    print(f"Stencil products to {a.tol:g} (solve seconds in brackets):\n")
    print("| mesh | scheme | " + " | ".join(METHODS) + " | paper / sgs | target |")
    print("|---|---|" + "---:|" * len(METHODS) + "---:|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, scheme in MESHES:
            path = os.path.join(SHARED, "medium", name)
            cells, products = [], {}
            for m in METHODS:
                p, s, err = solve(a.limn, tmp, path, scheme, m, a.tol)
                if err > a.tol:
                    sys.exit(f"{name} {scheme} {m}: error {err:.3g} above the tolerance")
                products[m] = p
                cells.append(f"{p:.3g} ({s:.3f})")
            ratio = products["paper"] / products["sgs"]
            label = name.rsplit(".", 1)[0] + (" (triangles)" if name == "horse.ply" and
                                              scheme == "catmark" else "")
            verdict = "met" if ratio >= TARGET[scheme] else "NOT met"
            print(f"| {label} | {scheme} | " + " | ".join(cells) +
                  f" | {ratio:.2f} | {TARGET[scheme]:.0f}x {verdict} |", flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""limn's performance suite: one command, one table, everything measured side
by side in the same run.

    bash scripts/build.sh -DLIMN_BUILD_PERF=ON
    python3 perf/run_suite.py [--max-size 9000000] [--quick]

For each mesh size (real shared meshes, refined with `limn subdivide` into
out/perf-meshes/ for the large sizes) and each scheme, it runs:
  - limn interpolate, every method (paper, weighted, chebyshev, cg), PoCL on 1 and 2
    threads (POCL_MAX_PTHREAD_COUNT), double precision;
  - the seeds' iteration on OpenSubdiv's limit stencils (perf/osd_iteration,
    a plain C++ double loop; sizes up to --osd-max: its adaptive stencil build
    grows fast);
  - SciPy on limn's exported operator (perf/scipy_anchor.py): the seeds'
    iteration on a CSR matrix, the same CG, SuperLU up to --superlu-max;
  - STREAM triad on 1 and 2 threads (perf/stream_triad), once;
  - denoise and morph throughput (perf/series_throughput.py).
It prints a markdown table (time per vertex per product, products, solve
seconds, GB/s moved by limn's solve loop and its fraction of the triad rate)
and writes out/perf_suite.csv and out/perf_suite.png (time per vertex against
size, per implementation).

Bytes one product moves (the roofline of DESIGN.md §6): the CSR table
(12 bytes a nonzero + 4 a row) plus the vectors the fused step streams
(m, p read, p_next written: 3 x 32 bytes a row) plus one gather of p (32 bytes
a row when the order is local).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (label, base mesh, levels, schemes)
SIZES = [
    ("horse 48k", "medium/horse.ply", 0, ["loop", "catmark"]),
    ("bob 21k", "medium/bob_quad.obj", 1, ["catmark"]),
    ("igea 134k", "large/igea.ply", 0, ["loop", "catmark"]),
    ("bob 342k", "medium/bob_quad.obj", 3, ["catmark"]),
    ("igea 537k", "large/igea.ply", 1, ["loop", "catmark"]),
    ("igea 2.1M", "large/igea.ply", 2, ["loop", "catmark"]),
    ("bob 5.5M", "medium/bob_quad.obj", 5, ["catmark"]),
    ("igea 8.6M", "large/igea.ply", 3, ["loop", "catmark"]),
]


def run(cmd, env=None, timeout=3600):
    e = dict(os.environ)
    if env:
        e.update(env)
    r = subprocess.run(cmd, capture_output=True, text=True, env=e, timeout=timeout)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: {r.stderr.strip()[-400:]}")
    return r.stdout


def mesh_for(a, base, levels):
    src = os.path.join(a.meshes, base)
    if levels == 0:
        return src
    out = os.path.join(ROOT, "out", "perf-meshes",
                       f"{os.path.splitext(os.path.basename(base))[0]}_L{levels}.ply")
    if not os.path.exists(out):
        os.makedirs(os.path.dirname(out), exist_ok=True)
        scheme = "loop" if base.endswith("igea.ply") else "catmark"
        run([a.limn, "subdivide", src, "-o", out, "--levels", str(levels), "--scheme", scheme,
             "-q"])
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--meshes", default=os.environ.get(
        "LIMN_SHARED_MESHES", os.path.join(ROOT, "..", "shared", "meshes")))
    ap.add_argument("--max-size", type=float, default=9e6)
    ap.add_argument("--osd-max", type=float, default=140e3)
    ap.add_argument("--scipy-max", type=float, default=2.2e6)
    ap.add_argument("--superlu-max", type=int, default=150000)
    ap.add_argument("--quick", action="store_true", help="1 thread count, cg and paper only")
    ap.add_argument("--csv", default=os.path.join(ROOT, "out", "perf_suite.csv"))
    a = ap.parse_args()
    a.limn = os.path.join(a.build, "limn")
    perf = os.path.join(a.build, "perf")
    tmp = tempfile.mkdtemp(prefix="limn_suite_")
    rows = []
    stream = {}
    for t in (1, 2):
        j = json.loads(run([os.path.join(perf, "stream_triad"), "512", "10"],
                           env={"OMP_NUM_THREADS": str(t)}))
        stream[t] = j["gb_per_s"]
    methods = ["paper", "chebyshev", "cg"] if a.quick else ["paper", "weighted", "chebyshev", "cg"]
    threads = [2] if a.quick else [1, 2]
    for label, base, levels, schemes in SIZES:
        path = mesh_for(a, base, levels)
        info = json.loads(run([a.limn, "info", path, "--json"]))
        n = info["vertices"]
        if n > a.max_size:
            continue
        for scheme in schemes:
            for method in methods:
                for t in threads:
                    rep = os.path.join(tmp, "r.json")
                    run([a.limn, "interpolate", path, "-o", os.path.join(tmp, "p.ply"), "-q",
                         "--scheme", scheme, "--method", method, "--report", rep],
                        env={"POCL_MAX_PTHREAD_COUNT": str(t)})
                    with open(rep) as f:
                        j = json.load(f)
                    per = j["seconds"]["solve"] / max(j["products"], 1)
                    nbytes = j["stencil_nonzeros"] * 12 + n * (4 + 4 * 32)
                    gbs = nbytes / per / 1e9
                    rows.append({"size": label, "vertices": n, "scheme": scheme,
                                 "impl": f"limn {method} {t}t", "products": j["products"],
                                 "seconds": j["seconds"]["solve"], "s_per_product": per,
                                 "gb_per_s": gbs, "triad_fraction": gbs / stream[t],
                                 "peak_rss_bytes": j.get("peak_rss_bytes", 0)})
                    print(f"  {label} {scheme} limn {method} {t}t: {j['products']:.1f} products, "
                          f"{per * 1e3:.2f} ms/product", file=sys.stderr)
            if n <= a.osd_max:
                j = json.loads(run([os.path.join(perf, "osd_iteration"), path, scheme]))
                rows.append({"size": label, "vertices": n, "scheme": scheme,
                             "impl": "opensubdiv stencils 1t", "products": j["products"],
                             "seconds": j["seconds_iterate"] + j["seconds_stencils"],
                             "s_per_product": j["seconds_per_product"], "gb_per_s": "",
                             "triad_fraction": "", "peak_rss_bytes": j["peak_rss_bytes"]})
            if n <= a.scipy_max:
                op = os.path.join(tmp, "op.bin")
                run([os.path.join(perf, "export_operator"), path, scheme, op])
                out = run([sys.executable, os.path.join(ROOT, "perf", "scipy_anchor.py"), op,
                           "--superlu-max", str(a.superlu_max)])
                per = None
                for line in out.splitlines():
                    j = json.loads(line)
                    if j["impl"] == "scipy_csr_product":
                        per = j["seconds_per_product"]
                    if j["impl"] in ("scipy_paper", "scipy_cg", "scipy_superlu") and "seconds" in j:
                        rows.append({"size": label, "vertices": n, "scheme": scheme,
                                     "impl": j["impl"].replace("_", " ") + " 1t",
                                     "products": j["products"], "seconds": j["seconds"],
                                     "s_per_product": per if j["products"] else "",
                                     "gb_per_s": "", "triad_fraction": "", "peak_rss_bytes": ""})
    os.makedirs(os.path.dirname(a.csv), exist_ok=True)
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"STREAM triad: {stream[1]:.1f} GB/s (1 thread), {stream[2]:.1f} GB/s (2 threads)")
    print("| size | scheme | implementation | products | solve s | ns / vertex / product "
          "| GB/s | of triad |")
    print("|---|---|---|---:|---:|---:|---:|---:|")
    for r in rows:
        per = r["s_per_product"]
        nsv = f"{per / r['vertices'] * 1e9:.1f}" if per else ""
        gbs = f"{r['gb_per_s']:.1f}" if r["gb_per_s"] != "" else ""
        frac = f"{100 * r['triad_fraction']:.0f}%" if r["triad_fraction"] != "" else ""
        print(f"| {r['size']} | {r['scheme']} | {r['impl']} | {r['products']:.1f} "
              f"| {r['seconds']:.3f} | {nsv} | {gbs} | {frac} |")
    # the series toolkit's throughput, same run (perf/series_throughput.py)
    sys.path.insert(0, os.path.join(ROOT, "perf"))
    import series_throughput
    print("\nDenoise and morph (PoCL, 2 threads; compute phase):")
    series_throughput.print_table(
        series_throughput.measure(a.build, a.meshes, min(a.max_size, 9e6), stream[2]), stream[2])
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
        for ax, scheme in zip(axes, ("loop", "catmark")):
            impls = sorted({r["impl"] for r in rows if r["scheme"] == scheme})
            for impl in impls:
                pts = sorted((r["vertices"], r["seconds"] / r["vertices"] * 1e9) for r in rows
                             if r["scheme"] == scheme and r["impl"] == impl)
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker="o", label=impl)
            ax.set_title(f"{scheme}: solve time per vertex to 1e-6")
            ax.set_xlabel("vertices")
            ax.grid(True, which="both", alpha=0.3)
        axes[0].set_ylabel("ns per vertex (whole solve)")
        axes[1].legend(fontsize=7, loc="upper right")
        fig.tight_layout()
        png = os.path.splitext(a.csv)[0] + ".png"
        fig.savefig(png, dpi=90)
        print(f"(plot: {png}; CSV: {a.csv}; {time.strftime('%Y-%m-%d')})")
    except ImportError:
        print("(matplotlib not installed: no plot; pip install matplotlib)")


if __name__ == "__main__":
    main()

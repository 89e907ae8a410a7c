#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""limn's performance suite: one command, one table, everything measured side
by side in the same run.

    bash scripts/build.sh -DLIMN_BUILD_PERF=ON
    python3 perf/run_suite.py [--max-size 9000000] [--quick]   # the whole suite
    python3 perf/run_suite.py --focus [--max-size 2200000]     # solve loop at >= 1M

The whole suite needs numpy, scipy and matplotlib (pip install numpy scipy
matplotlib); --focus needs none of them.

Whole suite: for each mesh size (real shared meshes, refined with `limn
subdivide` into out/perf-meshes/ for the large sizes) and each scheme:
  - limn interpolate, every method (paper, weighted, chebyshev, cg, sgs), PoCL on 1
    and on 2 threads (POCL_MAX_PTHREAD_COUNT); chebyshev and paper also in
    float precision (--precision);
  - the seeds' iteration on OpenSubdiv's limit stencils (perf/osd_iteration,
    a plain C++ double loop; sizes up to --osd-max: its adaptive stencil build
    grows fast);
  - SciPy on limn's exported operator (perf/scipy_anchor.py): the seeds'
    iteration on a CSR matrix, the same CG, SuperLU up to --superlu-max;
  - STREAM triad on 1 and 2 threads (perf/stream_triad), once;
  - denoise and morph throughput (perf/series_throughput.py).
It prints a markdown table (time per vertex per product, products, solve
seconds, GB/s moved by limn's solve and its fraction of the triad rate) and
writes out/perf_suite.csv and out/perf_suite.png (time per vertex against
size, per implementation).

--focus: sizes from --min-size (1M) to --max-size only. For each: the solve
loop's kernels alone (perf/step_bench: best of --repeats steps on resident
buffers, double and float, 1 and 2 threads) as GB/s and fraction of the
triad measured in the same run; and whole solves (limn interpolate, the
--focus-methods, double and float, 1 and 2 threads, best and median of
--repeats runs).

Both modes end with OpenCL set-up on the embedded Spot mesh: a cold PoCL
kernel cache (a fresh POCL_CACHE_DIR) and then a warm one, from the report's
seconds.opencl_setup and its parts (platform query, context, program build,
first-launch compiles).

Bytes a step must move (the roofline of DESIGN.md §6), per precision:
  double: the CSR table (4-byte column + 8-byte weight a nonzero, 4-byte row
          offset a row) and m, p read and p_next written (32 bytes a row each;
          chebyshev also reads the previous iterate it overwrites: 4 streams);
  float:  the table with float weights (4 + 4 a nonzero, 4 a row) and b, d
          read and d_next written (16 bytes a row each; chebyshev: 4 streams).
The gather of p (or d) is not counted again: in a local vertex order it hits
the lines the p stream brings in. A mixed solve moves products_float float
steps and, for the rest, residuals of P (m, p read, a float r written).
Write-allocate traffic is not counted (nor is it in STREAM).
"""
import argparse
import csv
import json
import os
import statistics
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
    ("bob 1.4M", "medium/bob_quad.obj", 4, ["catmark"]),
    ("igea 2.1M", "large/igea.ply", 2, ["loop", "catmark"]),
    ("bob 5.5M", "medium/bob_quad.obj", 5, ["catmark"]),
    ("igea 8.6M", "large/igea.ply", 3, ["loop", "catmark"]),
]


def step_bytes(nonzeros, vertices, precision, streams=3):
    """CSR table + `streams` vector streams (3: paper, weighted; 4: chebyshev,
    whose previous iterate is read, then overwritten)."""
    if precision == "float":
        return 8 * nonzeros + (4 + streams * 16) * vertices
    return 12 * nonzeros + (4 + streams * 32) * vertices


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


def interpolate(a, tmp, path, scheme, method, precision, threads, env=None):
    rep = os.path.join(tmp, "r.json")
    e = {"POCL_MAX_PTHREAD_COUNT": str(threads)}
    e.update(env or {})
    run([a.limn, "interpolate", path, "-o", os.path.join(tmp, "p.ply"), "-q", "--scheme",
         scheme, "--method", method, "--precision", precision, "--report", rep], env=e)
    with open(rep) as f:
        return json.load(f)


def solve_bytes(j):
    """Bytes of a whole solve: its double products (in a mixed solve, residuals
    of P: m and p read, a float r written) and its float ones."""
    nnz, n, nf = j["stencil_nonzeros"], j["vertices"], j.get("products_float", 0)
    # sgs: a step's two sweeps and update touch ~18 vector streams per
    # product's worth of table (README "Solvers")
    streams = {"chebyshev": 4, "sgs": 18}.get(j["method"], 3)
    if nf:
        residual = 12 * nnz + (4 + 32 + 32 + 16) * n
        return residual * (j["products"] - nf) + step_bytes(nnz, n, "float", streams) * nf
    return step_bytes(nnz, n, "double", streams) * j["products"]


def triad(perf):
    rates = {}
    for t in (1, 2):
        j = json.loads(run([os.path.join(perf, "stream_triad"), "512", "10"],
                           env={"OMP_NUM_THREADS": str(t)}))
        rates[t] = j["gb_per_s"]
    return rates


def setup_times(a, tmp, warm_runs=3):
    """OpenCL set-up of a small job with a cold, then a warm, PoCL cache."""
    spot = os.path.join(ROOT, "data", "spot_control_mesh.obj")
    cache = tempfile.mkdtemp(prefix="limn_pocl_cache_")
    rows = []
    for label, runs in (("cold cache", 1), ("warm cache", warm_runs)):
        js = [interpolate(a, tmp, spot, "catmark", "paper", "double", 2,
                          env={"POCL_CACHE_DIR": cache}) for _ in range(runs)]
        j = sorted(js, key=lambda x: x["seconds"]["opencl_setup"])[len(js) // 2]
        rows.append((label, j["seconds"]["opencl_setup"], j["opencl_setup"],
                     j["seconds"]["total"]))
    subprocess.run(["rm", "-rf", cache])
    return rows


def print_setup(rows):
    print("\nOpenCL set-up, embedded Spot mesh (2,930 vertices; median of the warm runs):")
    print("| kernel cache | set-up s | platform | context | program build | first launches "
          "| whole run s |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for label, total, parts, whole in rows:
        print(f"| {label} | {total:.3f} | {parts['platform']:.3f} | {parts['context']:.3f} "
              f"| {parts['build']:.3f} | {parts['kernels']:.3f} | {whole:.3f} |")


def focus(a, perf, tmp):
    stream = triad(perf)
    kernel_rows, solve_rows = [], []
    for label, base, levels, schemes in SIZES:
        path = mesh_for(a, base, levels)
        n = json.loads(run([a.limn, "info", path, "--json"]))["vertices"]
        if n < a.min_size or n > a.max_size:
            continue
        for scheme in schemes:
            for t in (1, 2):
                out = run([os.path.join(perf, "step_bench"), path, scheme, str(a.steps)],
                          env={"POCL_MAX_PTHREAD_COUNT": str(t)})
                for line in out.splitlines():
                    j = json.loads(line)
                    kernel_rows.append((label, scheme, f"{j['method']} {j['precision']}", t,
                                        j["seconds_best"], j["seconds_median"], j["gb_per_s"]))
                    print(f"  {label} {scheme} step {j['method']} {j['precision']} {t}t: "
                          f"{j['seconds_best'] * 1e3:.1f} ms", file=sys.stderr)
                for method, precision in ((m, p) for m in a.focus_methods.split(",")
                                          for p in ("double", "float")):
                    js = [interpolate(a, tmp, path, scheme, method, precision, t)
                          for _ in range(a.repeats)]
                    secs = sorted(j["seconds"]["solve"] for j in js)
                    loop = min(j["seconds"]["iterations"] for j in js)
                    j = js[0]
                    solve_rows.append((label, scheme, f"{method} {precision}", t, j["products"],
                                       j.get("products_float", 0), secs[0],
                                       statistics.median(secs), j["max_rel_error"],
                                       solve_bytes(j) / secs[0] / 1e9, loop,
                                       solve_bytes(j) / loop / 1e9))
    # the machine is shared: the triad is taken again at the end and the higher
    # rate kept, so that a busy moment cannot flatter the fractions
    again = triad(perf)
    stream = {t: max(stream[t], again[t]) for t in stream}
    print(f"STREAM triad: {stream[1]:.1f} GB/s (1 thread), {stream[2]:.1f} GB/s (2 threads), "
          "the higher of two runs")
    print("\nThe solve loop's step alone (perf/step_bench, best of "
          f"{a.steps} steps; bytes: see perf/run_suite.py):")
    print("| size | scheme | step, precision | threads | ms best | ms median | GB/s | of triad |")
    print("|---|---|---|---:|---:|---:|---:|---:|")
    for r in kernel_rows:
        print(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]} | {r[4] * 1e3:.1f} | {r[5] * 1e3:.1f} "
              f"| {r[6]:.1f} | {100 * r[6] / stream[r[3]]:.0f}% |")
    print(f"\nWhole solves to 1e-6 (limn interpolate; best and median of {a.repeats}). Its "
          "iteration loop alone (the report's seconds.iterations, best) and its rate; the "
          "whole solve's rate counts its buffers, packing and output mesh as time, not bytes:")
    print("| size | scheme | method, precision | threads | products (float) | solve s best "
          "| median | max error | loop s | loop GB/s | loop of triad | whole solve of triad |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in solve_rows:
        print(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]} | {r[4]:.0f} ({r[5]:.0f}) | {r[6]:.3f} "
              f"| {r[7]:.3f} | {r[8]:.2e} | {r[10]:.3f} | {r[11]:.1f} "
              f"| {100 * r[11] / stream[r[3]]:.0f}% | {100 * r[9] / stream[r[3]]:.0f}% |")


def need_modules(names, why):
    missing = []
    for m in names:
        try:
            __import__(m)
        except ImportError:
            missing.append(m)
    if missing:
        sys.exit(f"perf/run_suite.py: {why} needs the Python modules {', '.join(missing)}: "
                 f"pip install {' '.join(missing)}  (or run with --focus, which needs none)")


COLORS = {"paper": "tab:blue", "weighted": "tab:green", "chebyshev": "tab:red",
          "cg": "tab:purple", "sgs": "tab:orange", "opensubdiv": "black", "scipy paper": "tab:gray",
          "scipy cg": "tab:brown", "scipy superlu": "tab:olive"}


def style(impl):
    """Colour by method, line by threads (solid 2, dashed 1), marker by
    precision (o double, s float); anchors dotted."""
    words = impl.split()
    if words[0] == "limn":
        return dict(color=COLORS[words[1]], linestyle="-" if impl.endswith("2t") else "--",
                    marker="s" if "float" in words else "o", markersize=4)
    key = "opensubdiv" if words[0] == "opensubdiv" else " ".join(words[:2])
    return dict(color=COLORS.get(key, "tab:cyan"), linestyle=":", marker="^", markersize=5)


def plot(rows, png):
    """Time per vertex of the whole solve against size, one line per
    implementation, Loop and Catmull-Clark side by side."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), sharey=True)
    for ax, scheme in zip(axes, ("loop", "catmark")):
        impls = sorted({r["impl"] for r in rows if r["scheme"] == scheme})
        for impl in impls:
            pts = sorted((float(r["vertices"]), float(r["seconds"]) / float(r["vertices"]) * 1e9)
                         for r in rows if r["scheme"] == scheme and r["impl"] == impl)
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], label=impl, **style(impl))
        ax.set_title(f"{scheme}: solve time per vertex to 1e-6")
        ax.set_xlabel("vertices")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("ns per vertex (whole solve; OpenSubdiv: with its stencil build)")
    handles, labels = axes[0].get_legend_handles_labels()
    h2, l2 = axes[1].get_legend_handles_labels()
    for h, lab in zip(h2, l2):
        if lab not in labels:
            handles.append(h)
            labels.append(lab)
    fig.legend(handles, labels, fontsize=7, loc="center right")
    fig.tight_layout(rect=(0, 0, 0.84, 1))
    fig.savefig(png, dpi=90)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--meshes", default=os.environ.get(
        "LIMN_SHARED_MESHES", os.path.join(ROOT, "..", "shared", "meshes")))
    ap.add_argument("--max-size", type=float, default=9e6)
    ap.add_argument("--min-size", type=float, default=1e6, help="--focus: smallest mesh")
    ap.add_argument("--osd-max", type=float, default=140e3)
    ap.add_argument("--scipy-max", type=float, default=2.2e6)
    ap.add_argument("--superlu-max", type=int, default=150000)
    ap.add_argument("--quick", action="store_true", help="1 thread count, cg and paper only")
    ap.add_argument("--focus", action="store_true",
                    help="the solve loop at >= --min-size: kernels alone and whole solves, "
                         "double and float, 1 and 2 threads, against STREAM triad")
    ap.add_argument("--repeats", type=int, default=3, help="--focus: runs per whole solve")
    ap.add_argument("--focus-methods", default="chebyshev",
                    help="--focus: methods of the whole solves, comma-separated")
    ap.add_argument("--steps", type=int, default=20, help="--focus: timed kernel steps")
    ap.add_argument("--csv", default=os.path.join(ROOT, "out", "perf_suite.csv"))
    ap.add_argument("--plot-only", action="store_true",
                    help="redraw the PNG from an existing --csv, measuring nothing")
    a = ap.parse_args()
    if a.plot_only:
        with open(a.csv, newline="") as f:
            rows = list(csv.DictReader(f))
        png = os.path.splitext(a.csv)[0] + ".png"
        plot(rows, png)
        print(f"(plot: {png}, from {a.csv})")
        return
    a.limn = os.path.join(a.build, "limn")
    perf = os.path.join(a.build, "perf")
    for tool in ("stream_triad", "step_bench"):
        if not os.path.exists(os.path.join(perf, tool)):
            sys.exit(f"perf/run_suite.py: {perf}/{tool} is missing: build with "
                     "bash scripts/build.sh -DLIMN_BUILD_PERF=ON (or pass --build DIR)")
    tmp = tempfile.mkdtemp(prefix="limn_suite_")
    if a.focus:
        focus(a, perf, tmp)
        print_setup(setup_times(a, tmp))
        print(f"({time.strftime('%Y-%m-%d')})")
        return
    need_modules(["numpy", "scipy", "matplotlib"], "the whole suite (SciPy anchors, plot)")
    rows = []
    stream = triad(perf)
    methods = (["paper", "chebyshev", "cg", "sgs"] if a.quick
               else ["paper", "weighted", "chebyshev", "cg", "sgs"])
    threads = [2] if a.quick else [1, 2]
    for label, base, levels, schemes in SIZES:
        path = mesh_for(a, base, levels)
        info = json.loads(run([a.limn, "info", path, "--json"]))
        n = info["vertices"]
        if n > a.max_size:
            continue
        for scheme in schemes:
            runs = [(m, "double") for m in methods] + [("chebyshev", "float"), ("paper", "float")]
            for method, precision in runs:
                for t in threads:
                    j = interpolate(a, tmp, path, scheme, method, precision, t)
                    per = j["seconds"]["solve"] / max(j["products"], 1)
                    gbs = solve_bytes(j) / j["seconds"]["solve"] / 1e9
                    impl = f"limn {method}{' float' if precision == 'float' else ''} {t}t"
                    rows.append({"size": label, "vertices": n, "scheme": scheme,
                                 "impl": impl, "products": j["products"],
                                 "seconds": j["seconds"]["solve"], "s_per_product": per,
                                 "gb_per_s": gbs, "triad_fraction": gbs / stream[t],
                                 "peak_rss_bytes": j.get("peak_rss_bytes", 0)})
                    print(f"  {label} {scheme} {impl}: {j['products']:.1f} products, "
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
    print_setup(setup_times(a, tmp))
    png = os.path.splitext(a.csv)[0] + ".png"
    plot(rows, png)
    print(f"(plot: {png}; CSV: {a.csv}; {time.strftime('%Y-%m-%d')})")


if __name__ == "__main__":
    main()

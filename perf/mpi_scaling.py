#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Strong scaling of the MPI layer, 1 -> 2 ranks, and a projection to 64 ranks.

    bash scripts/build.sh -DLIMN_BUILD_PERF=ON && python3 perf/mpi_scaling.py

Makes a >= 2M-vertex mesh (igea.ply refined twice by Loop: 2,149,490 vertices)
with `limn subdivide` unless --mesh is given, then runs perf/mpi_bench (the
--method iteration to --tol, paper by default, best of --repeat runs) on 1 rank and on 2 ranks, one
core each (mpirun binds each rank to a core; the MPI layer gives PoCL the
rank's cores), and 1 rank with 2 PoCL threads for comparison. Prints per rank:
time per iteration, halo bytes per iteration, compute / halo / reduce time per
iteration; then METIS partitions of the same mesh into 2..64 parts and the
projected time per iteration at 64 ranks (model below). Also measures how many
cores the machine really gives (two busy processes against one): on a shared
machine the second core may be taken.

    python3 perf/mpi_scaling.py --pipeline [--skip-8m] [--json out.json]

The distributed pipeline instead (docs/mpi.md, "Distributed meshes"), side by
side in one run: `limn interpolate --precision double --report` on the 2.1M
float32 PLY (/tmp/limn_read_bench/scanner_l2_f32.ply) as one process and on
2 and 4 ranks, and on the 8.6M one (/tmp/limn_e2e/scanner_l3_f32.ply) as one
process and on 2 and 8 ranks (made as perf/end_to_end.py makes them when missing),
and each as 1 rank bound to one core (`mpirun -np 1 --bind-to core`: the core
each rank of the 2-rank run has, the strong-scaling baseline), each mesh after
one untimed run (this VM returns freed memory to its host: a first run after
an idle spell pays for fresh memory), then --pipeline-rounds rounds (3) taking
turns, each round starting one configuration later (a run's fresh memory here
depends on the run before it), each configuration's median set-up kept (every
round's printed), and the set-up with each stage at its best round (the
comparison where fresh memory is fast, as on bare metal: `setup_best_stages`
and every round's stages, `rounds_setup_parts`, in the JSON), and the rounds
2 ranks are the faster in with a sign test's p and the median of the rounds'
ratios with a 90% bootstrap interval (whether a difference is more than the
VM's spread). It
checks every output is the single process's bytes (cmp) and prints per rank:
peak resident bytes and the worst rank's ratio to the single process's,
set-up seconds (load + partition + local rows; one process: load + topology +
stencil + opening the device, which a rank does in its local rows), owned,
ghosts, halo bytes and
solve seconds; then the unit costs and the model for 16..1024 ranks at
--model-vertices (docs/mpi.md, "Model: 1,024 ranks and a billion vertices").
Ranks beyond the cores are oversubscribed: the memory figures are exact, the
times are those of shared cores.
"""
import argparse
import json
import math
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run_json(cmd, env):
    out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def effective_cores():
    """Wall time of one busy process over that of two at once (2.0 = two free cores)."""
    spin = [sys.executable, "-c", "x=0\nfor i in range(6000000): x+=i"]
    t0 = time.time()
    subprocess.run(spin, check=True)
    one = time.time() - t0
    t0 = time.time()
    procs = [subprocess.Popen(spin) for _ in range(2)]
    for p in procs:
        p.wait()
    two = time.time() - t0
    return 2.0 * one / two


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--mesh", help="mesh to use (default: igea refined twice, made if missing)")
    ap.add_argument("--tol", default="1e-10", help="tolerance (tight: enough iterations to time)")
    ap.add_argument("--repeat", default="3", help="solves per launch (the best is kept)")
    ap.add_argument("--rounds", default="3", help="launches per configuration, taking turns")
    ap.add_argument("--method", default="paper",
                    help="paper (default: the reference step), chebyshev, weighted or cg")
    ap.add_argument("--latency-us", type=float, default=2.0,
                    help="projection: network latency per message, microseconds")
    ap.add_argument("--bandwidth-gbs", type=float, default=10.0,
                    help="projection: network bandwidth per rank, GB/s")
    ap.add_argument("--pipeline", action="store_true",
                    help="the distributed pipeline and the model instead (see above)")
    ap.add_argument("--skip-8m", action="store_true", help="pipeline: leave out the 8.6M mesh")
    ap.add_argument("--pipeline-rounds", type=int, default=3,
                    help="pipeline: runs of each configuration, taking turns (the median kept)")
    ap.add_argument("--json", help="pipeline: also write every figure here")
    ap.add_argument("--tmp", help="pipeline: folder for the outputs (default: the system's)")
    ap.add_argument("--tol-pipe", help="pipeline: --tol for limn interpolate (default: its own)")
    ap.add_argument("--model-vertices", type=float, default=1e9)
    ap.add_argument("--fs-aggregate-gbs", type=float, default=10.0,
                    help="model: parallel file system bandwidth, all nodes, GB/s")
    ap.add_argument("--fs-node-gbs", type=float, default=1.0,
                    help="model: file system bandwidth one node gets, GB/s")
    ap.add_argument("--ranks-per-node", type=int, default=8)
    ap.add_argument("--partition-model", default="sfc", choices=["sfc", "scotch"],
                    help="pipeline model: the partition's growth with P (the curve's default "
                         "O(n/P) + 11 Allreduces, or PT-Scotch's assumed log2 P)")
    ap.add_argument("--neighbours", type=int, default=8,
                    help="model: neighbour ranks at least (2D partitions: about 6)")
    args = ap.parse_args()

    limn = os.path.join(args.build, "limn")
    if args.pipeline:
        env = dict(os.environ)
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        env.setdefault("POCL_CACHE_DIR", os.path.join(args.build, "pocl-cache"))
        pipeline(args, limn, env)
        return
    bench = os.path.join(args.build, "perf", "mpi_bench")
    if not os.path.exists(bench):
        sys.exit("perf/mpi_bench is missing: bash scripts/build.sh -DLIMN_BUILD_PERF=ON "
                 "(needs LIMN_MPI: apt-get install libopenmpi-dev openmpi-bin libmetis-dev "
                 "libptscotch-dev)")
    mesh = args.mesh
    if not mesh:
        os.makedirs(os.path.join(ROOT, "out"), exist_ok=True)
        mesh = os.path.join(ROOT, "out", "igea_loop2.ply")
        if not os.path.exists(mesh):
            src = os.path.join(ROOT, "..", "shared", "meshes", "large", "igea.ply")
            subprocess.run([limn, "subdivide", src, "-o", mesh, "--levels", "2", "-q"], check=True)

    env = dict(os.environ)
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    env.setdefault("POCL_CACHE_DIR", os.path.join(args.build, "pocl-cache"))
    env.pop("POCL_MAX_PTHREAD_COUNT", None)
    common = [bench, mesh, "--tol", args.tol, "--repeat", args.repeat, "--method", args.method]

    print(f"mesh: {mesh}")
    env2 = dict(env, POCL_MAX_PTHREAD_COUNT="2")
    configs = [("1 rank, 1 core", ["mpirun", "-np", "1", "--bind-to", "core"], env),
               ("2 ranks, 1 core each", ["mpirun", "-np", "2", "--bind-to", "core"], env),
               ("1 rank, 2 PoCL threads", ["mpirun", "-np", "1", "--bind-to", "none"], env2)]
    # the machine is shared: the configurations take turns for --rounds rounds and
    # each keeps its best round (least time per iteration of the slowest rank)
    runs, best = {}, {}
    for k in range(int(args.rounds)):
        cores = effective_cores()
        print(f"round {k + 1}: cores available {cores:.2f} of {os.cpu_count()} "
              f"(two busy processes vs one)", flush=True)
        for name, launcher, e in configs:
            lines = run_json(launcher + common, e)
            t = [r for r in lines if r.get("summary")][0]["seconds_per_iteration"]
            if name not in best or t < best[name]:
                best[name] = t
                runs[name] = lines

    print()
    print("| run | rank | owned | ghosts | halo B/iter out / in | s/iter | compute | halo "
          "(of which waiting) | reduce |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    summary = {}
    for name, lines in runs.items():
        for r in lines:
            if r.get("summary"):
                summary[name] = r
                continue
            print(f"| {name} | {r['rank']} | {r['owned']:,} | {r['ghosts']:,} | "
                  f"{r['halo_bytes_sent']:,} / {r['halo_bytes_received']:,} | "
                  f"{r['seconds_per_iteration']:.4f} | {r['compute_per_exchange']:.4f} | "
                  f"{r['halo_per_exchange']:.4f} ({r['wait_per_exchange']:.4f}) | "
                  f"{r['reduce_per_exchange']:.5f} |")
    base = summary["1 rank, 1 core"]["seconds_per_iteration"]
    print()
    for name, s in summary.items():
        print(f"{name}: {s['seconds_per_iteration']:.4f} s per iteration, "
              f"{s['iterations']} iterations, speed-up {base / s['seconds_per_iteration']:.2f}")
    one = [r for r in runs["1 rank, 1 core"] if not r.get("summary")][0]
    two = [r for r in runs["2 ranks, 1 core each"] if not r.get("summary")]
    print(f"setup on rank 0 (operator, RCM decision, METIS, plan): "
          f"{two[0]['seconds_partition']:.2f} s; distribution and upload: "
          f"{max(r['seconds_distribute'] for r in two):.2f} s")

    # Projection. Per-row compute cost from the 1-rank run (one core); at P ranks,
    # one core each, the slowest rank computes owned_max rows. Its halo costs the
    # handling measured at 2 ranks per ghost or sent value (device read and write,
    # packing; waiting excluded), a latency per message and the bytes over the
    # network; one Allreduce costs log2(P) latencies. Compute is not assumed to
    # hide the halo (the transfer completes in MPI_Waitall).
    t_row = one["compute_per_exchange"] / one["owned"]
    t_value = max((r["halo_per_exchange"] - r["wait_per_exchange"]) /
                  (r["ghosts"] + r["halo_bytes_sent"] / 24) for r in two)
    lat = args.latency_us * 1e-6
    bw = args.bandwidth_gbs * 1e9
    print()
    print(f"projection (one core per rank with the per-row compute of the 1-rank run, "
          f"{t_row * 1e9:.1f} ns; halo handling {t_value * 1e9:.0f} ns per value as measured "
          f"at 2 ranks; network {args.latency_us:g} us per message and "
          f"{args.bandwidth_gbs:g} GB/s per rank; Allreduce log2(P) latencies):")
    print("| ranks | owned max | ghosts max (mean) | neighbours max | edge cut | halo B/iter "
          "| compute s | halo s | reduce s | s/iter | speed-up | efficiency |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    t1 = one["compute_per_exchange"]
    for p in (2, 4, 8, 16, 32, 64):
        part = run_json([bench, mesh, "--parts", str(p)], env)[0]
        values = 2 * part["ghosts_max"]  # received, and about as many sent
        halo_bytes = 24 * values
        comp = t_row * part["owned_max"]
        halo = t_value * values + part["neighbours_max"] * 2 * lat + halo_bytes / bw
        red = math.log2(p) * lat
        t = comp + halo + red
        print(f"| {p} | {part['owned_max']:,} | {part['ghosts_max']:,} ({part['ghosts_mean']:,.0f}) "
              f"| {part['neighbours_max']} | {part['edge_cut']:,} | {halo_bytes:,} | {comp:.5f} | "
              f"{halo:.5f} | {red:.6f} | {t:.5f} | {t1 / t:.1f} | {t1 / t / p:.0%} |")
    setup = two[0]["seconds_partition"] + max(r["seconds_distribute"] for r in two)
    print(f"serial setup on rank 0 + distribution: {setup:.2f} s, against "
          f"{summary['1 rank, 1 core']['iterations']} iterations x the projected time per "
          f"iteration at 64 ranks: build once, solve many times (series, morph frames, "
          f"texture levels), or build the rows on each rank (test_local_rows).")


# ---- the distributed pipeline (--pipeline): no rank holds the whole mesh ----

def pipeline_inputs(args):
    """The scanner-layout float32 PLYs (2.1M at /tmp/limn_read_bench, 8.6M at
    /tmp/limn_e2e), made by perf/end_to_end.py's make_inputs when missing."""
    sys.path.insert(0, os.path.join(ROOT, "perf"))
    from end_to_end import make_inputs
    igea = os.path.join(ROOT, "..", "shared", "meshes", "large", "igea.ply")
    return make_inputs(argparse.Namespace(build=args.build, mesh=igea,
                                          only=["2.1M"] if args.skip_8m else None))


def interpolate(limn, ranks, path, tmp, env, tol, root=False, bound=False):
    """One `limn interpolate --precision double` (plain for 1 rank, else under
    mpirun, a core a rank, oversubscribed beyond the cores; root: the input on standard input, which takes the
    root path, rank 0 reading and building everything; bound: 1 rank under
    `mpirun --bind-to core`, one core as each rank of the 2-rank run has: the
    strong-scaling baseline); returns (report, output path, wall seconds)."""
    out = os.path.join(tmp, f"out_{ranks}{'_root' if root else ''}{'_bound' if bound else ''}.ply")
    rep = os.path.join(tmp, f"report_{ranks}.json")
    src = ["-", "--input-format", "ply"] if root else [path]
    cmd = [limn, "interpolate"] + src + ["-o", out, "--report", rep, "--precision", "double",
                                          "-q"]
    if tol:
        cmd += ["--tol", tol]
    if ranks > 1:  # one core a rank while the cores last, as the 1-core baseline has
        bind = ["--bind-to", "core"] if ranks <= (os.cpu_count() or 1) else \
            ["--oversubscribe", "--bind-to", "none"]
        cmd = ["mpirun", "-np", str(ranks)] + bind + cmd
    elif bound:
        cmd = ["mpirun", "-np", "1", "--bind-to", "core"] + cmd
    t0 = time.time()
    with open(path, "rb") as stdin:
        r = subprocess.run(cmd, env=env, stdin=stdin if root else subprocess.DEVNULL,
                           capture_output=True)
    if r.returncode:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}): {r.stderr[-2000:].decode()}")
    return json.load(open(rep)), out, time.time() - t0


def single_row(rep, wall, bound=False):
    s = rep["seconds"]
    # the device's opening too: a distributed rank opens it in its local rows
    # (mpi_open_rows), the single process in its solve (opencl_setup)
    parts = {"load": s["load"], "topology": s.get("topology", 0),
             "stencil": s.get("stencil", 0), "device": s.get("opencl_setup", 0)}
    return {"ranks": 1, "path": "1 core" if bound else "single", "vertices": rep["vertices"],
            "iterations": rep["iterations"],
            "method": rep["method"], "wall": wall, "seconds": s,
            "peak_bytes": [rep["peak_rss_bytes"]], "setup": [sum(parts.values())],
            "setup_parts": [parts],
            "solve": [s["solve"]], "owned": [rep["vertices"]], "ghosts": [0],
            "halo_bytes_sent": [0], "halo_bytes_received": [0], "neighbours": [0]}


def ranks_row(rep, wall, root=False):
    if "mpi" not in rep:
        sys.exit("the report has no mpi object: is limn built with LIMN_MPI?")
    per = rep["mpi"]["per_rank"]
    if root:  # rank 0 read and repaired the whole mesh
        for r in per:
            r["seconds_load"] = rep["seconds"]["load"] if r["rank"] == 0 else 0.0
    row = {"ranks": len(per), "vertices": rep["vertices"], "iterations": rep["iterations"],
           "path": "root" if root else "distributed",
           "method": rep["method"], "wall": wall, "seconds": rep["seconds"],
           "edge_cut": rep["mpi"]["edge_cut"], "per_rank": per}
    for key in ("owned", "ghosts", "halo_bytes_sent", "halo_bytes_received", "neighbours"):
        row[key] = [r[key] for r in per]
    row["peak_bytes"] = [r["peak_rss_bytes"] for r in per]
    row["setup_parts"] = [{"load": r["seconds_load"], "partition": r["seconds_partition"],
                           "local_rows": r["seconds_distribute"]} for r in per]
    row["setup"] = [sum(p.values()) for p in row["setup_parts"]]
    row["solve"] = [r["seconds_solve"] for r in per]
    return row


def thp_faults():
    """Transparent huge pages faulted in so far, machine-wide (/proc/vmstat's
    thp_fault_alloc; None where absent): each a fresh 2 MiB page cleared, which
    on this VM the host backs first (docs/mpi.md, "Set-up, 2026-12-05
    (session 20)")."""
    try:
        with open("/proc/vmstat") as f:
            for line in f:
                if line.startswith("thp_fault_alloc "):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def same_bytes(a, b):
    return subprocess.run(["cmp", "-s", a, b]).returncode == 0


def run_pipeline(args, limn, env):
    rows = []
    # (ranks, root path, bound to one core): the root path at 2 ranks is the set-up
    # issue 14 replaces; 1 rank bound to one core is the strong-scaling baseline
    plan = [("2.1M", [(1, 0, 0), (1, 0, 1), (2, 0, 0), (4, 0, 0), (2, 1, 0)]),
            ("8.6M", [(1, 0, 0), (1, 0, 1), (2, 0, 0), (8, 0, 0)])]
    files = pipeline_inputs(args)
    for name, counts in plan:
        if name not in files:
            continue
        with tempfile.TemporaryDirectory(prefix="limn_scaling_", dir=args.tmp) as tmp:
            # a run first, not kept: a VM that hands freed memory back to its host
            # (free page reporting) makes the first run after an idle spell pay for
            # fresh memory the later ones do not (docs/performance.md "First touch")
            interpolate(limn, 1, files[name], tmp, env, args.tol_pipe)
            ref, runs = None, {c: [] for c in counts}
            # rounds taking turns, each configuration's median kept: this VM's
            # fresh memory makes single runs vary by 1.5x (docs/performance.md)
            for k in range(args.pipeline_rounds):
                # each round starts one configuration later: on this VM a run's
                # fresh memory depends on the run before it (one core after the
                # 2-thread process: its stencil stage 0.35-0.45 s in every round,
                # 0.07 s after other runs), so no configuration always follows
                # the same one (the first round starts with the single process,
                # the reference of the bytes and peaks)
                for ranks, root, bound in counts[k % len(counts):] + counts[:k % len(counts)]:
                    thp0 = thp_faults()
                    rep, out, wall = interpolate(limn, ranks, files[name], tmp, env,
                                                 args.tol_pipe, root, bound)
                    thp1 = thp_faults()
                    row = (single_row(rep, wall, bound) if ranks == 1
                           else ranks_row(rep, wall, root))
                    row["mesh"], row["file"] = name, files[name]
                    # the whole run's, every process's (the machine is otherwise quiet)
                    row["fresh_huge_mib"] = 2 * (thp1 - thp0) if thp0 is not None and \
                        thp1 is not None else None
                    row["load_average"] = os.getloadavg()[0]
                    row["output_bytes"] = os.path.getsize(out)
                    row["input_bytes"] = os.path.getsize(files[name])
                    if ref is None:
                        ref, base = out, row
                    row["same_bytes"] = same_bytes(ref, out)
                    row["peak_ratio"] = max(row["peak_bytes"]) / base["peak_bytes"][0]
                    runs[(ranks, root, bound)].append(row)
                    print(f"{name}, {ranks} rank(s) ({row['path']}), round {k + 1}: "
                          f"{wall:.1f} s wall, set-up {max(row['setup']):.2f} s, load average "
                          f"{row['load_average']:.1f}, worst peak "
                          f"{max(row['peak_bytes']) / 2**20:,.0f} MiB "
                          f"({row['peak_ratio']:.2f}x), fresh huge pages "
                          f"{row['fresh_huge_mib'] if row['fresh_huge_mib'] is not None else '?'}"
                          f" MiB, same bytes: {row['same_bytes']}",
                          flush=True)
            for c in counts:
                got = sorted(runs[c], key=lambda r: max(r["setup"]))
                row = got[len(got) // 2]
                row["setup_rounds"] = [max(r["setup"]) for r in runs[c]]
                row["fresh_huge_mib_rounds"] = [r["fresh_huge_mib"] for r in runs[c]]
                row["setup_best_stages"] = best_stages(runs[c])
                row["rounds_setup_parts"] = [r["setup_parts"] for r in runs[c]]
                row["same_bytes"] = all(r["same_bytes"] for r in runs[c])
                rows.append(row)
    return rows


def best_stages(rounds):
    """The worst rank's set-up with each stage at its best round: this VM's
    fresh memory comes at 0.4-16 GB/s from minute to minute (the host backs the
    pages or not; docs/performance.md "First touch"), and a stage that lands on
    slow pages in one round lands on fast ones in another, so the sum of the
    stages' best rounds is the set-up where fresh memory is fast (bare metal)."""
    ranks = len(rounds[0]["setup_parts"])
    return max(sum(min(r["setup_parts"][k][stage] for r in rounds)
                   for stage in rounds[0]["setup_parts"][k]) for k in range(ranks))


def print_measured(rows):
    print()
    print("| mesh | ranks | path | same bytes | peak MiB per rank | worst / 1 process | "
          "set-up s per "
          "rank (load + partition + local rows), the median round | worst rank's set-up, "
          "every round | fresh huge-page MiB, all ranks, every round | owned per rank | "
          "ghosts per rank | halo B sent per exchange | solve s | iterations |")
    print("|---|---:|---|---|---|---:|---|---|---|---|---|---|---:|---:|")
    for r in rows:
        mib = " / ".join(f"{b / 2**20:,.0f}" for b in r["peak_bytes"])
        if r["ranks"] == 1:
            p = r["setup_parts"][0]
            setup = f"{r['setup'][0]:.2f} ({p['load']:.2f} + {p['topology']:.2f} topology + " \
                    f"{p['stencil']:.2f} stencil + {p['device']:.2f} device)"
        else:
            setup = " / ".join(f"{s:.2f} ({p['load']:.2f} + {p['partition']:.2f} + "
                               f"{p['local_rows']:.2f})"
                               for s, p in zip(r["setup"], r["setup_parts"]))
        j = lambda k: " / ".join(f"{v:,}" for v in r[k])
        same = "yes" if r["same_bytes"] else "NO"
        print(f"| {r['mesh']} | {r['ranks']} | {r['path']} | {same} | {mib} | "
              f"{r['peak_ratio']:.2f} | {setup} | "
              f"{', '.join(f'{v:.2f}' for v in r['setup_rounds'])} | "
              f"{', '.join('?' if v is None else f'{v:,}' for v in r['fresh_huge_mib_rounds'])} | "
              f"{j('owned')} | {j('ghosts')} | "
              f"{j('halo_bytes_sent')} | {max(r['solve']):.2f} | {r['iterations']} |")


def fitted_costs(rows, args):
    """Per-rank unit costs from the measured runs (docs/mpi.md, "Model")."""
    two = [r for r in rows if r["ranks"] == 2 and r["path"] == "distributed"][0]
    single = [r for r in rows if r["ranks"] == 1][0]
    n = two["vertices"]
    c = {"iterations": single["iterations"], "vertices_measured": n}
    block = n / 2
    parts = two["setup_parts"]
    c["load_per_vertex"] = max(p["load"] for p in parts) / block
    c["partition_per_vertex"] = max(p["partition"] for p in parts) / block
    c["rows_per_vertex"] = max(p["local_rows"] / o for p, o in zip(parts, two["owned"]))
    per = two["per_rank"]
    c["exchanges_per_iteration"] = per[0]["exchanges"] / max(1, two["iterations"])
    c["product_per_row"] = max(r["seconds_compute"] / r["exchanges"] / r["owned"] for r in per)
    vb = per[0]["halo_bytes_received"] / max(1, per[0]["ghosts"])
    c["bytes_per_value"] = vb
    c["halo_per_value"] = max((r["seconds_halo"] - r["seconds_wait"]) / r["exchanges"] /
                              (r["ghosts"] + r["halo_bytes_sent"] / vb) for r in per)
    mpi = [r for r in rows if r["path"] == "distributed"]
    c["ghost_coefficient"] = max(g / math.sqrt(o) for r in mpi for g, o in
                                 zip(r["ghosts"], r["owned"]))
    c["neighbours"] = max(args.neighbours, max(max(r["neighbours"]) for r in mpi))
    # peak bytes = base + slope x block vertices, least squares over every rank measured
    xs = [r["vertices"] / r["ranks"] for r in mpi for _ in r["peak_bytes"]]
    ys = [b for r in mpi for b in r["peak_bytes"]]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else my / mx
    c["memory_per_vertex"], c["memory_base"] = slope, my - slope * mx
    c["input_bytes_per_vertex"] = single["input_bytes"] / n
    c["output_bytes_per_vertex"] = single["output_bytes"] / n
    return c


def model_row(c, p, n, args):
    lat, bw = args.latency_us * 1e-6, args.bandwidth_gbs * 1e9
    v = n / p
    ghosts = c["ghost_coefficient"] * math.sqrt(v)
    if args.partition_model == "scotch":  # PT-Scotch's per-vertex cost grows as log2 P (assumed)
        part = v * c["partition_per_vertex"] * math.log2(p)
    else:  # the curve: O(v), the top-bit histogram's Allreduce (2^16 counts), then 10
        # digits of (P - 1) x 255 binary searches (in a bucket: log2 v at most) and an
        # Allreduce each
        part = (v * c["partition_per_vertex"] + 10 * (p - 1) * 255 * math.log2(v) * 5e-9 +
                math.log2(p) * lat + 65536 * 8 / bw +
                10 * (math.log2(p) * lat + (p - 1) * 255 * 8 / bw))
    setup = v * (c["load_per_vertex"] + c["rows_per_vertex"]) + part
    values = 2 * ghosts
    halo = (c["halo_per_value"] * values + c["neighbours"] * 2 * lat +
            values * c["bytes_per_value"] / bw)
    reduce = math.log2(p) * lat
    exchange = c["product_per_row"] * v + halo + reduce
    nodes = max(1, p // args.ranks_per_node)
    io_bw = min(args.fs_aggregate_gbs, nodes * args.fs_node_gbs) * 1e9
    io = n * (c["input_bytes_per_vertex"] + c["output_bytes_per_vertex"]) / io_bw
    k = c["exchanges_per_iteration"]  # products (halo exchanges) an iteration
    solve = exchange * k * c["iterations"]
    return {"ranks": p, "nodes": nodes, "vertices_per_rank": v, "ghosts_per_rank": ghosts,
            "memory_per_rank": c["memory_base"] + c["memory_per_vertex"] * v,
            "setup": setup, "seconds_per_iteration": exchange * k,
            "compute": c["product_per_row"] * v * k, "halo": halo * k, "reduce": reduce * k,
            "io": io, "solve": solve, "total": setup + solve + io}


def print_model(c, args):
    n = args.model_vertices
    print()
    print(f"model at {n:.3g} vertices (unit costs from the 2-rank run; {args.latency_us:g} us "
          f"a message, {args.bandwidth_gbs:g} GB/s network per rank; file system "
          f"{args.fs_aggregate_gbs:g} GB/s aggregate, {args.fs_node_gbs:g} GB/s per node, "
          f"{args.ranks_per_node} ranks a node; {c['iterations']} iterations; partition "
          f"grows as {args.partition_model}'s):")
    print("| ranks | nodes | vertices / rank | ghosts / rank | memory / rank | set-up s | "
          "s / iteration (compute + halo + reduce) | solve s | I/O s | total s |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    out = []
    for p in (16, 32, 64, 128, 256, 512, 1024):
        m = model_row(c, p, n, args)
        out.append(m)
        print(f"| {p} | {m['nodes']} | {m['vertices_per_rank']:,.0f} | "
              f"{m['ghosts_per_rank']:,.0f} | {m['memory_per_rank'] / 2**30:.1f} GiB | "
              f"{m['setup']:.1f} | {m['seconds_per_iteration']:.4f} ({m['compute']:.4f} + "
              f"{m['halo']:.4f} + {m['reduce']:.6f}) | {m['solve']:.2f} | {m['io']:.1f} | "
              f"{m['total']:.1f} |")
    return out


def print_setup_scaling(mesh, rows):
    """Issue 14's set-up target, 1 -> 2 ranks, on one mesh's rows."""
    two = [r for r in rows if r["ranks"] == 2 and r["path"] == "distributed"]
    one = [r for r in rows if r["ranks"] == 1 and r["path"] == "single"]
    if not two or not one:
        return
    two, one = two[0], one[0]
    core = [r for r in rows if r["path"] == "1 core"]
    root = [r for r in rows if r["path"] == "root"]
    print(f"{mesh}: set-up (medians), 1 -> 2 ranks: {one['setup'][0]:.2f} s -> "
          f"{max(two['setup']):.2f} s (worst rank)" +
          (f"; 1 rank on one core: {core[0]['setup'][0]:.2f} s: 2 ranks "
           f"{max(two['setup']) / core[0]['setup'][0]:.2f}x" if core else "") +
          (f"; the root path at 2 ranks: {max(root[0]['setup']):.2f} s" if root else ""))
    if core:  # the comparison without this VM's slow fresh memory (best_stages)
        print(f"{mesh}: set-up, each stage at its best round (fast fresh memory): 1 rank on "
              f"one core {core[0]['setup_best_stages']:.2f} s, 2 ranks "
              f"{two['setup_best_stages']:.2f} s (worst rank): "
              f"{two['setup_best_stages'] / core[0]['setup_best_stages']:.2f}x")
        # the configurations take turns within a round: round k of each is a pair
        pairs = list(zip(core[0]["setup_rounds"], two["setup_rounds"]))
        below = sum(b < a for a, b in pairs)
        ratio, low, high = ratio_interval(pairs)
        print(f"{mesh}: set-up, round by round: 2 ranks below 1 rank on one core in "
              f"{below} of {len(pairs)} rounds (one-sided sign test p = "
              f"{sign_test(below, len(pairs)):.3f}); the rounds' ratios 2 ranks / 1 core: "
              f"median {ratio:.2f}x, 90% bootstrap interval {low:.2f}-{high:.2f}x")


def sign_test(below, n):
    """P(at least `below` of n rounds lower) if either configuration were as
    likely to be the faster in a round: how surprising the count is by chance."""
    return sum(math.comb(n, k) for k in range(below, n + 1)) / 2 ** n


def ratio_interval(pairs, draws=4000):
    """The median of the rounds' ratios (second / first: a round's pair ran
    back to back, so the VM's drift between rounds cancels) and a 90% interval
    of it by resampling the rounds (seeded: the same rounds print the same)."""
    ratios = [b / a for a, b in pairs]
    rng = random.Random(14)
    medians = sorted(statistics.median(rng.choices(ratios, k=len(ratios)))
                     for _ in range(draws))
    return (statistics.median(ratios), medians[int(0.05 * draws)],
            medians[int(0.95 * draws) - 1])


def pipeline(args, limn, env):
    print(f"distributed pipeline, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"{os.cpu_count()} cores (ranks beyond them oversubscribed: memory is exact, times "
          f"are shared cores')", flush=True)
    rows = run_pipeline(args, limn, env)
    print_measured(rows)
    for mesh in dict.fromkeys(r["mesh"] for r in rows):  # 1 -> 2 ranks, each mesh
        print_setup_scaling(mesh, [r for r in rows if r["mesh"] == mesh])
    costs = fitted_costs(rows, args)
    print("unit costs: " + ", ".join(f"{k} {v:.4g}" for k, v in costs.items()))
    model = print_model(costs, args)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"measured": rows, "unit_costs": costs, "model": model,
                       "assumptions": {k: getattr(args, k) for k in
                                       ("latency_us", "bandwidth_gbs", "fs_aggregate_gbs",
                                        "fs_node_gbs", "ranks_per_node", "neighbours",
                                        "model_vertices")}}, f, indent=1)
    return rows


if __name__ == "__main__":
    main()

# SPDX-License-Identifier: MIT
"""Command-line options the perf scripts share: the build folder, the shared
meshes and the size cap of the scale runs, and the operator exporter."""
import argparse
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def parser(doc):
    """A parser described by the first line of doc, with --build."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    return ap


def scale_parser(doc):
    """parser(doc) with --meshes (the shared meshes) and --max-size."""
    ap = parser(doc)
    ap.add_argument("--meshes", default=os.environ.get(
        "LIMN_SHARED_MESHES", os.path.join(ROOT, "..", "shared", "meshes")))
    ap.add_argument("--max-size", type=float, default=9e6)
    return ap


def operator_args(doc, default_meshes):
    """Parses --build and MESH:SCHEME ...; returns (args, the path of
    perf/export_operator), exiting when it is not built."""
    ap = parser(doc)
    ap.add_argument("meshes", nargs="*", default=default_meshes)
    args = ap.parse_args()
    exporter = os.path.join(args.build, "perf", "export_operator")
    if not os.path.exists(exporter):
        sys.exit(f"{exporter} is missing: bash scripts/build.sh -DLIMN_BUILD_PERF=ON")
    return args, exporter


def exported_operators(meshes, exporter, shared):
    """For each MESH:SCHEME (a path, or a name under shared/medium): yields the
    name, the scheme and the file perf/export_operator wrote the operator to
    (in a temporary folder, overwritten by the next mesh's)."""
    with tempfile.TemporaryDirectory() as tmp:
        for item in meshes:
            name, scheme = item.rsplit(":", 1)
            path = name if os.path.exists(name) else os.path.join(shared, "medium", name)
            out = os.path.join(tmp, "op.bin")
            subprocess.run([exporter, path, scheme, out], check=True)
            yield name, scheme, out

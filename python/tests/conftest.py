# SPDX-License-Identifier: MIT
"""Shared fixtures: the meshes (the shared small meshes when present, else
the repository's data/), the CLI to compare with, scratch files."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def mesh_dir():
    """LIMN_SHARED_MESHES/small, ../shared/meshes/small beside the repository,
    else the repository's data/ (spot_control_mesh.obj)."""
    for base in (os.environ.get("LIMN_SHARED_MESHES"), REPO.parent / "shared" / "meshes"):
        if base and (pathlib.Path(base) / "small").is_dir():
            return pathlib.Path(base) / "small"
    return REPO / "data"


def meshes():
    exts = (".obj", ".ply", ".off", ".stl")
    return sorted(p for p in mesh_dir().iterdir() if p.suffix.lower() in exts)


MESHES = meshes()
SPOT = REPO / "data" / "spot_control_mesh.obj"  # 188 vertices: tri, quad, pentagon faces


def cli_path():
    """LIMN_CLI, else the repository's build/limn."""
    p = os.environ.get("LIMN_CLI") or str(REPO / os.environ.get("LIMN_BUILD_DIR", "build") / "limn")
    if not os.access(p, os.X_OK):
        pytest.fail("the limn CLI to compare with is not at %s: build it (bash scripts/build.sh) "
                    "or set LIMN_CLI" % p)
    return p


@pytest.fixture(scope="session")
def cli():
    path = cli_path()

    def run(*args, check=True):
        r = subprocess.run([path, *map(str, args), "-q"], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError("limn %s failed (%d): %s" % (" ".join(map(str, args)),
                                                               r.returncode, r.stderr))
        return r

    return run

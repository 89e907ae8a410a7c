#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The Python package's tests (docs/python.md): a fresh virtual environment
# under the build directory, `pip install ./python` (builds the C library and
# the extension, warnings as errors), pytest, numpy and trimesh from PyPI,
# then python/tests with the CLI of the build directory to compare with.
#   scripts/test_python.sh        (after scripts/build.sh: needs build/limn)
# LIMN_BUILD_DIR (build), LIMN_PYTHON (python3) override.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${LIMN_BUILD_DIR:-build}
py=${LIMN_PYTHON:-python3}
if [[ ! -x $build/limn ]]; then
    echo "limn: $build/limn is missing: run scripts/build.sh first (the tests compare with the CLI)" >&2
    exit 1
fi
build=$(cd "$build" && pwd)
venv=$build/python-venv
repo=$(pwd)
rm -rf "$venv"
"$py" -m venv "$venv"
"$venv/bin/python" -m pip install -q pytest numpy trimesh
"$venv/bin/python" -m pip install -q --config-settings=cmake.define.LIMN_PYTHON_WERROR=ON ./python
# from a neutral directory: the installed package is tested, not python/src
cd "$venv"
LIMN_CLI=$build/limn "$venv/bin/python" -m pytest -q -p no:cacheprovider "$repo/python/tests"

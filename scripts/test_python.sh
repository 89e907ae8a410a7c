#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The Python package's tests (docs/python.md): a fresh virtual environment
# under the build directory, `pip install ./python` (builds the C library and
# the extension, warnings as errors), pytest, numpy and trimesh from PyPI,
# then python/tests with the CLI of the build directory to compare with; then
# once more with the library and the extension under ASan + UBSan
# (LIMN_PYTHON_SANITIZE=0 skips that).
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
if [[ "${LIMN_PYTHON_SANITIZE:-1}" != 0 ]]; then
    # again with the library and the extension under ASan + UBSan: built
    # beside the venv (--target, no build isolation: no second download) and
    # put first on the venv's path; the runtimes preloaded into python; leaks
    # not checked (the interpreter keeps memory of its own); the leak test
    # left out, since ASan's quarantine holds freed memory by design
    echo "== limn: the Python package under AddressSanitizer + UBSan"
    asan=$build/python-asan
    cd "$repo"
    rm -rf "$asan"
    "$venv/bin/python" -m pip install -q scikit-build-core
    "$venv/bin/python" -m pip install -q --no-deps --no-build-isolation --target "$asan" \
        --config-settings=cmake.define.LIMN_SANITIZE=ON \
        "--config-settings=cmake.define.CMAKE_C_FLAGS=-fsanitize=address,undefined -fno-omit-frame-pointer" \
        --config-settings=cmake.define.LIMN_PYTHON_WERROR=ON --config-settings=install.strip=false \
        ./python
    cd "$venv"
    export PYTHONPATH=$asan ASAN_OPTIONS=detect_leaks=0:halt_on_error=1 \
        UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
        LD_PRELOAD="$(gcc -print-file-name=libasan.so) $(gcc -print-file-name=libubsan.so)"
    # the sanitized extension is the one imported
    "$venv/bin/python" -c "import sys, limn._limn as m; sys.exit(not m.__file__.startswith('$asan'))"
    LIMN_CLI=$build/limn "$venv/bin/python" -m pytest -q -p no:cacheprovider \
        -k "not test_no_leak_over_1000_calls" "$repo/python/tests"
fi

#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian packages limn needs that are missing (as root, or via sudo).
#   scripts/deps.sh          build + run dependencies
#   scripts/deps.sh --test   also the test-only ones (cmocka, OpenSubdiv, clang
#                            and its libFuzzer runtime for scripts/fuzz.sh,
#                            Oclgrind for tests/test_oclgrind.sh), and
#                            Open MPI + METIS + PT-Scotch so that the MPI layer is built and
#                            tested (optional for users: LIMN_MPI, README "MPI"),
#                            and locales (test_locale generates de_DE.UTF-8),
#                            and python3-venv + python3-dev for the Python
#                            package's tests (scripts/test_python.sh)
set -euo pipefail

packages=(gcc g++ make cmake pkg-config ocl-icd-opencl-dev opencl-headers pocl-opencl-icd
          libhwloc-dev)
if [[ "${1:-}" == "--test" ]]; then
    packages+=(libcmocka-dev libosd-dev clang-14 libclang-rt-14-dev oclgrind
               libopenmpi-dev openmpi-bin libmetis-dev libptscotch-dev locales python3-venv
               python3-dev)
fi

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
if [[ ${#missing[@]} -eq 0 ]]; then
    exit 0
fi

echo "limn: installing missing packages: ${missing[*]}" >&2
if [[ $(id -u) -eq 0 ]]; then
    as_root=()
elif command -v sudo >/dev/null; then
    as_root=(sudo)
else
    echo "limn: not root and no sudo: install these as root: apt-get install -y ${missing[*]}" >&2
    exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null

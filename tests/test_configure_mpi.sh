#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# A build directory configured while MPI was missing picks the MPI layer up
# once it is installed (scripts/demo.sh before scripts/test.sh, the README's
# order): configure with MPI hidden, then again with it visible, in a fresh
# build directory; LIMN_MPI stays AUTO in the cache and the layer is on.
#   test_configure_mpi.sh CMAKE SOURCE_DIR
set -euo pipefail
cmake=$1 src=$2
tmp=$(mktemp -d "${TMPDIR:-/tmp}/limn_configure.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "test_configure_mpi: $*" >&2; exit 1; }

"$cmake" -S "$src" -B "$tmp" -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON >"$tmp/first.log" 2>&1 ||
    { cat "$tmp/first.log"; fail "first configure failed"; }
grep -q "limn: MPI layer off: no MPI C library" "$tmp/first.log" ||
    { cat "$tmp/first.log"; fail "MPI hidden, yet the layer was not reported off"; }
"$cmake" -S "$src" -B "$tmp" -DCMAKE_DISABLE_FIND_PACKAGE_MPI=OFF >"$tmp/second.log" 2>&1 ||
    { cat "$tmp/second.log"; fail "second configure failed"; }
grep -q "limn: MPI layer on" "$tmp/second.log" ||
    { cat "$tmp/second.log"; fail "MPI installed, yet the cached build directory left the layer off"; }
grep -q "^LIMN_MPI:STRING=AUTO$" "$tmp/CMakeCache.txt" || fail "LIMN_MPI is not AUTO in the cache"
"$cmake" -S "$src" -B "$tmp" -DLIMN_MPI=OFF >"$tmp/third.log" 2>&1 ||
    { cat "$tmp/third.log"; fail "configure with -DLIMN_MPI=OFF failed"; }
grep -q "limn: MPI layer off (-DLIMN_MPI=OFF)" "$tmp/third.log" || fail "-DLIMN_MPI=OFF was not obeyed"
echo "test_configure_mpi: AUTO re-decided at each configure, OFF obeyed"

#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The CLI is a client of the public API only (issue 12.4): `cmake --install`
# into a fresh prefix, then host/cli/*.c (copied away from host/, with
# cli_mpi_none.c: the MPI layer is not installed) compiled with the system
# compiler against ONLY the installed headers (-I PREFIX/include) and linked
# with the installed liblimn.so (-llimn -lm). That limn must print the same
# --version and write the same bytes for one interpolate as the in-tree one.
#   test_cli_installed.sh BUILD_DIR SOURCE_DIR C_COMPILER IN_TREE_LIMN [FLAGS]
# FLAGS go to the compile and link lines: the sanitizer flags when the library
# was built with -DLIMN_SANITIZE=ON, as in test_install.sh.
set -euo pipefail
build=$1 src=$2 cc=$3 intree=$4 flags="${5:-}"
# shellcheck source=install_prefix.sh
source "$(dirname "${BASH_SOURCE[0]}")/install_prefix.sh"
install_prefix cli_installed "$build"
[[ -f $prefix/include/limn.h ]] || fail "no limn.h under $prefix/include"

# the CLI's own files only: nothing of host/ can be found beside them
mkdir "$tmp/cli"
cp "$src"/host/cli/*.c "$src"/host/cli/*.h "$tmp/cli/"
rm "$tmp/cli/cli_mpi.c" "$tmp/cli/cli_mpi_sliced.c"
# shellcheck disable=SC2086 # FLAGS is a list of flags
if ! "$cc" -std=c11 -Wall -Wextra -Wpedantic -Werror -O2 -D_POSIX_C_SOURCE=200809L \
        -I"$prefix/include" $flags "$tmp"/cli/*.c -o "$tmp/limn" \
        -L"$libdir" -llimn -lm -Wl,-rpath,"$libdir" >"$tmp/cc.log" 2>&1; then
    cat "$tmp/cc.log"
    fail "the CLI does not build against the installed headers and liblimn.so"
fi
needed=$(objdump -p "$tmp/limn" | awk '$1 == "NEEDED" {print $2}' | tr '\n' ' ')
[[ $needed == *liblimn.so* ]] || fail "the installed-prefix CLI does not link liblimn.so ($needed)"
resolved=$(ldd "$tmp/limn" | grep liblimn || true)
[[ $resolved == *" => $libdir/"* ]] || fail "liblimn.so is not taken from $libdir: $resolved"

v1=$("$intree" --version) || fail "in-tree limn --version failed"
v2=$("$tmp/limn" --version) || fail "installed-prefix limn --version failed"
[[ $v1 == "$v2" ]] || fail "--version differs: in-tree '$v1', installed-prefix '$v2'"
echo "limn --version: $v2"

# without an OpenCL platform both run on the reference backend
if ! "$intree" devices >"$tmp/devices.txt" 2>&1; then
    grep -q "no OpenCL platform" "$tmp/devices.txt" || { cat "$tmp/devices.txt"; fail "limn devices failed"; }
    export LIMN_DEVICE=reference
fi
mesh=$src/data/spot_control_mesh.obj
for who in intree installed; do
    bin=$intree
    [[ $who == installed ]] && bin=$tmp/limn
    "$bin" interpolate "$mesh" -o "$tmp/$who.ply" --report "$tmp/$who.json" -q \
        2>"$tmp/$who.err" || { cat "$tmp/$who.err"; fail "$who limn interpolate failed"; }
done
cmp "$tmp/intree.ply" "$tmp/installed.ply" ||
    fail "the installed-prefix CLI's control mesh differs from the in-tree CLI's"
cmp "$tmp/intree.err" "$tmp/installed.err" || fail "the two CLIs print different diagnostics"
# the reports differ in their output name, memory and timings only (the last keys)
keys() { sed '/"peak_rss_bytes"/,$d' "$1" | grep -v '^  "output": '; }
diff <(keys "$tmp/intree.json") <(keys "$tmp/installed.json") ||
    fail "the two CLIs' reports differ (above, before peak_rss_bytes)"
echo "test_cli_installed: the CLI built against $prefix (headers and liblimn.so only) writes" \
     "the in-tree CLI's bytes ($(stat -c %s "$tmp/installed.ply") bytes of $(basename "$mesh" .obj))"

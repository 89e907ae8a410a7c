#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `cmake --install` into a fresh prefix, then examples/embed built against it
# the four ways a user would: find_package with limn::limn and with
# limn::limn_static, pkg-config with limn.pc and with limn-static.pc. Each
# binary runs and must print "check: OK" (the limit of its control mesh
# reproduces its mesh); the shared builds must load liblimn.so from the
# prefix, the static ones must not need it at all.
#   test_install.sh BUILD_DIR SOURCE_DIR C_COMPILER [FLAGS]
# FLAGS go to the example's compile and link lines: the sanitizer flags when
# the library was built with -DLIMN_SANITIZE=ON (an instrumented liblimn needs
# the sanitizer runtime in the program), plus -Werror.
set -euo pipefail
build=$1 src=$2 cc=$3 flags="${4:-} -Werror"
# shellcheck source=install_prefix.sh
source "$(dirname "${BASH_SOURCE[0]}")/install_prefix.sh"
install_prefix install "$build"
for f in "$prefix/bin/limn" "$prefix/include/limn.h" "$libdir/liblimn.a" \
         "$libdir/cmake/limn/limnConfig.cmake" "$libdir/cmake/limn/limnConfigVersion.cmake" \
         "$libdir/pkgconfig/limn.pc" "$libdir/pkgconfig/limn-static.pc"; do
    [[ -f $f ]] || fail "$f was not installed"
done
echo "installed into $prefix: $(cd "$prefix" && find . -type f | sort | tr '\n' ' ')"

# without an OpenCL platform the examples run on the reference backend
if ! "$prefix/bin/limn" devices >"$tmp/devices.txt" 2>&1; then
    grep -q "no OpenCL platform" "$tmp/devices.txt" || { cat "$tmp/devices.txt"; fail "limn devices failed"; }
    export LIMN_DEVICE=reference
fi

# check_run NAME BINARY shared|static [ENV...]
check_run() {
    local name=$1 bin=$2 kind=$3
    shift 3
    local needed
    needed=$(objdump -p "$bin" | awk '$1 == "NEEDED" {print $2}' | tr '\n' ' ')
    if [[ $kind == shared ]]; then
        [[ $needed == *liblimn.so* ]] || fail "$name: does not link liblimn.so (NEEDED: $needed)"
        local resolved
        resolved=$(env "$@" ldd "$bin" | grep liblimn || true)
        [[ $resolved == *" => $libdir/"* ]] ||
            fail "$name: liblimn.so is not taken from $libdir: $resolved"
    else
        [[ $needed != *liblimn* ]] || fail "$name: needs $needed, not only the static library"
    fi
    local out rc=0
    out=$(env "$@" "$bin" 2>&1) || rc=$?
    [[ $rc -eq 0 ]] || { echo "$out"; fail "$name: exit status $rc"; }
    grep -qx "check: OK" <<<"$out" || { echo "$out"; fail "$name: no 'check: OK'"; }
    echo "$name: $(grep -m1 '^limit of P' <<<"$out"); $(grep -m1 '^threads' <<<"$out")"
}

for kind in shared static; do
    dir=$tmp/cmake-$kind
    static=OFF
    [[ $kind == static ]] && static=ON
    cmake_example "$src/examples/embed" "$dir" "$cc" "$flags" -DEMBED_STATIC=$static
    # the shared one finds liblimn.so through the RPATH CMake sets
    check_run "find_package, $kind" "$dir/embed" $kind
done

mkdir "$tmp/make"
if ! PKG_CONFIG_PATH="$libdir/pkgconfig" make -C "$tmp/make" -f "$src/examples/embed/Makefile" \
         CC="$cc" CFLAGS="-O2 $flags" LDFLAGS="$flags" >"$tmp/log" 2>&1; then
    cat "$tmp/log"
    fail "pkg-config build failed"
fi
check_run "pkg-config, shared" "$tmp/make/embed" shared LD_LIBRARY_PATH="$libdir"
check_run "pkg-config, static" "$tmp/make/embed_static" static

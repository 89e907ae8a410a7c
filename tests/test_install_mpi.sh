#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The installed MPI layer as an application uses it: `cmake --install` into a
# fresh prefix, then examples/embed_mpi built with mpicc against it by
# find_package(limn COMPONENTS mpi) (limn::mpi), COMPONENTS mpi_static
# (limn::mpi_static) and pkg-config (limn-mpi.pc); each runs under
# `mpirun -np 2` and must print "check: OK" (its control mesh over two ranks
# equals the single process's bit for bit). Then a prefix whose limn lacks
# the MPI layer must fail COMPONENTS mpi with the message that says so.
#   test_install_mpi.sh BUILD_DIR SOURCE_DIR MPICC [FLAGS]
# LIMN_MPIEXEC: the launcher, ending with its -np flag (tests/CMakeLists.txt).
set -euo pipefail
build=$1 src=$2 cc=$3 flags="${4:-} -Werror"
# shellcheck source=install_prefix.sh
source "$(dirname "${BASH_SOURCE[0]}")/install_prefix.sh"
install_prefix install_mpi "$build"
for f in "$prefix/include/limn_mpi.h" "$libdir/liblimn_mpi.so" "$libdir/liblimn_mpi.a" \
         "$libdir/cmake/limn/limnMpiTargets.cmake" "$libdir/cmake/limn/limnMpiDependencies.cmake" \
         "$libdir/pkgconfig/limn-mpi.pc"; do
    [[ -f $f ]] || fail "$f was not installed"
done
read -ra launch <<<"${LIMN_MPIEXEC:?LIMN_MPIEXEC names the MPI launcher}"
if ! "$prefix/bin/limn" devices >/dev/null 2>&1; then
    export LIMN_DEVICE=reference # no OpenCL platform: the reference backend
fi

# check_run NAME BINARY shared|static [ENV...]
check_run() {
    local name=$1 bin=$2 kind=$3
    shift 3
    local needed out rc=0
    needed=$(objdump -p "$bin" | awk '$1 == "NEEDED" {print $2}' | tr '\n' ' ')
    if [[ $kind == shared ]]; then
        [[ $needed == *liblimn_mpi.so* && $needed == *liblimn.so* ]] ||
            fail "$name: does not link liblimn_mpi.so and liblimn.so (NEEDED: $needed)"
        [[ $(env "$@" ldd "$bin" | grep liblimn_mpi) == *" => $libdir/"* ]] ||
            fail "$name: liblimn_mpi.so is not taken from $libdir"
    else
        [[ $needed != *liblimn* ]] || fail "$name: needs $needed, not only the static libraries"
    fi
    out=$(env "$@" "${launch[@]}" 2 "$bin" 2>&1) || rc=$?
    [[ $rc -eq 0 ]] || { echo "$out"; fail "$name: exit status $rc"; }
    grep -qx "check: OK" <<<"$out" || { echo "$out"; fail "$name: no 'check: OK'"; }
    echo "$name: $(grep -m1 '^single process' <<<"$out")"
}

for kind in shared static; do
    dir=$tmp/cmake-$kind static=OFF
    [[ $kind == static ]] && static=ON
    cmake_example "$src/examples/embed_mpi" "$dir" "$cc" "$flags" -DEMBED_STATIC=$static
    check_run "find_package, $kind" "$dir/embed_mpi" $kind
done

mkdir "$tmp/make"
if ! PKG_CONFIG_PATH="$libdir/pkgconfig" make -C "$tmp/make" -f "$src/examples/embed_mpi/Makefile" \
         CC="$cc" CFLAGS="-O2 $flags" LDFLAGS="$flags" >"$tmp/log" 2>&1; then
    cat "$tmp/log"
    fail "pkg-config build failed"
fi
check_run "pkg-config, shared" "$tmp/make/embed_mpi" shared LD_LIBRARY_PATH="$libdir"

# the same prefix as a limn built without the MPI layer would install it
cp -a "$prefix" "$tmp/nompi"
rm "$tmp/nompi/${libdir#"$prefix"/}"/cmake/limn/limnMpi*
if cmake -S "$src/examples/embed_mpi" -B "$tmp/cmake-nompi" -DCMAKE_PREFIX_PATH="$tmp/nompi" \
         -DCMAKE_C_COMPILER="$cc" >"$tmp/log" 2>&1; then
    fail "COMPONENTS mpi was found in a limn without the MPI layer"
fi
message=$(tr -s ' \n' ' ' <"$tmp/log") # CMake wraps the reason over lines
grep -q "was built without its MPI layer: rebuild it with -DLIMN_MPI=ON" <<<"$message" ||
    { cat "$tmp/log"; fail "no clear message for COMPONENTS mpi without the MPI layer"; }
echo "without the MPI layer: $(grep -o 'was built without its MPI layer[^(]*' <<<"$message")"

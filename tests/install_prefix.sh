# SPDX-License-Identifier: MIT
# Sourced by test_install.sh, test_install_mpi.sh and test_cli_installed.sh: `cmake --install` of
# BUILD into a fresh prefix under a temporary directory removed on exit.
#   install_prefix NAME BUILD
# sets tmp, prefix, so (the installed liblimn.so) and libdir; defines fail(),
# whose messages start with NAME.
install_prefix() {
    test_name=$1
    tmp=$(mktemp -d "${TMPDIR:-/tmp}/limn_$test_name.XXXXXX")
    trap 'rm -rf "$tmp"' EXIT
    prefix=$tmp/prefix
    cmake --install "$2" --prefix "$prefix" >"$tmp/install.log" ||
        { cat "$tmp/install.log"; fail "cmake --install failed"; }
    so=$(find "$prefix" -name 'liblimn.so' | head -n 1)
    [[ -n $so ]] || fail "no liblimn.so under $prefix"
    libdir=$(dirname "$so")
}

fail() { echo "test_$test_name: $*" >&2; exit 1; }

# cmake_example SOURCE BUILD CC FLAGS [CMAKE_ARGS...]: configures and builds an
# example against $prefix with CC and FLAGS (-Werror among them); on failure
# prints the log and fails.
cmake_example() {
    local src=$1 dir=$2 cc=$3 flags=$4
    shift 4
    if ! { cmake -S "$src" -B "$dir" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_C_COMPILER="$cc" \
                 -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_FLAGS="$flags" \
                 -DCMAKE_EXE_LINKER_FLAGS="$flags" "$@" &&
           cmake --build "$dir"; } >"$tmp/log" 2>&1; then
        cat "$tmp/log"
        fail "find_package build of $src ($*) failed"
    fi
}

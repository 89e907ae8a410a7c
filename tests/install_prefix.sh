# SPDX-License-Identifier: MIT
# Sourced by test_install.sh and test_cli_installed.sh: `cmake --install` of
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

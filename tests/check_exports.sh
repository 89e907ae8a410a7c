#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The installable libraries export exactly limn.h's API: every function the
# header marks LIMN_API is a defined global of liblimn.so (nm -D) and of
# liblimn.a, and nothing else is (internal functions are hidden in the .so and
# local in the archive, so they cannot clash with an application's symbols),
# and no function prototype of the header lacks LIMN_API. NAME (default
# limn) picks the library: limn_mpi checks liblimn_mpi.so / .a against
# limn_mpi.h (limn.h's functions are local there: liblimn.so has them).
#   check_exports.sh LIBDIR HEADER [NAME]
set -euo pipefail
libdir=$1 header=$2 name=${3:-limn}
so=$libdir/lib$name.so a=$libdir/lib$name.a
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# a prototype without LIMN_API would be hidden in liblimn.so: name it
if grep -nE '^[a-z][a-z0-9_ ]*[ *]limn_[a-z0-9_]+\(' "$header" | grep -vE ':(LIMN_API|typedef) '; then
    echo "check_exports: the declarations above in $header lack LIMN_API" >&2
    exit 1
fi
# LIMN_API declarations: the name before the first '(' of each
grep -E '^LIMN_API ' "$header" | sed -E 's/\(.*//; s/.*[ *]//' | sort -u >"$tmp/api"
# sanitizer builds add their own instrumentation symbols (reserved names)
filter() { grep -vE '^(_init|_fini|__(asan|ubsan|odr_asan|sanitizer)|___asan)' || true; }
nm -D --defined-only "$so" | awk '{print $NF}' | filter | sort -u >"$tmp/so"
nm -g --defined-only "$a" | awk 'NF == 3 {print $3}' | filter | sort -u >"$tmp/a"

status=0
for lib in so a; do
    file=$so
    [[ $lib == a ]] && file=$a
    if ! diff -u "$tmp/api" "$tmp/$lib" >"$tmp/diff"; then
        echo "check_exports: $file does not export exactly the LIMN_API functions of $header" \
             "('-' missing, '+' extra):" >&2
        grep -E '^[-+][a-zA-Z_]' "$tmp/diff" >&2 || true
        status=1
    fi
done
n=$(wc -l <"$tmp/api")
[[ $n -gt 0 ]] || { echo "check_exports: no LIMN_API function found in $header" >&2; exit 1; }
[[ $status -eq 0 ]] && echo "check_exports: lib$name.so and lib$name.a export the $n LIMN_API functions, nothing else"
exit $status

#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every kernel file states `#pragma OPENCL FP_CONTRACT OFF` itself (the
# device's results equal the C reference's only without contraction, and a
# file must not rely on being joined after another that says it).
set -euo pipefail
dir=${1:?usage: check_kernels.sh KERNEL_DIR}
bad=0
n=0
for f in "$dir"/*.cl; do
    n=$((n + 1))
    if ! grep -Eq '^[[:space:]]*#[[:space:]]*pragma[[:space:]]+OPENCL[[:space:]]+FP_CONTRACT[[:space:]]+OFF' "$f"; then
        echo "check_kernels: $f lacks '#pragma OPENCL FP_CONTRACT OFF'" >&2
        bad=1
    fi
done
[[ $n -gt 0 ]] || { echo "check_kernels: no .cl files in $dir" >&2; exit 1; }
[[ $bad -eq 0 ]] && echo "check_kernels: all $n kernel files turn FP_CONTRACT off"
exit $bad

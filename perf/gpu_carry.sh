#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# A limn to carry to a machine that cannot build it (the GPU machine of
# docs/performance.md "Kernel shapes": no OpenCL headers, hwloc or cmocka
# there, nothing to install): a Release build without MPI and tests, and the
# shared libraries it needs beside it (liblimn, the OpenCL ICD loader, hwloc,
# udev; glibc 2.34 is the newest symbol version they use).
#   bash perf/gpu_carry.sh DIR     -> DIR/limn, DIR/lib/*.so*
# (DIR inside the repository and ignored by git, e.g. build-gpu-carry, so that
# the device tool can carry it). On the other machine:
#   export LD_LIBRARY_PATH=$PWD/DIR/lib; DIR/limn devices
# and, where the driver installs no ICD file (as on the H200 machine here),
# name the vendor's library for the ICD loader:
#   mkdir -p /tmp/icd; echo /usr/local/nvidia/lib64/libnvidia-opencl.so.1 >/tmp/icd/n.icd
#   export OCL_ICD_VENDORS=/tmp/icd
# Then, e.g.: LIMN=$PWD/DIR/limn bash perf/gpu_run.sh "$OUT" (the measurement of the
# first GPU run, 2026-12-04), or perf/gpu_ab.sh with two such builds.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:?usage: gpu_carry.sh DIR}
build=$root/build-carry
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLIMN_MPI=OFF -DLIMN_BUILD_TESTS=OFF \
    >/dev/null
cmake --build "$build" -j "$(nproc)" --target limn_cli >/dev/null
mkdir -p "$dir/lib"
cp "$build/limn" "$dir/limn"
ldd "$build/limn" | awk '/=> \// {print $3}' | while read -r lib; do
    case $(basename "$lib") in
        libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|ld-linux*) ;; # the system's own
        *) cp -L "$lib" "$dir/lib/" ;;
    esac
done
echo "gpu_carry: $dir/limn and $(ls "$dir/lib" | wc -l) libraries in $dir/lib"

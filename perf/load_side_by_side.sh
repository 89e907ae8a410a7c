#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Two limn binaries side by side on the load stage, interleaved in one run
# (docs/performance.md "The whole job, end to end"): per file and repetition,
# `limn info FILE` wall seconds and `limn interpolate`'s seconds.load (read +
# repair + the run's one topology), then trimesh.load of the same file; at the
# end, whether both binaries wrote the same bytes (interpolate's output, info's
# text).
#   perf/load_side_by_side.sh BEFORE AFTER PYTHON REPS FILE...
# PYTHON: an interpreter with trimesh and numpy ("" skips trimesh).
set -euo pipefail
[ $# -ge 5 ] || { echo "usage: $0 BEFORE AFTER PYTHON REPS FILE..." >&2; exit 2; }
before=$1 after=$2 python=$3 reps=$4
shift 4
tmp=$(mktemp -d /tmp/limn_load_sbs_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
trimesh='import sys, time, trimesh
t = time.perf_counter(); trimesh.load(sys.argv[1], process=False); print(time.perf_counter() - t)'
for f in "$@"; do
  name=$(basename "$f")
  for i in $(seq "$reps"); do
    for which in before after; do
      bin=${!which}
      t0=$(date +%s.%N)
      "$bin" info "$f" > "$tmp/info_$which.txt"
      t1=$(date +%s.%N)
      "$bin" interpolate "$f" -o "$tmp/out_$which.ply" --report "$tmp/r_$which.json" -q
      load=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['seconds']['load'])" \
             "$tmp/r_$which.json")
      printf '%s %s info %.2f load %.2f\n' "$name" "$which" "$(echo "$t1 - $t0" | bc)" "$load"
    done
    [ -z "$python" ] || printf '%s trimesh.load %.2f\n' "$name" "$("$python" -c "$trimesh" "$f")"
  done
  cmp -s "$tmp/out_before.ply" "$tmp/out_after.ply" && same=same || same=DIFFERENT
  cmp -s "$tmp/info_before.txt" "$tmp/info_after.txt" && isame=same || isame=DIFFERENT
  echo "$name: interpolate output $same bytes, info output $isame bytes"
done

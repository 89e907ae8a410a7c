#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The folders of host/ are the layers of limn (docs/layout.md): a
# folder includes only itself, lower folders and the public headers
# (include/limn.h, limn_mpi.h). Fails when
#   - a .c or .h lies loose directly in host/;
#   - a folder holding sources has no rank in the table below (a new folder
#     must be given its place);
#   - an #include "..." is not a path from host/ (the one include root, so
#     the layer of every include shows) naming an existing file;
#   - a folder includes a higher folder, or another folder of its own rank
#     (the two backends stay apart);
#   - the CLI (host/cli) includes anything but the public headers and its own.
#   check_layers.sh SOURCE_DIR
set -euo pipefail
cd "$1/host"

# folder rank: lower numbers are lower layers
declare -A rank=(
    [base]=0            # context and errors core, clock, growbuf, C locale, atomic outputs
    [mesh]=1            # the mesh container, access, argument checks
    [mesh/io]=2         # reader toolkit, format dispatch, OBJ/PLY/OFF/STL
    [topology]=3        # edges, rings, classification; measure, repair, info
    [scheme]=4          # limit and refinement masks (pure functions)
    [stencil]=5         # CSR tables, locality order, Gauss-Seidel colouring
    [device]=6          # the backend interface and helpers both backends use
    [device/reference]=7 # the plain C backend
    [device/opencl]=7    # the OpenCL backend
    [device/choice]=8   # the context life cycle and the backend choice, above both
    [solve]=9           # operator, interpolation loop, solvers
    [refine]=10         # refinement plan, limn_subdivide
    [series]=11         # bands, filters, morph, texture
    [render]=12         # pictures, PNG
    [mpi]=13            # the MPI layer
    [cli]=14            # the limn executable
)

fail=0 edges=0
complain() { echo "check_layers: $*" >&2; fail=$((fail + 1)); }

while IFS= read -r -d '' f; do
    complain "$f lies loose in host/: put it in the folder of its layer"
done < <(find . -maxdepth 1 -type f \( -name '*.c' -o -name '*.h' \) -printf '%P\0')

declare -A seen=()
while IFS= read -r -d '' f; do
    dir=$(dirname "$f")
    if [[ -z ${rank[$dir]+x} && -z ${seen[$dir]+x} ]]; then
        complain "folder host/$dir has no rank in tests/check_layers.sh"
        seen[$dir]=1
    fi
done < <(find . -mindepth 2 -type f \( -name '*.c' -o -name '*.h' \) -printf '%P\0')

# every quoted include: FILE:LINE:TEXT
while IFS= read -r hit; do
    f=${hit%%:*} rest=${hit#*:}
    n=${rest%%:*} line=${rest#*:}
    f=${f#./} dir=$(dirname "$f")
    [[ $dir != . && -n ${rank[$dir]+x} ]] || continue # reported above
    [[ $line =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*\"([^\"]+)\" ]] || continue
    inc=${BASH_REMATCH[1]}
    case $inc in limn.h | limn_mpi.h) continue ;; esac
    if [[ $dir == cli ]]; then
        # the CLI is a client of the public API (built without host/ on its
        # include path): its own headers by name, nothing of the library's
        [[ $inc != */* && -f cli/$inc ]] ||
            complain "host/$f:$n: #include \"$inc\": the CLI includes only limn.h, limn_mpi.h and its own headers"
        continue
    fi
    if [[ ! -f $inc ]]; then
        complain "host/$f:$n: #include \"$inc\" is not a path from host/ to a file"
        continue
    fi
    to=$(dirname "$inc")
    [[ $to == "$dir" ]] && continue
    if [[ -z ${rank[$to]+x} ]]; then
        complain "host/$f:$n: includes $inc from folder host/$to, which has no rank"
    elif ((rank[$to] >= rank[$dir])); then
        complain "host/$f:$n: $dir (rank ${rank[$dir]}) includes $inc of $to (rank ${rank[$to]}): a layer includes only lower ones"
    fi
    edges=$((edges + 1))
done < <(grep -rnE --include='*.c' --include='*.h' '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' . | sort)

[[ $fail -eq 0 ]] || { echo "check_layers: $fail problem(s)" >&2; exit 1; }
echo "check_layers: ${#rank[@]} layers, $edges includes across folders, every one downwards"

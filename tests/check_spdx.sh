#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every source file limn ships (C, headers, kernels, C++, shell, Python, CMake)
# carries an SPDX licence line matching LICENSE (MIT) in its first three lines.
#   check_spdx.sh SOURCE_DIR
set -euo pipefail
cd "$1"
[[ -f LICENSE ]] && grep -q "^MIT License" LICENSE || { echo "check_spdx: LICENSE is not MIT" >&2; exit 1; }
missing=0 count=0
while IFS= read -r -d '' f; do
    count=$((count + 1))
    if ! head -n 3 "$f" | grep -q "SPDX-License-Identifier: MIT"; then
        echo "check_spdx: $f has no 'SPDX-License-Identifier: MIT' line" >&2
        missing=$((missing + 1))
    fi
done < <(if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
             git ls-files -z --cached --others --exclude-standard -- \
                 '*.c' '*.h' '*.cl' '*.cpp' '*.sh' '*.py' '*.cmake' 'CMakeLists.txt' \
                 '*/CMakeLists.txt' '.ci/run' ':!:tests/fuzz/corpus/*' ':!:tests/fuzz/regressions/*'
         else # an unpacked source tree without .git: the same files by name
             find . -path ./.git -prune -o -path './build*' -prune -o -path ./tests/fuzz/corpus \
                 -prune -o -path ./tests/fuzz/regressions -prune -o -type f \( -name '*.[ch]' \
                 -o -name '*.cl' -o -name '*.cpp' -o -name '*.sh' -o -name '*.py' -o -name \
                 '*.cmake' -o -name CMakeLists.txt -o -path ./.ci/run \) -print0
         fi)
[[ $missing -eq 0 ]] || { echo "check_spdx: $missing of $count files lack the line" >&2; exit 1; }
echo "check_spdx: $count source files carry SPDX-License-Identifier: MIT"

#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Long functions hide what they do (issue 12: at most 10 functions of the
# library and CLI over 80 lines). Counts the lines of every top-level brace
# block in host/**/*.c that follows a parameter list (a function body: not a
# struct, enum or initialiser), comments and string literals ignored, lists
# those over LIMIT and fails when there are more than ALLOWED.
#   check_function_length.sh SOURCE_DIR [LIMIT=80] [ALLOWED=10]
set -euo pipefail
cd "$1"
limit=${2:-80} allowed=${3:-10}
report=$(find host -name '*.c' | LC_ALL=C sort | while read -r f; do
    awk -v file="$f" -v limit="$limit" '
    BEGIN { depth = 0; incomment = 0; last = "" }
    {
        line = $0; out = ""
        # strip comments and literals, keeping braces that are code
        i = 1; n = length(line)
        while (i <= n) {
            c = substr(line, i, 1); c2 = substr(line, i, 2)
            if (incomment) {
                if (c2 == "*/") { incomment = 0; i += 2 } else i++
                continue
            }
            if (c2 == "/*") { incomment = 1; i += 2; continue }
            if (c2 == "//") break
            if (c == "\"" || c == "\047") {
                q = c; i++
                while (i <= n && substr(line, i, 1) != q)
                    i += (substr(line, i, 1) == "\\") ? 2 : 1
                i++; out = out q q; continue
            }
            out = out c; i++
        }
        for (j = 1; j <= length(out); j++) {
            c = substr(out, j, 1)
            if (c == "{") {
                if (depth == 0) {
                    head = last " " substr(out, 1, j - 1)
                    isfn = (head ~ /\)[ \t]*$/)
                    start = NR; name = head
                    sub(/[ \t]*\(.*$/, "", name); sub(/^.*[ \t*]/, "", name)
                }
                depth++
            } else if (c == "}") {
                depth--
                if (depth == 0 && isfn && NR - start + 1 > limit)
                    printf "%d %s:%d %s\n", NR - start + 1, file, start, name
            }
        }
        if (depth == 0 && out ~ /[^ \t]/) last = (out ~ /[;}][ \t]*$/) ? "" : last " " out
    }' "$f"
done | sort -rn)
count=$(printf '%s' "$report" | grep -c . || true)
[ -n "$report" ] && printf '%s\n' "$report"
echo "check_function_length: $count functions over $limit lines (at most $allowed allowed)"
[ "$count" -le "$allowed" ]

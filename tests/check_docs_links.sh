#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every relative link in README.md and docs/*.md resolves: the file (or folder)
# exists in the source tree and, for a #fragment, the Markdown file it names has
# a heading with that slug (GitHub's rule: lower case, punctuation dropped,
# spaces to hyphens, -1, -2 ... for repeats). Links inside code are not links.
# Also refuses references to DESIGN.md (not in the repository) and the
# internal "seed 00N" names of the papers (docs/references.md cites them).
# No network: http(s) and mailto links are not followed.
#   check_docs_links.sh SOURCE_DIR
set -euo pipefail
cd "$1"
exec python3 - <<'PY'
import glob, os, re, sys, unicodedata

files = ["README.md"] + sorted(glob.glob("docs/*.md"))
fence = re.compile(r"^\s*(```|~~~)")
link = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
heading = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")

def prose(text):
    """Lines outside fenced code, with inline code spans blanked."""
    out, in_fence = [], False
    for n, line in enumerate(text.split("\n"), 1):
        if fence.match(line):
            in_fence = not in_fence
            continue
        if not in_fence:
            out.append((n, re.sub(r"`+[^`]*`+", "``", line)))
    return out

def slug(title):
    t = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", title)      # [text](url) -> text
    t = t.replace("`", "").replace("*", "").lower()
    t = "".join(c for c in t if c in " -_" or unicodedata.category(c)[0] in "LN")
    return t.replace(" ", "-")

anchors = {}
def anchors_of(path):
    if path not in anchors:
        seen, found = {}, set()
        with open(path, encoding="utf-8") as f:
            text = f.read()
        in_fence = False
        for line in text.split("\n"):
            if fence.match(line):
                in_fence = not in_fence
                continue
            m = None if in_fence else heading.match(line)
            if m:
                s = slug(m.group(2))
                k = seen.get(s, 0)
                seen[s] = k + 1
                found.add(s if k == 0 else f"{s}-{k}")
        found |= set(re.findall(r'<a\s+(?:name|id)="([^"]+)"', text))
        anchors[path] = found
    return anchors[path]

bad = checked = 0
def fail(msg):
    global bad
    bad += 1
    print(f"check_docs_links: {msg}", file=sys.stderr)

for md in files:
    text = open(md, encoding="utf-8").read()
    for n, line in prose(text):
        for ref in ("DESIGN.md", "seed 00"):
            if ref in line:
                fail(f"{md}:{n}: mentions '{ref}' (not in the repository / internal name)")
        for target in link.findall(line):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
                continue
            checked += 1
            path, _, frag = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(md), path)) if path else md
            if not os.path.exists(dest):
                fail(f"{md}:{n}: link to '{target}': {dest} does not exist")
                continue
            if frag:
                if not dest.endswith(".md") or os.path.isdir(dest):
                    fail(f"{md}:{n}: link to '{target}': a fragment on a file that is not Markdown")
                elif frag not in anchors_of(dest):
                    fail(f"{md}:{n}: link to '{target}': no heading '#{frag}' in {dest}")
    if md.startswith("docs/") and "](../README.md" not in text:
        fail(f"{md}: no link back to the README")

if bad:
    print(f"check_docs_links: {bad} problem(s) in {len(files)} files", file=sys.stderr)
    sys.exit(1)
print(f"check_docs_links: {checked} relative links in {len(files)} files resolve")
PY

#!/usr/bin/env bash
# The repository is self-contained and cites its sources one way. No file
# may name a path outside the repository (the design notes and workload
# definitions that once lived beside it, a sibling `shared` folder, an
# absolute /wor[k]/ path) or cite a source by its old number ("seed" and
# three digits) instead of its key in docs/SOURCES.md. Every docs/*.md path
# a file names must exist, and every relative Markdown link in a *.md file
# must resolve, its #anchor included. The patterns below are written so that
# this file does not match them itself.
#
# Files: `git ls-files` in a git checkout (CI runs on a clone), otherwise
# every file under the source folder except .git, build*/ and out/. The
# persp binary ($1) is not used.
set -u
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
. "$(dirname "$0")/lib.sh"
cd "$src" || { echo "FAIL: no source folder $src"; exit 1; }

if git rev-parse --is-inside-work-tree >/dev/null 2>&1 && [ -n "$(git ls-files | head -1)" ]; then
    git ls-files -z >"$tmp/files"
else
    find . \( -name .git -o -path './build*' -o -path ./out \) -prune -o -type f -print0 |
        sed -z 's|^\./||' >"$tmp/files"
fi
[ -s "$tmp/files" ] && ok || bad "no files to check under $src"

# name|extended regex (case-insensitive). Each regex is spelled so that it
# does not match its own text.
forbidden=(
    "the benchmark notes outside the repository|BENCHMARKS[.]md"
    "the architecture brief outside the repository|ARCHITECTURE[.]md"
    "a sibling shared folder|[.][.]/shared"
    "an absolute path of the working machine|/wor[k]/"
    "a source cited by number instead of its docs/SOURCES.md key|seed[ _-]?00[0-9]"
)
for entry in "${forbidden[@]}"; do
    what="${entry%%|*}" re="${entry#*|}"
    hits=$(xargs -0 grep -I -n -i -E -- "$re" <"$tmp/files" 2>/dev/null)
    if [ -z "$hits" ]; then ok; else bad "$what:"$'\n'"$hits"; fi
done

# Markdown paths under docs/ named anywhere, and relative links in *.md files.
if python3 - "$tmp/files" >"$tmp/links" <<'PY'; then ok; else bad "broken references:"$'\n'"$(cat "$tmp/links")"; fi
import os, re, sys

files = [f for f in open(sys.argv[1], 'rb').read().decode().split('\0') if f]
errors = []

def text(path):
    try:
        with open(path, 'rb') as fh:
            data = fh.read()
    except OSError:
        return None
    if b'\0' in data:
        return None
    return data.decode('utf-8', 'replace')

def slugs(md):
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to
    hyphens, repeated headings numbered."""
    seen, out, fence = {}, set(), False
    for line in md.splitlines():
        if re.match(r'^\s*(```|~~~)', line):
            fence = not fence
            continue
        m = None if fence else re.match(r'^ {0,3}#{1,6}\s+(.*?)\s*#*\s*$', line)
        if not m:
            continue
        h = re.sub(r'\]\([^)]*\)', ']', m.group(1)).lower()
        s = re.sub(r'[^\w\- ]', '', h).replace(' ', '-')
        n = seen.get(s, 0)
        seen[s] = n + 1
        out.add(s if n == 0 else f'{s}-{n}')
    return out

docs_path = re.compile(r'(?<![\w./-])docs/[\w.-]+\.md\b')
link = re.compile(r'\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\)')
for f in files:
    t = text(f)
    if t is None:
        continue
    for no, line in enumerate(t.splitlines(), 1):
        for m in docs_path.finditer(line):
            if not os.path.isfile(m.group(0)):
                errors.append(f'{f}:{no}: names {m.group(0)}, which does not exist')
    if not f.endswith('.md'):
        continue
    body = re.sub(r'(?ms)^\s*(```|~~~).*?^\s*\1', '', t)   # fenced code
    body = re.sub(r'`[^`\n]*`', '', body)                  # inline code
    for m in link.finditer(body):
        target = m.group(1)
        if re.match(r'^[a-z][a-z0-9+.-]*:', target, re.I):  # http:, mailto:, ...
            continue
        path, _, anchor = target.partition('#')
        dest = os.path.normpath(os.path.join(os.path.dirname(f), path)) if path else f
        if not os.path.exists(dest):
            errors.append(f'{f}: link ({target}) points to a missing {dest}')
            continue
        if anchor and dest.endswith('.md'):
            if anchor.lower() not in slugs(text(dest) or ''):
                errors.append(f'{f}: link ({target}): no heading #{anchor} in {dest}')
print('\n'.join(errors))
sys.exit(1 if errors else 0)
PY

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

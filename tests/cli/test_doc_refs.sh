#!/usr/bin/env bash
# Every section the documents and the sources' comments cite by name
# (docs/RELIABILITY.md, "Memory and time bounds") is a heading of that
# document, and README.md lists every document (scripts/check_doc_refs.py).
# Then copies with a citation broken each way, which it must refuse.
# (The persp binary in $1 is not used.)
set -u
. "$(dirname "$0")/lib.sh"

check=(python3 "$PERSP_SOURCE_DIR/scripts/check_doc_refs.py")
expect 0 "section citations checked, 0 broken" -- "${check[@]}"

copy() { # DIR: README.md and docs/ of the tree
    mkdir -p "$1/src"
    cp -r "$PERSP_SOURCE_DIR/README.md" "$PERSP_SOURCE_DIR/docs" "$1/"
}
copy "$tmp/a"
expect 0 " 0 broken" -- "${check[@]}" --root "$tmp/a"
# A source comment citing a section that is not there.
# (The document's name comes from a variable: this file is checked too.)
doc=RELIABILITY
printf '/* As bounded (docs/%s.md,\n * "Bounded resources"). */\n' "$doc" >"$tmp/a/src/x.c"
expect 1 "^src/x.c:1: $doc.md, \"Bounded resources\": no such heading" -- "${check[@]}" --root "$tmp/a"
# A heading renamed under the citations of it.
copy "$tmp/b"
sed -i 's/^## Fuzzing$/## Fuzz testing/' "$tmp/b/docs/RELIABILITY.md"
expect 1 'RELIABILITY.md, "Fuzzing": no such heading' -- "${check[@]}" --root "$tmp/b"
# A document README.md does not list.
copy "$tmp/c"
new=EXTRA
printf '# Extra\n' >"$tmp/c/docs/$new.md"
expect 1 "does not list docs/$new.md" -- "${check[@]}" --root "$tmp/c"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

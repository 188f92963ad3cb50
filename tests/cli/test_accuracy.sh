#!/usr/bin/env bash
# CLI behaviour of `persp accuracy`: the table, CSV and JSON outputs parse and
# agree, --method/--case select, --heatmap writes PNGs, and bad usage exits 2
# with a message naming the problem.
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"

expect 0 "usage: persp accuracy" -- "$persp" accuracy --help
expect 0 "paper-quad" -- "$persp" accuracy --help
expect 0 "^exact +paper-quad " -- "$persp" accuracy --method exact --case paper-quad
expect 0 "relpt: point-wise relative error" -- "$persp" accuracy --method affine --case paper-quad
expect 2 "unknown option '--bogus'" -- "$persp" accuracy --bogus
expect 2 "unknown method 'nosuch'" -- "$persp" accuracy --method nosuch
expect 2 "unknown method 'nosuch'" -- "$persp" accuracy --method exact,nosuch
expect 2 "bad parameters in method 'exact:3'" -- "$persp" accuracy --method exact:3
expect 2 "unknown case 'nowhere'" -- "$persp" accuracy --case nowhere
expect 2 "needs a value" -- "$persp" accuracy --method
expect 2 "bad --size" -- "$persp" accuracy --size 0x5
expect 2 "bad --triangles" -- "$persp" accuracy --triangles -3
expect 2 "bad --rel-floor" -- "$persp" accuracy --rel-floor abc
expect 2 "unexpected argument" -- "$persp" accuracy stray

# Selection: two methods x (paper-quad + 7 depth-ratio groups) = 16 CSV rows.
"$persp" accuracy --method exact --method affine --case paper-quad,random-triangles \
    --triangles 3 --csv >"$tmp/a.csv" 2>"$tmp/err" || bad "csv run failed: $(cat "$tmp/err")"
rows=$(($(wc -l <"$tmp/a.csv") - 1))
[ "$rows" -eq 16 ] && ok || bad "expected 16 CSV rows, got $rows"
head -1 "$tmp/a.csv" | grep -q '^method,case,hbar,pixels' && ok || bad "CSV header"
# Every row has as many fields as the header.
awk -F, 'NR==1{n=NF} NF!=n{exit 1}' "$tmp/a.csv" && ok || bad "CSV field counts differ"
# exact stays below 1e-3 texels, affine is far off at hbar 8 (column 7 = max_u).
awk -F, '$1=="\"exact\"" && ($7+0 >= 1e-3 || $8+0 >= 1e-3) {exit 1}' "$tmp/a.csv" && ok || bad "exact error >= 1e-3"
awk -F, '$1=="\"affine\"" && $3=="8" && $7+0 > 10 {f=1} END{exit !f}' "$tmp/a.csv" && ok || bad "affine not far off at hbar 8"

"$persp" accuracy --method exact,affine --case paper-quad --json >"$tmp/a.json" || bad "json run failed"
if command -v python3 >/dev/null; then
    python3 - "$tmp/a.json" <<'PY' && ok || bad "JSON does not parse or lacks rows"
import json, sys
d = json.load(open(sys.argv[1]))
rows = d["rows"]
assert [r["method"] for r in rows] == ["exact", "affine"], rows
assert rows[0]["max_u"] < 1e-3 and rows[1]["max_u"] > 1
assert "relpt" in d["definitions"] and d["rel_floor"] == 0.01
PY
else
    grep -q '"rows"' "$tmp/a.json" && ok || bad "JSON lacks rows"
fi

expect 0 "" -- "$persp" accuracy --method affine,exact --case paper-quad,paper-quad-full --heatmap "$tmp/hm"
for f in paper-quad_affine paper-quad_exact paper-quad-full_affine paper-quad-full_exact; do
    [ -s "$tmp/hm/$f.png" ] && [ "$(head -c 8 "$tmp/hm/$f.png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] \
        && ok || bad "heat map $f.png missing or not a PNG"
done

echo "accuracy CLI: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

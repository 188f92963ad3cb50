#!/usr/bin/env bash
# Sharded accuracy sweeps: three slices run by GNU Parallel and merged by
# `persp merge` give the unsharded JSON byte for byte (docs/SWEEPS.md); merge
# refuses incomplete, repeated or foreign slices.
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"

sweep=(accuracy --case paper-quad,random-triangles,floor --size 96x72 --triangles 3 --json)

"$persp" "${sweep[@]}" >"$tmp/full.json" 2>"$tmp/err" || bad "unsharded run: $(cat "$tmp/err")"

if command -v parallel >/dev/null 2>&1; then
    parallel --will-cite -j 3 "'$persp' ${sweep[*]} --shard {}/3 > '$tmp'/shard{}.json" ::: 1 2 3 \
        2>"$tmp/err" || bad "parallel shards: $(cat "$tmp/err")"
else
    echo "note: GNU parallel not installed (scripts/deps.sh installs it); shards run one by one"
    for k in 1 2 3; do "$persp" "${sweep[@]}" --shard $k/3 >"$tmp/shard$k.json" || bad "shard $k"; done
fi
"$persp" merge "$tmp/shard3.json" "$tmp/shard1.json" "$tmp/shard2.json" >"$tmp/merged.json" \
    2>"$tmp/err" || bad "merge: $(cat "$tmp/err")"
cmp -s "$tmp/full.json" "$tmp/merged.json" && ok || bad "merged JSON differs from the unsharded run"
# Each slice holds its rows only, dealt round-robin.
for k in 1 2 3; do
    grep -q '"count": 3' "$tmp/shard$k.json" && ok || bad "shard $k lacks its description"
done
grep -q '"shard"' "$tmp/merged.json" && bad "merged JSON still describes a shard" || ok
"$persp" merge -o "$tmp/m2.json" "$tmp"/shard*.json && cmp -s "$tmp/full.json" "$tmp/m2.json" && ok ||
    bad "merge -o"

# The GNU Parallel recipe of docs/SWEEPS.md: a slice that fails leaves no
# file, the merge names it, and --resume-failed runs that slice alone.
if command -v parallel >/dev/null 2>&1; then
    mkdir -p "$tmp/p"
    printf '#!/bin/sh\ncase "$*" in *"--shard 2/3"*) [ -e "%s/p/again" ] || { touch "%s/p/again"; exit 1; } ;; esac\nexec "%s" "$@"\n' \
        "$tmp" "$tmp" "$persp" >"$tmp/flaky"
    chmod +x "$tmp/flaky"
    recipe=(parallel --will-cite --joblog "$tmp/p/joblog" -j 3
            "'$tmp/flaky' ${sweep[*]} --shard {}/3 -o '$tmp'/p/shard-{}-of-3.json" ::: 1 2 3)
    "${recipe[@]}" 2>/dev/null && bad "parallel: a failed slice is not reported" || ok
    expect 1 "missing shard 2 of 3 \(2 files given\)" -- "$persp" merge -o "$tmp/p/accuracy.json" \
        "$tmp"/p/shard-*-of-3.json
    "${recipe[@]:0:4}" --resume-failed "${recipe[@]:4}" || bad "parallel --resume-failed"
    [ "$(grep -c -- '--shard 2/3' "$tmp/p/joblog")" -eq 2 ] && [ "$(grep -c -- '--shard 1/3' "$tmp/p/joblog")" -eq 1 ] &&
        ok || bad "--resume-failed ran other slices than the failed one: $(cat "$tmp/p/joblog")"
    "$persp" merge -o "$tmp/p/accuracy.json" "$tmp"/p/shard-*-of-3.json &&
        cmp -s "$tmp/full.json" "$tmp/p/accuracy.json" && ok || bad "parallel recipe: merged JSON differs"
fi

# The merged result feeds the page's tables as the measured one would.
"$persp" merge --csv "$tmp"/shard*.json >"$tmp/m.csv" && "$persp" "${sweep[@]:0:7}" --csv >"$tmp/f.csv" &&
    cmp -s "$tmp/m.csv" "$tmp/f.csv" && ok || bad "merged CSV differs"

expect 1 "missing shard 3 of 3 \(2 files given\)" -- "$persp" merge "$tmp/shard1.json" "$tmp/shard2.json"
expect 1 "missing shards 1,3 of 3 \(1 file given\)" -- "$persp" merge "$tmp/shard2.json"
# Runs of missing slices as sbatch --array writes them; a slice with no rows
# (more slices than rows) reads and merges like any other.
"$persp" accuracy --case paper-quad --json --shard 40/40 -o "$tmp/s40.json" || bad "slice 40 of 40"
expect 1 "missing shards 1-39 of 40 \(1 file given\)" -- "$persp" merge "$tmp/s40.json"
expect 1 "given twice" -- "$persp" merge "$tmp/shard1.json" "$tmp/shard1.json" "$tmp/shard2.json"
expect 1 "whole run, not a shard" -- "$persp" merge "$tmp/full.json"
"$persp" accuracy --case paper-quad --json --shard 2/3 >"$tmp/other.json"
expect 1 "other.json is not a shard of the same sweep as .*shard1.json: setting 'cases' is paper-quad, not" \
    -- "$persp" merge "$tmp/shard1.json" "$tmp/other.json" "$tmp/shard3.json"
# A slice of the same cases with other settings is named with the setting.
"$persp" accuracy --case paper-quad,random-triangles,floor --size 96x72 --triangles 4 --json --shard 2/3 \
    >"$tmp/tri4.json"
expect 1 "tri4.json is not a shard of the same sweep as .*shard1.json: setting 'triangles' is 4, not 3" \
    -- "$persp" merge "$tmp/shard1.json" "$tmp/tri4.json" "$tmp/shard3.json"
"$persp" "${sweep[@]}" --shard 2/4 >"$tmp/of4.json"
expect 1 "of4.json is a shard of 4, .*shard1.json of 3" -- "$persp" merge "$tmp/shard1.json" "$tmp/of4.json" "$tmp/shard3.json"

# Files edited after the run: each edit is refused, naming the file and
# what is wrong, and no output is left behind.
edit() { # edit NAME PYTHON-STATEMENT: shard2.json with d changed, as tmp/NAME.json
    python3 - "$tmp/shard2.json" "$tmp/$1.json" "$2" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
exec(sys.argv[3])
open(sys.argv[2], "w").write(json.dumps(d, indent=2) + "\n")
PY
}
refused() { # refused NAME PATTERN: merge with tmp/NAME.json as slice 2 fails, writes nothing
    rm -f "$tmp/out.json"
    expect 1 "$2" -- "$persp" merge -o "$tmp/out.json" "$tmp/shard1.json" "$tmp/$1.json" "$tmp/shard3.json"
    [ ! -e "$tmp/out.json" ] && ok || bad "$1: merge left $tmp/out.json behind"
}
edit same 'pass'
"$persp" merge -o "$tmp/same.out" "$tmp/shard1.json" "$tmp/same.json" "$tmp/shard3.json" &&
    cmp -s "$tmp/full.json" "$tmp/same.out" && ok || bad "an unedited slice rewritten by python is refused"
edit floor 'd["rel_floor"] = 0.02'
refused floor "floor.json: setting 'rel_floor' 0.02 differs from the sweep's \(0.01"
edit reference 'd["reference"] = "u = s1"'
refused reference "reference.json: setting 'reference' is missing or not this version's"
edit defs 'd["definitions"]["ops/px"] = "other"'
refused defs "defs.json: setting 'definitions' is missing or not this version's"
edit nofield 'del d["rows"][0]["max_u"]'
refused nofield "nofield.json: row 1 is malformed: it 'max_u' is missing or not a number or null"
edit strfield 'd["rows"][1]["p99_v"] = "0.5"'
refused strfield "strfield.json: row 2 is malformed: it 'p99_v' is missing or not a number or null"
edit nopixels 'd["rows"][0]["pixels"] = None'
refused nopixels "nopixels.json: row 1 is malformed: it 'pixels' is missing or not a count"
edit noops 'del d["rows"][0]["ops_per_pixel"]'
refused noops "noops.json: row 1 is malformed: it 'ops_per_pixel' is missing"
edit rowkey 'd["rows"][0]["note"] = 1'
refused rowkey "rowkey.json: row 1 is malformed: it has an unknown key 'note'"
edit topkey 'd["comment"] = "x"'
refused topkey "topkey.json: unknown key 'comment'"
edit shardkey 'd["shard"]["host"] = "n1"'
refused shardkey "shardkey.json: shard description has an unknown key 'host'"
edit control 'd["rows"][0]["method"] = "exact\r\nx,1"'
refused control "control.json: row 1 is malformed: it 'method' holds a control character"
sed '0,/"rel_floor"/s/"rel_floor"/"rel_floor": 0.01, "rel_floor"/' "$tmp/shard2.json" >"$tmp/dup.json"
refused dup "dup.json:.*duplicate object key"

# A quote in a name stays inside its CSV field (RFC 4180: doubled).
for k in 1 2 3; do
    sed 's/"method": "exact"/"method": "ex\\"act"/' "$tmp/shard$k.json" >"$tmp/q$k.json"
done
"$persp" merge --csv "$tmp"/q[123].json >"$tmp/q.csv" && grep -q '^"ex""act",' "$tmp/q.csv" && ok ||
    bad "a quote in a method name is not doubled in the CSV"

# The output may not be one of the inputs, under any name: refused before
# anything is read or written.
cp "$tmp/shard1.json" "$tmp/keep1.json"
expect 2 "-o '.*shard1.json' is also input 1" -- "$persp" merge "$tmp/shard1.json" "$tmp/shard2.json" \
    "$tmp/shard3.json" -o "$tmp/shard1.json"
ln -sf "$tmp/shard2.json" "$tmp/link2.json"
expect 2 "-o '.*link2.json' is also input 2" -- "$persp" merge "$tmp/shard1.json" "$tmp/shard2.json" \
    "$tmp/shard3.json" -o "$tmp/link2.json"
cmp -s "$tmp/shard1.json" "$tmp/keep1.json" && ok || bad "merge -o over an input changed it"

# A memory budget as for the other commands: the JSON's parse is bounded
# before it starts, so a budget too small is refused with its size named.
expect 1 "out of memory.*parsing the JSON|budget" -- "$persp" merge --max-memory 64K "$tmp"/shard[123].json
"$persp" merge --max-memory 64M "$tmp"/shard[123].json >"$tmp/mm.json" && cmp -s "$tmp/full.json" "$tmp/mm.json" &&
    ok || bad "merge --max-memory 64M"
expect 2 "max-memory" -- "$persp" merge --max-memory 0 "$tmp"/shard[123].json
# A 20 MB slice (30000 rows) under a 64 MiB budget: refused before jansson
# builds its tree (some 200 MiB), so the process stays near the budget.
python3 - "$tmp/shard1.json" "$tmp/big.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
rows, n = d["rows"], 30000
d["rows"] = [rows[i % len(rows)] for i in range(n)]
d["shard"].update(index=0, count=1, rows=n, row_index=list(range(n)))
open(sys.argv[2], "w").write(json.dumps(d, indent=2) + "\n")
PY
peak=$(python3 - "$persp" "$tmp/big.json" "$tmp/big.out" <<'PY'
import resource, subprocess, sys
r = subprocess.run([sys.argv[1], "merge", "--max-memory", "64M", sys.argv[2], "-o", sys.argv[3]],
                   stderr=subprocess.PIPE, text=True)
print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss // 1024, r.stderr.strip())
PY
)
case "$peak" in
"1 "*"parsing the JSON: needs"*"over the memory budget of 64.0 MiB"*) ok ;;
*) bad "a 20 MB slice under --max-memory 64M: $peak" ;;
esac
# (A sanitizer build's shadow memory and quarantine have no such bound.)
if [ "${PERSP_TEST_SANITIZER:-0}" != 1 ]; then
    [ "$(cut -d' ' -f2 <<<"$peak")" -lt 96 ] && ok || bad "merge under --max-memory 64M peaked at $(cut -d' ' -f2 <<<"$peak") MiB"
fi
[ ! -e "$tmp/big.out" ] && ok || bad "a refused merge left its output"
"$persp" merge --max-memory 512M "$tmp/big.json" -o "$tmp/big.out" && ok || bad "a 20 MB slice under 512M"
echo '{"rows": 3}' >"$tmp/bad.json"
expect 1 "not a persp accuracy JSON report" -- "$persp" merge "$tmp/bad.json"
expect 1 "cannot open" -- "$persp" merge "$tmp/none.json"
expect 2 "needs --json" -- "$persp" accuracy --case paper-quad --shard 1/2
expect 2 "bad --shard" -- "$persp" accuracy --json --shard 3/2
expect 2 "bad --shard" -- "$persp" accuracy --json --shard 0/2
expect 2 "no files" -- "$persp" merge
expect 0 "usage: persp merge" -- "$persp" merge --help

echo "test_shard: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

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

# The merged result feeds the page's tables as the measured one would.
"$persp" merge --csv "$tmp"/shard*.json >"$tmp/m.csv" && "$persp" "${sweep[@]:0:7}" --csv >"$tmp/f.csv" &&
    cmp -s "$tmp/m.csv" "$tmp/f.csv" && ok || bad "merged CSV differs"

expect 1 "2 files for a sweep of 3 shards" -- "$persp" merge "$tmp/shard1.json" "$tmp/shard2.json"
expect 1 "given twice" -- "$persp" merge "$tmp/shard1.json" "$tmp/shard1.json" "$tmp/shard2.json"
expect 1 "whole run, not a shard" -- "$persp" merge "$tmp/full.json"
"$persp" accuracy --case paper-quad --json --shard 2/3 >"$tmp/other.json"
expect 1 "not a shard of the same sweep" -- "$persp" merge "$tmp/shard1.json" "$tmp/other.json" "$tmp/shard3.json"
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

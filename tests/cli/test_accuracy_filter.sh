#!/usr/bin/env bash
# CLI behaviour of `persp accuracy --filter`: the table, CSV and JSON outputs,
# filter and case selection, heat maps, and bad usage exiting 2 with a
# message naming the problem.
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"

small=(--size 40x30 --samples 2 --repeats 1)
expect 0 "usage: persp accuracy --filter" -- "$persp" accuracy --filter --help
expect 0 "tilt-85" -- "$persp" accuracy --filter --help
expect 0 "texture filters instead of methods" -- "$persp" accuracy --help
expect 0 "^  screen +trilinear +[0-9.]+ +[0-9.-]+ " -- "$persp" accuracy --filter trilinear --case tilt-45 "${small[@]}"
expect 0 "mip chain \+33\.3% memory" -- "$persp" accuracy --filter nearest --case corridor "${small[@]}"
expect 0 "^  object +object " -- "$persp" accuracy --filter object --case floor "${small[@]}"
# Every default filter appears when no list is given.
out=$("$persp" accuracy --filter --case tilt-0 "${small[@]}" 2>&1)
for f in nearest bilinear nearest-mip-nearest bilinear-mip-nearest nearest-mip-linear trilinear \
         aniso:16 aniso-window:16 ewa object; do
    if grep -qE "^  (screen|object) +$f " <<<"$out"; then ok; else bad "default run lacks $f: $out"; fi
done
# CSV: header plus one line per filter and case, 16 fields each.
csv=$("$persp" accuracy --filter nearest,aniso:4 --case tilt-0,tilt-80 --csv "${small[@]}")
if [ "$(wc -l <<<"$csv")" -eq 5 ] && awk -F, 'NF != 16 { exit 1 }' <<<"$csv"; then ok; else bad "csv: $csv"; fi
# JSON parses.
if "$persp" accuracy --filter ewa --case tilt-45 --json "${small[@]}" |
   python3 -c 'import json,sys; r=json.load(sys.stdin); assert r[0]["filter"]=="ewa" and r[0]["texture"]["levels"]==9'; then
    ok; else bad "json does not parse"; fi
# Heat maps: one PNG per filter and case, ':' replaced in names.
"$persp" accuracy --filter aniso:8,object --case tilt-70 --heatmap "$tmp/hm" "${small[@]}" >/dev/null
for f in filter_tilt-70_aniso-8.png filter_tilt-70_object.png; do
    if [ -s "$tmp/hm/$f" ] && [ "$(head -c 4 "$tmp/hm/$f" | tail -c 3)" = "PNG" ]; then ok; else bad "no heat map $f"; fi
done

expect 2 "unknown filter 'blur'" -- "$persp" accuracy --filter blur
expect 2 "bad filter 'aniso:40'" -- "$persp" accuracy --filter aniso:40
expect 2 "unknown case 'tilt-33'" -- "$persp" accuracy --filter --case tilt-33
expect 2 "bad --samples '0'" -- "$persp" accuracy --filter --samples 0
expect 2 "bad --size '0x3'" -- "$persp" accuracy --filter --size 0x3
expect 2 "unknown option '--method' with --filter" -- "$persp" accuracy --filter --method exact
expect 2 "needs a value" -- "$persp" accuracy --filter --case

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

#!/usr/bin/env bash
# `persp accuracy --filter --threads N`: the thread count changes no measured
# number (timings aside), since the renders are bit-identical for any number
# of workers (persp.h, "Threads"). Kept apart from test_accuracy_filter.sh so
# that the ThreadSanitizer pass runs these few renders and not that whole
# test (minutes under TSan).
# ctest-labels: threads (persp runs with --threads > 1)
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"

small=(--size 40x30 --samples 2 --repeats 1)
for t in 1 3; do
    "$persp" accuracy --filter trilinear,ewa,object --case tilt-45,tilt-80 --json --threads "$t" \
        "${small[@]}" >"$tmp/threads$t.json" && ok || bad "accuracy --filter --threads $t failed"
done
if python3 - "$tmp/threads1.json" "$tmp/threads3.json" <<'PY'; then ok; else bad "--threads 3 changed the results"; fi
import json, sys
def load(p):
    rows = json.load(open(p))
    for r in rows:
        r.pop("ms"), r.pop("ns_px")
    return rows
a, b = (load(p) for p in sys.argv[1:])
sys.exit(0 if a == b and len(a) == 6 else 1)
PY

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

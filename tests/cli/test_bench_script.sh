#!/usr/bin/env bash
# scripts/bench.sh --quick: every workload of the docs/PERFORMANCE.md table
# runs and yields a row with persp's fill rate and, with the OSMesa peer,
# llvmpipe's, the ratio and a PSNR; the header names the CPU and the commit.
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"

out=$(bash "$src/scripts/bench.sh" --quick "$persp" "$tmp/bench" 2>"$tmp/err"); rc=$?
if [ "$rc" -ne 0 ]; then bad "bench.sh --quick exited $rc: $(cat "$tmp/err") $out"
else
    grep -qE "^CPU: .+; persp commit [0-9a-f]+" <<<"$out" && ok || bad "no CPU / commit line: $out"
    rows=$(grep -cE "^\| (torus-(2k|20k|200k|2m)|soup-200k|corridor) \|" <<<"$out")
    [ "$rows" -eq 18 ] && ok || bad "expected 18 workload rows, got $rows: $out"
    grep -q "error" <<<"$out" && bad "a workload failed: $out" || ok
    # persp's rate is a positive number in every row.
    awk -F'|' '/^\| (torus|soup|corridor)/ { if (!($5 + 0 > 0)) bad = 1 } END { exit bad }' <<<"$out" && ok \
        || bad "a row without persp's fill rate: $out"
    if "$persp" bench --help | grep -q "not built with OSMesa"; then
        grep -q "no OSMesa peer" "$tmp/err" && ok || bad "no note about the missing peer: $(cat "$tmp/err")"
    else
        # llvmpipe's rate, the ratio and a PSNR in every row; unlit rows
        # agree closely (the clamp of lit colours in GL lowers gouraud's).
        awk -F'|' '/^\| (torus|soup|corridor)/ {
                gsub(/[ *]/, "", $7); if (!($6 + 0 > 0 && $7 + 0 > 0 && $8 + 0 > 20)) bad = 1
                if ($3 ~ /none/ && !($8 + 0 > 40)) bad = 1 }
             END { exit bad }' <<<"$out" && ok || bad "a row without peer rate, ratio or PSNR: $out"
    fi
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

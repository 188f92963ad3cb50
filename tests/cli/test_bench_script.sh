#!/usr/bin/env bash
# scripts/bench.sh --quick: every workload of the docs/PERFORMANCE.md table
# runs and yields a row with persp's fill rate and, with the OSMesa peer,
# llvmpipe's, the ratio and a PSNR; the header names the CPU and the commit,
# or outside a git checkout (a downloaded archive) the version: also run
# from a copy of the scripts and scenes without .git.
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"

version=$("$persp" --version | sed 's/^persp //')
mkdir -p "$tmp/archive/scenes"
cp -r "$src/scripts" "$tmp/archive/"
cp -r "$src/scenes/bench" "$tmp/archive/scenes/"
git -C "$tmp/archive" rev-parse --short HEAD >/dev/null 2>&1 && bad "$tmp/archive is inside a git checkout"
for from in "$src" "$tmp/archive"; do
    out=$(bash "$from/scripts/bench.sh" --quick "$persp" "$tmp/bench" 2>"$tmp/err"); rc=$?
    if [ "$rc" -ne 0 ]; then bad "bench.sh --quick from $from exited $rc: $(cat "$tmp/err") $out"
    else
        if git -C "$from" rev-parse --short HEAD >/dev/null 2>&1; then
            grep -qE "^CPU: .+; persp commit [0-9a-f]+" <<<"$out" && ok || bad "no CPU / commit line: $out"
        else
            grep -qE "^CPU: .+; persp version $version, not a git checkout;" <<<"$out" && ok ||
                bad "no CPU / version line from $from: $out"
        fi
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
done

# Two threads with FAR_NS=0: every run counts as far apart, so every row is
# listed under the table with its runs as far runs (where the machine has a
# second processor to measure the round trip to).
if [ "$(nproc)" -gt 1 ]; then
    out=$(THREADS=2 FAR_NS=0 bash "$src/scripts/bench.sh" --quick "$persp" "$tmp/bench2" 2>"$tmp/err"); rc=$?
    if [ "$rc" -ne 0 ]; then bad "bench.sh --quick, two threads, exited $rc: $(cat "$tmp/err")"
    else
        grep -q "^Rows with runs while the vCPUs were far apart" <<<"$out" && ok || bad "no far-apart list: $out"
        far=$(grep -cE "^- (torus-(2k|20k|200k|2m)|soup-200k|corridor) .*, 2 threads: 1 of 1 runs .* near runs none, far runs [0-9.]+ Mpix/s" <<<"$out")
        [ "$far" -eq 18 ] && ok || bad "expected 18 far-apart rows, got $far: $out"
    fi
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

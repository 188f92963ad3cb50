#!/usr/bin/env bash
# persp report: the quick page is written with its plots, images and data,
# loads in headless Chromium without script errors and renders to a
# non-blank screenshot; --from builds the page from a merged sharded sweep.
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"

expect 0 "usage: persp report" -- "$persp" report --help
expect 2 "-o DIR is required" -- "$persp" report --quick
expect 2 "unknown option" -- "$persp" report -o "$tmp/x" --bogus
# The folder that cannot be made is the one named.
expect 1 "$tmp/none/r: cannot create the folder" -- "$persp" report --quick -o "$tmp/none/r"

start=$(date +%s)
(cd "$tmp" && "$persp" report --quick -o "$tmp/r") 2>"$tmp/log" || bad "report --quick failed: $(cat "$tmp/log")"
echo "report --quick took $(($(date +%s) - start)) s"
# --max-memory with room: the same page data and images (timings aside).
# (and a folder given with a trailing slash names its files without "//")
"$persp" report --quick --max-memory 256M -o "$tmp/rb/" 2>"$tmp/log_b" ||
    bad "report --quick --max-memory 256M failed: $(cat "$tmp/log_b")"
grep -q "^report: wrote $tmp/rb/index.html$" "$tmp/log_b" && ok || bad "-o DIR/: $(grep wrote "$tmp/log_b")"
same=1
for f in $(cd "$tmp/r" && find . -type f \( -name '*.png' -o -name accuracy.json -o -name '*.svg' \) | sort); do
    cmp -s "$tmp/r/$f" "$tmp/rb/$f" || { same=0; echo "differs with --max-memory: $f"; }
done
[ "$(sed -E 's/"(ms|ns_px)": [0-9.e+-]+//g' "$tmp/r/filter.json")" = \
  "$(sed -E 's/"(ms|ns_px)": [0-9.e+-]+//g' "$tmp/rb/filter.json")" ] || { same=0; echo "filter.json differs"; }
[ "$same" = 1 ] && ok || bad "the memory budget changed the report"
page="$tmp/r/index.html"
# The page names the commit persp was built from (its source tree's), not
# that of the folder the report is run in.
if head=$(git -C "$PERSP_SOURCE_DIR" rev-parse --short=12 HEAD 2>/dev/null); then
    grep -q "git commit<td>$head" "$page" && ok || bad "page's commit: $(grep -o 'git commit<td>[^<]*' "$page")"
else
    grep -q "git commit<td>none: not a git checkout" "$page" && ok ||
        bad "page's commit outside a checkout: $(grep -o 'git commit<td>[^<]*' "$page")"
fi
[ -s "$page" ] && ok || bad "no index.html"
grep -q "^report: method accuracy" "$tmp/log" && grep -q "^report: wrote" "$tmp/log" && ok ||
    bad "progress lines missing on stderr: $(cat "$tmp/log")"
# Inline plots: the error-by-depth panels and the shading figures.
svgs=$(grep -o "<svg" "$page" | wc -l)
[ "$svgs" -ge 3 ] && ok || bad "expected at least 3 inline SVGs, found $svgs"
grep -q "<polyline" "$page" && ok || bad "plots have no lines"
# One id space for the whole page: an id used twice (every plot's clip path
# was c0) makes browsers clip later plots to the first plot's box.
dups=$(grep -oE ' id="?[^" >]+' "$page" | sed -E 's/^ id="?//' | sort | uniq -d)
[ -z "$dups" ] && ok || bad "ids used more than once in the page: $(echo $dups)"
refs_ok=1
for id in $(grep -oE 'url\(#[^)]+\)' "$page" | sed -E 's/^url\(#//; s/\)$//' | sort -u); do
    grep -qE " id=\"?$id[\" >]" "$page" || { refs_ok=0; echo "url(#$id) names no id"; }
done
[ "$refs_ok" = 1 ] && ok || bad "clip-path references without their ids"
grep -q "filter quality against tilt" "$page" && ok || bad "no filter plot"
for section in 'id=methods' 'id=claims' 'id=images' 'id=shading' 'id=filters' 'id=env' 'PSNR' \
    'Reproduce:' 'class=holds' 'model name\|CPU'; do
    grep -q "$section" "$page" && ok || bad "page lacks '$section'"
done
# No network: every src/href is a local file that exists and is not empty.
refs=$(grep -oE '(src|href|value)="[^"#]+\.(png|json|svg)"' "$page" | sed -E 's/^[a-z]+="//; s/"$//' | sort -u)
n=0
for f in $refs; do
    n=$((n + 1))
    [ -s "$tmp/r/$f" ] || bad "referenced file $f missing or empty"
done
[ "$n" -ge 50 ] && ok || bad "expected the images of every method, found $n files referenced"
grep -qE '(src|href)="(https?:)?//' "$page" && bad "page references the network" || ok
for f in "$tmp"/r/img/corridor_exact.png "$tmp"/r/heat/corridor-*_affine.png; do
    [ "$(head -c 8 "$f" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] && ok || bad "$f is not a PNG"
done
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert len(d['rows']) > 100" "$tmp/r/accuracy.json" &&
    ok || bad "accuracy.json beside the page"

# The page in a browser.
browser=""
for b in chromium chromium-browser google-chrome; do
    command -v "$b" >/dev/null 2>&1 && browser="$b" && break
done
if [ -z "$browser" ]; then
    echo "SKIP: no chromium (scripts/deps.sh installs it); the page was checked without a browser"
else
    flags=(--headless --no-sandbox --disable-gpu --user-data-dir="$tmp/profile" --enable-logging=stderr --v=0)
    timeout 120 "$browser" "${flags[@]}" --dump-dom "file://$page" >"$tmp/dom" 2>"$tmp/console" ||
        bad "chromium --dump-dom failed: $(tail -5 "$tmp/console")"
    # The slider's script marks the slider once it has run without throwing.
    grep -q 'data-slider="ready"' "$tmp/dom" && ok || bad "the slider script did not run"
    grep -q "<svg" "$tmp/dom" && grep -q "<img" "$tmp/dom" && ok || bad "DOM lacks plots or images"
    # The page logs nothing itself: any console line is an error or a warning.
    grep -E ":CONSOLE[:(]|Uncaught" "$tmp/console" && bad "console messages (errors) while loading the page" || ok
    timeout 120 "$browser" "${flags[@]}" --hide-scrollbars --screenshot="$tmp/shot.png" --window-size=1280,2000 \
        "file://$page" >/dev/null 2>"$tmp/console" || bad "chromium --screenshot failed: $(tail -5 "$tmp/console")"
    # Not blank: many distinct colours and a spread of brightness.
    PYTHONPATH="$(dirname "$0")" python3 - "$tmp/shot.png" <<'PY' && ok || bad "screenshot is blank or unreadable"
import sys
from png_rows import png
w, h, rows = png(sys.argv[1])
colours, lum = set(), []
for y in range(0, h, 8):
    for x in range(0, w, 8):
        colours.add(rows[y][x])
        lum.append(sum(rows[y][x]))
mean = sum(lum) / len(lum)
var = sum((v - mean) ** 2 for v in lum) / len(lum)
print("screenshot: %dx%d, %d colours, brightness sd %.1f" % (w, h, len(colours), var ** 0.5))
assert len(colours) > 50 and var ** 0.5 > 20
PY
fi

# --from: the page of a merged sharded sweep, measured nothing itself.
mkdir -p "$tmp/sweep"
sweep=(accuracy --method exact,affine,quadratic,quadratic-shifted,quadratic-unnorm,incremental
    --case paper-quad,random-triangles,corridor,floor --size 64x48 --triangles 2 --json)
for k in 1 2; do "$persp" "${sweep[@]}" --shard $k/2 >"$tmp/sweep/s$k.json" || bad "shard $k"; done
"$persp" merge -o "$tmp/sweep/accuracy.json" "$tmp"/sweep/s*.json || bad "merge"
cp "$tmp/r/filter.json" "$tmp/sweep/filter.json"
"$persp" report --from "$tmp/sweep" -o "$tmp/r2" 2>"$tmp/log2" || bad "report --from: $(cat "$tmp/log2")"
grep -q "read from a merged sweep" "$tmp/r2/index.html" && ok || bad "--from page does not say where its data came from"
grep -q "<td>quadratic-shifted<td>" "$tmp/r2/index.html" && ok || bad "--from page lacks the sweep's methods"
[ -s "$tmp/r2/img/corridor_affine_crop.png" ] && ok || bad "--from page lacks images"
grep -q "filter quality against tilt" "$tmp/r2/index.html" && [ -s "$tmp/r2/filter.json" ] && ok ||
    bad "--from page lacks the filter results of filter.json"
grep -q "^report: method accuracy" "$tmp/log2" && bad "--from measured the methods again" || ok
expect 1 "accuracy.json" -- "$persp" report --from "$tmp/nowhere" -o "$tmp/r3"
# The hardware section: only from a summary named (or out/hw/summary.json
# of the folder persp runs in), with its rows; none without one.
mkdir -p "$tmp/hw"
printf '{"modules": [{"module": "exact", "cmos_transistors": 86086, "ice40_lc": 2353, "ice40_dsp": 6, "fmax_mhz": 17.2, "pixels_per_clock": 1.0, "max_error_texels": 0.17, "vectors_checked": 481566, "mismatches": 0}]}\n' >"$tmp/hw/summary.json"
"$persp" report --from "$tmp/sweep" --hardware "$tmp/hw/summary.json" -o "$tmp/r4" 2>"$tmp/log4" || bad "report --hardware: $(cat "$tmp/log4")"
grep -q "id=hardware" "$tmp/r4/index.html" && grep -q "<td>exact<td>86086" "$tmp/r4/index.html" && ok ||
    bad "--hardware page lacks the summary's table"
grep -q "id=hardware" "$tmp/r2/index.html" && bad "a page without a summary has a hardware section" || ok

echo "test_report: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

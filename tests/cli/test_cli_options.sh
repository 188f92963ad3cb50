#!/usr/bin/env bash
# Options shared by render, bench and accuracy: --opt=value reads like
# --opt value, -o - writes the image (or report) to standard output and
# nothing else goes there, the image format follows the -o file's extension
# (JPEG loads back close to the PNG; an unknown extension is a usage error),
# every command fails with a message when its output cannot be written
# (/dev/full), and each command's --help lists the shared options.
# ctest-labels: threads (persp runs with --threads > 1)
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"

sig() { head -c "$2" "$1" | od -An -tx1 | tr -d ' \n'; }
png_sig=89504e470d0a1a0a
jpeg_sig=ffd8ff

# A PNG decoder (8-bit RGBA, as persp writes) for size and pixel checks.
have_python=0
command -v python3 >/dev/null && have_python=1
cat >"$tmp/png.py" <<'PY'
import sys
from png_rows import png

if sys.argv[1] == 'size':
    w, h, _ = png(sys.argv[2])
    print('%dx%d' % (w, h))
else:  # diff A B: largest and mean RGB difference
    (w, h, a), (w2, h2, b) = png(sys.argv[2]), png(sys.argv[3])
    assert (w, h) == (w2, h2), 'sizes differ'
    d = [abs(p[c] - q[c]) for ra, rb in zip(a, b) for p, q in zip(ra, rb) for c in range(3)]
    print('%d %.3f' % (max(d), sum(d) / len(d)))
PY
export PYTHONPATH="$(cd "$(dirname "$0")" && pwd)"

# ------------------------------------------------------------ --opt=value
expect 0 "32x24, method affine, filter nearest, shading none, depth 1/w, 2 threads" -- \
    "$persp" render cube --size=32x24 --method=affine --filter=nearest --depth=invw --threads=2 -o "$tmp/eq.png"
"$persp" render cube --size 32x24 --method affine --filter nearest --depth invw --threads 2 -q -o "$tmp/sp.png"
cmp -s "$tmp/eq.png" "$tmp/sp.png" && ok || bad "--opt=value and --opt value give different images"
expect 0 "" -- "$persp" render corridor --size=32x24 --lod-bias=-1.5 --min-lod=0 --max-lod=2 --filter=trilinear -q --output="$tmp/lod.png"
[ -s "$tmp/lod.png" ] && ok || bad "--output=FILE wrote nothing"
expect 2 "render: bad --size '0x10' \(expected WxH" -- "$persp" render --size=0x10
expect 2 "render: bad --cull 'maybe' \(expected on or off\)" -- "$persp" render --cull=maybe
expect 2 "render: option --quiet takes no value" -- "$persp" render --quiet=yes
# persp methods parses with the common table: its messages and help alike.
expect 2 "methods: unknown option '--bogus' \(see persp methods --help\)" -- "$persp" methods --bogus
expect 2 "methods: unexpected argument 'extra'" -- "$persp" methods extra
expect 0 "-h, --help" -- "$persp" methods --help
expect 2 "render: unknown option '--bogus' \(see persp render --help\)" -- "$persp" render --bogus=1
expect 2 "render: option --depth needs a value \(expected z or invw\)" -- "$persp" render --depth
expect 2 "render: unknown filter 'blurry' \(expected nearest, bilinear, .* or ewa\)" -- "$persp" render --filter=blurry
expect 2 "render: bad --quality '0' \(expected 1..100\)" -- "$persp" render --quality 0
expect 2 "render: bad --format 'gif' \(expected png, jpeg or jpg\)" -- "$persp" render --format=gif
expect 0 "^method,case," -- "$persp" accuracy --method=exact --case=paper-quad --csv
expect 2 "accuracy: bad --triangles '0' \(expected 1..100000\)" -- "$persp" accuracy --triangles=0
expect 0 "^  screen +nearest " -- "$persp" accuracy --filter=nearest --case=tilt-0 --size=16x12 --samples=1 --repeats=1
expect 2 "accuracy --shading: bad --seed 'x'" -- "$persp" accuracy --shading --seed=x
expect 2 "bench: bad --reps '0' \(expected 1..100\)" -- "$persp" bench --reps=0
if "$persp" bench --size=16x12 --frames=1 --reps=1 --json >"$tmp/b.json" 2>"$tmp/err" &&
   python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); assert j["width"] == 16 and j["results"][0]["frames"] == 1' "$tmp/b.json"
then ok; else bad "bench --size=16x12 --json: $(cat "$tmp/err")"; fi

# ------------------------------------------------------------------- -o -
# The image alone on standard output, byte for byte the file -o would write;
# the summary on standard error.
"$persp" render cube --size 32x24 -o - >"$tmp/out.png" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] && ok || bad "render -o - exited $rc: $(cat "$tmp/err")"
[ "$(sig "$tmp/out.png" 8)" = "$png_sig" ] && ok || bad "render -o - did not write a PNG to standard output"
grep -q "rendered cube: 32x24" "$tmp/err" && grep -q -- "-> standard output" "$tmp/err" && ok || bad "no summary on stderr: $(cat "$tmp/err")"
"$persp" render cube --size 32x24 -q -o "$tmp/file.png"
cmp -s "$tmp/out.png" "$tmp/file.png" && ok || bad "-o - output differs from the -o FILE image"
"$persp" render cube --size 32x24 -q -o - >"$tmp/q.png" 2>"$tmp/err"
[ ! -s "$tmp/err" ] && cmp -s "$tmp/q.png" "$tmp/file.png" && ok || bad "-o - -q: $(cat "$tmp/err")"
# Decodable: persp loads it as a texture, and a PNG decoder reads 32x24 pixels.
expect 0 "" -- "$persp" render floor --size 16x12 -q --texture "$tmp/out.png" -o "$tmp/tex.png"
if [ "$have_python" = 1 ]; then
    [ "$(python3 "$tmp/png.py" size "$tmp/out.png" 2>&1)" = "32x24" ] && ok || bad "-o - PNG does not decode to 32x24"
fi
# --format jpeg on standard output: a whole JPEG (SOI ... EOI).
"$persp" render cube --size 32x24 -q -o - --format jpeg >"$tmp/out.jpg"
[ "$(sig "$tmp/out.jpg" 3)" = "$jpeg_sig" ] && [ "$(tail -c 2 "$tmp/out.jpg" | od -An -tx1 | tr -d ' \n')" = "ffd9" ] \
    && ok || bad "render -o - --format jpeg did not write a JPEG"
# Pipes work too (no seeking on the stream).
"$persp" render cube --size 32x24 -q -o - | cat >"$tmp/piped.png"
cmp -s "$tmp/piped.png" "$tmp/file.png" && ok || bad "-o - through a pipe differs"
# Reports: -o - is standard output, -o FILE the same bytes in a file.
"$persp" accuracy --method exact,affine --case paper-quad --csv >"$tmp/r1.csv"
"$persp" accuracy --method exact,affine --case paper-quad --csv -o - >"$tmp/r2.csv"
"$persp" accuracy --method exact,affine --case paper-quad --csv -o "$tmp/r3.csv" >"$tmp/r3.out"
cmp -s "$tmp/r1.csv" "$tmp/r2.csv" && cmp -s "$tmp/r1.csv" "$tmp/r3.csv" && [ ! -s "$tmp/r3.out" ] && ok \
    || bad "accuracy -o - / -o FILE differ from standard output"
"$persp" accuracy --filter nearest --case tilt-0 --size 16x12 --samples 1 --repeats 1 --json -o "$tmp/f.json" >/dev/null
python3 -c 'import json,sys; assert json.load(open(sys.argv[1]))[0]["filter"] == "nearest"' "$tmp/f.json" && ok \
    || bad "accuracy --filter -o FILE is not the JSON report"
"$persp" accuracy --shading --triangles 1 --size 32x24 -o "$tmp/s.txt" >"$tmp/s.out"
grep -qF "4. Delta I" "$tmp/s.txt" && [ ! -s "$tmp/s.out" ] && ok || bad "accuracy --shading -o FILE"
"$persp" bench --size 16x12 --frames 1 --reps 1 --json -o "$tmp/bench.json" >"$tmp/bench.out"
python3 -m json.tool "$tmp/bench.json" >/dev/null && [ ! -s "$tmp/bench.out" ] && ok || bad "bench -o FILE"
expect 1 "accuracy: cannot create '$tmp/no/dir/r.csv'" -- "$persp" accuracy --case paper-quad --method exact -o "$tmp/no/dir/r.csv"
expect 2 "unknown case" -- "$persp" accuracy --case nowhere -o "$tmp/never.csv"
[ ! -e "$tmp/never.csv" ] && ok || bad "a failed accuracy run left its report file"

# ------------------------------------------------- format from the extension
expect 0 "-> $tmp/c.jpg" -- "$persp" render corridor --size 64x64 -o "$tmp/c.jpg"
[ "$(sig "$tmp/c.jpg" 3)" = "$jpeg_sig" ] && ok || bad "-o x.jpg is not a JPEG"
expect 0 "" -- "$persp" render corridor --size 64x64 -q -o "$tmp/c.JPEG"
[ "$(sig "$tmp/c.JPEG" 3)" = "$jpeg_sig" ] && ok || bad "-o x.JPEG is not a JPEG"
expect 0 "" -- "$persp" render corridor --size 64x64 -q -o "$tmp/c.png"
[ "$(sig "$tmp/c.png" 8)" = "$png_sig" ] && ok || bad "-o x.png is not a PNG"
expect 0 "" -- "$persp" render corridor --size 64x64 -q --quality 30 -o "$tmp/c30.jpg"
[ "$(wc -c <"$tmp/c30.jpg")" -lt "$(wc -c <"$tmp/c.jpg")" ] && ok || bad "--quality 30 is not smaller than the default"
expect 0 "warning: --quality applies to JPEG output only" -- \
    "$persp" render corridor --size 16x16 --quality 30 -o "$tmp/q.png"
expect 0 "-o, --output DIR" -- "$persp" report --help
# Loads back close to the PNG: a square facing the camera that fills a 90°
# view shows its texture texel for pixel, so rendering it with --texture
# turns an image file into a PNG of the same pixels.
mkdir -p "$tmp/quad"
cp "$tmp/c.png" "$tmp/quad/tex.png"
cat >"$tmp/quad/quad.json" <<'EOF'
{
  "camera": {"position": [0, 0, 0], "target": [0, 0, -1], "fov": 90, "near": 0.5, "far": 2},
  "materials": {"m": {"texture": {"file": "tex.png", "wrap": "clamp-to-edge", "filter": "nearest"}}},
  "objects": [{"mesh": "plane", "material": "m", "transform": {"rotate": [90, 1, 0, 0], "translate": [0, 0, -1]}}]
}
EOF
quad() { "$persp" render "$tmp/quad/quad.json" --size 64x64 --filter nearest -q --texture "$1" -o "$2"; }
quad "$tmp/c.png" "$tmp/via_png.png" && quad "$tmp/c.jpg" "$tmp/via_jpg.png" && ok || bad "the JPEG does not load back"
if [ "$have_python" = 1 ]; then
    d=$(python3 "$tmp/png.py" diff "$tmp/c.png" "$tmp/via_png.png")
    [ "$d" = "0 0.000" ] && ok || bad "the quad scene does not copy its texture exactly (max, mean: $d)"
    d=$(python3 "$tmp/png.py" diff "$tmp/c.png" "$tmp/via_jpg.png")
    awk -v d="$d" 'BEGIN { split(d, v, " "); exit !(v[1] <= 64 && v[2] < 8) }' && ok \
        || bad "the JPEG differs too much from the PNG (max, mean: $d)"
fi
# Unknown or missing extension: a usage error before rendering, no file.
expect 2 "render: cannot tell the image format of '$tmp/x.bmp' from its extension \(expected .png, .jpg or .jpeg" -- \
    "$persp" render cube --size 8x8 -o "$tmp/x.bmp"
expect 2 "cannot tell the image format of '$tmp/noext'" -- "$persp" render cube --size 8x8 -o "$tmp/noext"
[ ! -e "$tmp/x.bmp" ] && [ ! -e "$tmp/noext" ] && ok || bad "an unknown extension left a file"
expect 2 "render: --format jpeg does not match the extension of '$tmp/y.png'" -- \
    "$persp" render cube --size 8x8 --format jpeg -o "$tmp/y.png"
expect 0 "" -- "$persp" render cube --size 8x8 -q --format jpeg -o "$tmp/img.data"
[ "$(sig "$tmp/img.data" 3)" = "$jpeg_sig" ] && ok || bad "--format jpeg with another extension"
# Replacing a file is atomic: a failed render keeps the old one, and no
# temporary file is left anywhere.
cp "$tmp/c.png" "$tmp/keep.png"
expect 1 "missing.png" -- "$persp" render cube --size 8x8 --texture "$tmp/missing.png" -o "$tmp/keep.png"
cmp -s "$tmp/c.png" "$tmp/keep.png" && ok || bad "a failed render changed the existing output file"
[ -z "$(find "$tmp" -name '*.tmp-*')" ] && ok || bad "temporary files left: $(find "$tmp" -name '*.tmp-*')"

# ----------------------------------------------------------- write errors
# Each command reports output it could not write (exit 1, a message on
# stderr) instead of succeeding silently; /dev/full stays a device.
if [ -c /dev/full ]; then
    full() {
        local out rc
        out=$("$@" 2>&1 >/dev/full); rc=$?
        if [ "$rc" -ne 1 ]; then bad "$* >/dev/full exited $rc, expected 1: $out"; return; fi
        if ! grep -qE "writ|No space" <<<"$out"; then bad "$* >/dev/full: no write error message: $out"; return; fi
        ok
    }
    full "$persp" render cube --size 16x12 -o -
    full "$persp" render cube --size 16x12 -o - --format jpeg
    full "$persp" render cube --size 16x12 -o /dev/full
    full "$persp" render cube --size 16x12 -q -o /dev/full --format jpeg
    full "$persp" render cube --size 16x12 -o "$tmp/ok.png"
    full "$persp" render --help
    full "$persp" methods
    full "$persp" --help
    full "$persp" --version
    full "$persp" accuracy --method exact --case paper-quad
    full "$persp" accuracy --method exact --case paper-quad --json
    full "$persp" accuracy --method exact --case paper-quad -o /dev/full
    full "$persp" accuracy --filter nearest --case tilt-0 --size 16x12 --samples 1 --repeats 1
    full "$persp" accuracy --shading --triangles 1 --size 32x24
    full "$persp" bench --size 16x12 --frames 1 --reps 1
    full "$persp" bench --size 16x12 --frames 1 --reps 1 --json
    full "$persp" bench --size 16x12 --frames 1 --reps 1 --json -o /dev/full
    [ -c /dev/full ] && ok || bad "/dev/full is no longer a character device"
fi
# Devices without an extension get a PNG (like standard output).
expect 0 "" -- "$persp" render cube --size 16x12 -q -o /dev/null
[ -c /dev/null ] && ok || bad "/dev/null is no longer a character device"

# ------------------------------------------------------------------ --help
# The shared options appear in each command's help, generated from its table.
help_lists() {
    local cmd="$1" out; shift
    out=$("$persp" $cmd --help 2>&1) || { bad "persp $cmd --help failed"; return; }
    for o in "$@"; do
        grep -qE -- "^  $o( |$)" <<<"$out" && ok || bad "persp $cmd --help lacks $o"
    done
}
help_lists render "-o, --output FILE" "--format png\|jpeg" "--quality N" "--method M" "--filter F" "--wrap W" \
    "--shading S" "--size WxH" "--depth z\|invw" "--lod pixel\|polygon" "--lod-bias B" "--min-lod L" \
    "--max-lod L" "--pipeline screen\|object" "--texture FILE" "--threads N" "--cull on\|off" "--count-ops" \
    "-q, --quiet" "-h, --help"
help_lists bench "-o, --output FILE" "--method M\|all" "--filter F" "--threads N" "--size WxH" "--json" \
    "--frames N" "--reps N" "--time S" "--peer D" "-h, --help"
help_lists accuracy "-o, --output FILE" "--method M\[,M...\]" "--case C\[,C...\]" "--size WxH" "--seed N" \
    "--csv" "--json" "--heatmap DIR" "--filter \[F,...\]" "-h, --help"
help_lists "accuracy --filter" "-o, --output FILE" "--filter \[F,...\]" "--size WxH" "--threads N" \
    "--lod pixel\|polygon" "--lod-bias B" "--csv" "--json" "--heatmap DIR" "-h, --help"
help_lists "accuracy --shading" "-o, --output FILE" "--seed N" "--size WxH" "-h, --help"
# The same shared option reads the same in every command that takes it.
for c in render "accuracy --filter"; do
    "$persp" $c --help | grep -E -- "^  --lod-bias B " >>"$tmp/lodbias"
done
[ "$(sort -u "$tmp/lodbias" | wc -l)" -eq 1 ] && ok || bad "--lod-bias help differs between commands: $(cat "$tmp/lodbias")"

echo "cli options: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

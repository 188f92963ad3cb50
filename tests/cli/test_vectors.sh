#!/usr/bin/env bash
# `persp vectors`: test vectors of midpoint:int checked by a second model of
# the method written from docs/METHODS.md (midpoint_vectors_check.py) on
# every path a design must reproduce — ordinary pixels, re-seeds after 32
# lattice steps, spans leaving the format part-way and whole spans outside
# it, both lattices — and bad input refused with the file and line.
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"
check="$(dirname "$0")/midpoint_vectors_check.py"

# run NAME CHECK-PATTERN -- persp vectors options...
run() {
    local name="$1" want="$2"; shift 3
    if ! "$persp" vectors "$@" -o "$tmp/$name.txt" 2>"$tmp/$name.err"; then
        bad "vectors $*: $(cat "$tmp/$name.err")"; return
    fi
    local out
    if ! out=$(python3 "$check" "$tmp/$name.txt"); then bad "vectors $*: $out"; return; fi
    if grep -qE -- "$want" <<<"$out"; then ok; else bad "vectors $* lacks /$want/: $out"; fi
}
nonzero='[1-9][0-9]*'
run plain "int_pixels=$nonzero double_pixels=0 " -- --triangles 12
run edge "int_pixels=$nonzero " -- --method midpoint:int,edge --triangles 12 --depth-ratio 100
# 4096 texels over a few pixels: more than 32 texels a pixel re-seeds.
run reseed "reseeds=$nonzero" -- --texture-size 4096x4096 --triangles 10
# u up to 20 on 4096 texels crosses the format's 2^16 texel limit inside spans.
run limit "fallbacks=$nonzero" -- --texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3
run outside "double_spans=$nonzero" -- --texture-size 4096x4096 --uv-range 100 --triangles 4
if [ "$(grep -c '^tri ' "$tmp/plain.txt")" -eq 12 ] && grep -q '^# 12 triangles' "$tmp/plain.txt"; then ok; else bad "12 triangles"; fi
# The same seed gives the same file; another seed another one.
"$persp" vectors --triangles 12 -o "$tmp/again.txt" 2>/dev/null
"$persp" vectors --triangles 12 --seed 2 -o "$tmp/other.txt" 2>/dev/null
if cmp -s "$tmp/plain.txt" "$tmp/again.txt" && ! cmp -s "$tmp/plain.txt" "$tmp/other.txt"; then ok; else bad "seeding"; fi

# Triangles from a file: comments, blank lines, one degenerate and one
# off-screen triangle (no spans), a triangle larger than a tile.
cat >"$tmp/tris.txt" <<'TRIS'
# x y w u v, three vertices a line
10 10 1 0 0   200 30 4 1 0   40 150 2 0 1
5 5 1 0 0  10 10 1 1 1  15 15 1 0 1   # degenerate: a line

-50 -50 1 0 0  -10 -50 1 1 0  -30 -10 1 0 1
TRIS
run input "triangles=3 " -- --input "$tmp/tris.txt" --size 256x256 --texture-size 64x32
if grep -q '^# window 256x256, texture 64x32, triangles from ' "$tmp/input.txt" && [ "$(grep -c '^span ' "$tmp/input.txt")" -gt 64 ]; then ok; else bad "input spans"; fi

printf '1 2 1 0 0  3 4 0 1 0  5 1 1 0 1\n' >"$tmp/w0.txt"
expect 1 "w0.txt:1: vertex 2 has w = 0" -- "$persp" vectors --input "$tmp/w0.txt" -o "$tmp/w0.out"
if [ ! -e "$tmp/w0.out" ]; then ok; else bad "refused input left $tmp/w0.out"; fi
printf '# ok\n1 2 1 0 0  3 4 1 1 0  5 1 1 0\n' >"$tmp/short.txt"
expect 1 "short.txt:2: 14 numbers, expected 15" -- "$persp" vectors --input "$tmp/short.txt"
printf '1 2 1 0 0  3 4 1 1 0  5 1 1 0 x\n' >"$tmp/word.txt"
expect 1 "word.txt:1: number 15 is not a number" -- "$persp" vectors --input "$tmp/word.txt"
printf '1 2 1 0 0  3 4 1 1 0  5 1 1 0 nan\n' >"$tmp/nan.txt"
expect 1 "nan.txt:1: number 15 is not finite" -- "$persp" vectors --input "$tmp/nan.txt"
expect 1 "nope.txt: cannot open" -- "$persp" vectors --input "$tmp/nope.txt"
# Numbers are decimal: strtod's hexadecimal is refused, not read as 16.
printf '1 2 1 0 0  3 4 1 1 0  5 1 1 0 0x10\n' >"$tmp/hex.txt"
expect 1 "hex.txt:1: number 15 is not a number" -- "$persp" vectors --input "$tmp/hex.txt"
printf '1 2 1 0 0  3 4 1 1 0  5 1 1 0 -inf\n' >"$tmp/inf.txt"
expect 1 "inf.txt:1: number 15 is not finite" -- "$persp" vectors --input "$tmp/inf.txt"
# A NUL byte is an error naming its line, not the end of the line.
printf '# ok\n1 2 1 0 0  3 4 1 1 0  5 1 1 0 1\0 junk\n' >"$tmp/nul.txt"
expect 1 "nul.txt:2: a NUL byte in the line" -- "$persp" vectors --input "$tmp/nul.txt"
mkdir -p "$tmp/dir.txt"
expect 1 "dir.txt: is a directory" -- "$persp" vectors --input "$tmp/dir.txt"
expect 2 "-o '$tmp/tris.txt' is the input file" -- "$persp" vectors --input "$tmp/tris.txt" -o "$tmp/tris.txt"
# The output is capped: one triangle over the whole window is refused with
# the option that raises the cap, and leaves no file.
printf -- '-10 -10 1 0 0  2000 -10 1 1 0  -10 2000 1 0 1\n' >"$tmp/full.txt"
expect 1 "would exceed --max-output 1048576 bytes; nothing was written \(raise --max-output" -- \
    "$persp" vectors --input "$tmp/full.txt" --max-output 1M -o "$tmp/full.out"
if [ ! -e "$tmp/full.out" ]; then ok; else bad "a capped output left $tmp/full.out"; fi
for m in exact tw_cubic subdiv; do
    expect 1 "would exceed --max-output 4096 bytes" -- "$persp" vectors --module $m --input "$tmp/full.txt" \
        --max-output 4K -o "$tmp/full_$m.out"
done
expect 2 "bad --max-output '0'" -- "$persp" vectors --max-output 0
"$persp" vectors --input "$tmp/full.txt" --max-output 64M -o "$tmp/full.out" 2>/dev/null && ok ||
    bad "a raised --max-output still refused"
expect 2 "bad --method 'midpoint'" -- "$persp" vectors --method midpoint
expect 2 "--input takes the triangles from its file" -- "$persp" vectors --input "$tmp/tris.txt" --seed 2
expect 2 "bad --texture-size '0x4'" -- "$persp" vectors --texture-size 0x4
expect 0 "usage: persp vectors" -- "$persp" vectors --help
expect 0 "vectors +test vectors of midpoint:int" -- "$persp" --help


# --module: midpoint_int is the default, byte for byte; exact writes the
# RTL baseline's vectors (docs/HARDWARE.md, "Vectors") with its model's error.
"$persp" vectors --module midpoint_int --triangles 12 -o "$tmp/module.txt" 2>/dev/null
if cmp -s "$tmp/plain.txt" "$tmp/module.txt"; then ok; else bad "--module midpoint_int differs from the default"; fi
if "$persp" vectors --module exact --triangles 12 -o "$tmp/exact.txt" 2>/dev/null &&
   grep -q '^# persp test vectors of the RTL module exact, format 1' "$tmp/exact.txt" &&
   grep -qE '^# 12 triangles, [0-9]+ spans, [0-9]+ pixels \([1-9][0-9]* in the hardware, 0 of them out of range\), max \|du\| 0\.0[0-9]+ texels' "$tmp/exact.txt" &&
   [ "$(grep -c '^xpx ' "$tmp/exact.txt")" -gt 1000 ] && [ "$(grep -c '^xfmt ' "$tmp/exact.txt")" -eq 12 ]; then ok
else bad "--module exact: $(tail -1 "$tmp/exact.txt")"; fi
# |t| beyond 2^15 texels: pixels flagged out of range.
"$persp" vectors --module exact --texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3 -o "$tmp/exact_ovf.txt" 2>/dev/null
if grep -q '^xpx 1 ' "$tmp/exact_ovf.txt" && grep -q '^xspan [0-9]* [0-9]* [0-9]* 0 ' "$tmp/exact_ovf.txt"; then ok; else bad "exact out of range"; fi
expect 2 "--module exact has none" -- "$persp" vectors --module exact --method midpoint:int
expect 2 "bad --module 'nosuch'" -- "$persp" vectors --module nosuch
# Every module writes vectors a testbench can read: records after the
# header, and the closing line with the counts.
for m in subdiv subdiv:8 incremental quadratic cubic bezier window_one window_two tw_exact tw_quadratic tw_pwquad tw_cubic; do
    if "$persp" vectors --module "$m" --triangles 3 -o "$tmp/m.txt" 2>/dev/null && [ "$(grep -vc '^#' "$tmp/m.txt")" -gt 3 ] &&
        tail -n 1 "$tmp/m.txt" | grep -q '^#'; then ok; else bad "--module $m wrote no vectors"; fi
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

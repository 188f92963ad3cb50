#!/usr/bin/env bash
# `persp render` with every texture filter, the level-of-detail options and
# the object-space pipeline: images are written, the object pipeline reports
# its pieces and no holes, and bad values exit 2 naming the problem.
# ctest-labels: threads (persp runs with --threads > 1)
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"

for f in nearest bilinear nearest-mip-nearest bilinear-mip-nearest nearest-mip-linear trilinear \
         aniso:2 aniso:16 aniso-window:4 ewa; do
    name=${f/:/-}
    expect 0 "filter $f" -- "$persp" render corridor --filter "$f" --size 64x48 -o "$tmp/$name.png"
    if [ -s "$tmp/$name.png" ]; then ok; else bad "no image for $f"; fi
done
expect 0 "filter trilinear" -- "$persp" render floor --filter trilinear --lod polygon --size 64x48 -o "$tmp/p.png"
expect 0 "filter trilinear" -- "$persp" render floor --filter trilinear --lod-bias 1.5 --min-lod 0.5 --max-lod 3 --size 64x48 -o "$tmp/b.png"
expect 0 "object space: [0-9]+ pieces, [0-9]+ samples walked, [0-9]+ splats, 0 holes" -- \
    "$persp" render corridor --pipeline object --size 96x72 -o "$tmp/o.png"
expect 0 "object space: .* 0 holes" -- "$persp" render floor --pipeline object --threads 3 --size 96x72 -o "$tmp/o2.png"
# --max-lod 0 keeps every pixel on level 0: trilinear then equals bilinear.
"$persp" render corridor --filter trilinear --min-lod 0 --max-lod 0 --size 64x48 -q -o "$tmp/l0.png"
"$persp" render corridor --filter bilinear --size 64x48 -q -o "$tmp/bl.png"
if cmp -s "$tmp/l0.png" "$tmp/bl.png"; then ok; else bad "trilinear clamped to level 0 differs from bilinear"; fi
# --min-lod 3 changes the image (the near end is magnified otherwise).
"$persp" render corridor --filter trilinear --min-lod 3 --size 64x48 -q -o "$tmp/l3.png"
if cmp -s "$tmp/l3.png" "$tmp/bl.png"; then bad "--min-lod 3 had no effect"; else ok; fi

expect 2 "bad --filter 'aniso:1': aniso taps must be 2..16" -- "$persp" render --filter aniso:1
expect 2 "unknown filter 'box'" -- "$persp" render --filter box
expect 2 "bad --lod 'face'" -- "$persp" render --lod face
expect 2 "bad --min-lod 'x'" -- "$persp" render --min-lod x
expect 2 "bad --max-lod '2000'" -- "$persp" render --max-lod 2000
expect 2 "--min-lod 3 is above --max-lod 2" -- "$persp" render --min-lod 3 --max-lod 2
expect 2 "bad --pipeline 'world'" -- "$persp" render --pipeline world

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

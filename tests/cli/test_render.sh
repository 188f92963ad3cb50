#!/usr/bin/env bash
# CLI behaviour of `persp render`, `persp methods`, `--help` and `--version`:
# successful renders write a PNG, bad usage exits 2 with a message naming the
# problem, failures exit 1 and leave no output file behind.
# ctest-labels: threads (persp runs with --threads > 1)
set -u
persp="$1"
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
. "$(dirname "$0")/lib.sh"

expect 0 "usage: persp" -- "$persp" --help
expect 0 "^persp [0-9]+\.[0-9]+\.[0-9]+" -- "$persp" --version
expect 2 "unknown command 'frobnicate'" -- "$persp" frobnicate
expect 2 "usage" -- "$persp"
expect 0 "--method" -- "$persp" render --help
expect 0 "^exact " -- "$persp" methods
expect 0 "^affine " -- "$persp" methods

expect 0 "1024x768, method exact, filter bilinear" -- "$persp" render corridor --method exact --filter bilinear -o "$tmp/c.png"
[ -s "$tmp/c.png" ] && [ "$(head -c 8 "$tmp/c.png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] && ok || bad "corridor PNG missing or not a PNG"
expect 0 "64x48" -- "$persp" render floor --size 64x48 --depth invw -o "$tmp/f.png"
# Sort first (each thread drawing its own tile rows) and sort middle give
# the same image and counts, and the summary says which drew it.
expect 0 "3 threads sort first\$" -- "$persp" render "$src/scenes/bench/torus-2k.json" --size 200x150 --threads 3 --sort-first on -o "$tmp/sf-on.png"
expect 0 "3 threads\$" -- "$persp" render "$src/scenes/bench/torus-2k.json" --size 200x150 --threads 3 --sort-first off -o "$tmp/sf-off.png"
cmp -s "$tmp/sf-on.png" "$tmp/sf-off.png" && ok || bad "sort first and sort middle drew different images"
expect 2 "bad --sort-first 'maybe'" -- "$persp" render "$src/scenes/bench/torus-2k.json" --sort-first maybe
expect 0 "method affine" -- "$persp" render cube --method affine --size 40x30 --threads 3 -o "$tmp/k.png"
expect 0 "" -- "$persp" render corridor --size 32x24 --pipeline object -q -o "$tmp/o.png"
# Lit draws keep the screen pipeline's colour, and the user is told so.
expect 0 "warning: object-space pipeline: 6 of 6 triangles are lit or untextured" -- \
    "$persp" render cube --size 32x24 --pipeline object --shading phong -o "$tmp/o.png"
out=$("$persp" render corridor --size 32x24 --pipeline object -o "$tmp/o.png" 2>&1)
grep -q "warning" <<<"$out" && bad "unlit textured corridor warned: $out" || ok
[ -s "$tmp/o.png" ] && ok || bad "object-space render wrote nothing"

expect 2 "unknown option '--bogus'" -- "$persp" render --bogus
expect 2 "unknown method 'nosuch'" -- "$persp" render --method nosuch -o "$tmp/x.png"
expect 2 "bad parameters in method 'exact:3'" -- "$persp" render --method exact:3 -o "$tmp/x.png"
expect 2 "unknown filter 'blurry'" -- "$persp" render --filter blurry -o "$tmp/x.png"
expect 2 "unknown wrap mode 'sideways'" -- "$persp" render --wrap sideways -o "$tmp/x.png"
expect 2 "bad --size '0x10'" -- "$persp" render --size 0x10 -o "$tmp/x.png"
expect 2 "bad --size '100000x100000'" -- "$persp" render --size 100000x100000 -o "$tmp/x.png"
expect 2 "bad --size '16384x16384' .*at most 67108864 pixels" -- "$persp" render --size 16384x16384 -o "$tmp/x.png"
expect 2 "bad --size 'axb'" -- "$persp" render --size axb -o "$tmp/x.png"
expect 2 "bad --depth 'w'" -- "$persp" render --depth w -o "$tmp/x.png"
expect 2 "bad --threads '0'" -- "$persp" render --threads 0 -o "$tmp/x.png"
expect 2 "needs a value" -- "$persp" render -o
expect 2 "more than one scene" -- "$persp" render corridor cube
expect 1 "nowhere/x.png" -- "$persp" render corridor --size 8x8 -o "$tmp/nowhere/x.png"
expect 1 "missing.png" -- "$persp" render corridor --texture "$tmp/missing.png" -o "$tmp/x.png"
printf 'not an image at all' > "$tmp/junk.png"
expect 1 "junk.png" -- "$persp" render corridor --texture "$tmp/junk.png" -o "$tmp/x.png"
[ ! -e "$tmp/x.png" ] && ok || bad "a failed render left $tmp/x.png behind"

# Bad texture files: each a clear message naming the file and the problem,
# exit 1, no output file.
head -c 100 "$tmp/c.png" > "$tmp/trunc.png"
expect 1 "trunc.png: truncated PNG" -- "$persp" render corridor --size 8x8 --texture "$tmp/trunc.png" -o "$tmp/x.png"
# Signature and a valid IHDR chunk (CRC included) claiming 100000x100000 RGBA8.
printf '\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x01\x86\xa0\x00\x01\x86\xa0\x08\x06\x00\x00\x00\xa8\x52\x0b\xc8' > "$tmp/huge.png"
expect 1 "huge.png: image size 100000x100000 exceeds the limit" -- "$persp" render corridor --size 8x8 --texture "$tmp/huge.png" -o "$tmp/x.png"
expect 1 "junk.png: not an image persp reads" -- "$persp" render corridor --size 8x8 --texture "$tmp/junk.png" -o "$tmp/x.png"
expect 1 "missing.png: cannot open" -- "$persp" render corridor --size 8x8 --texture "$tmp/missing.png" -o "$tmp/x.png"
mkdir "$tmp/dir.png"
expect 1 "dir.png: is a directory" -- "$persp" render corridor --size 8x8 --texture "$tmp/dir.png" -o "$tmp/x.png"
printf '\xff\xd8\xff\xe0 not really a JPEG' > "$tmp/bad.jpg"
expect 1 "bad.jpg: corrupt JPEG" -- "$persp" render corridor --size 8x8 --texture "$tmp/bad.jpg" -o "$tmp/x.png"
[ ! -e "$tmp/x.png" ] && ok || bad "a failed texture load left $tmp/x.png behind"
expect 1 "neither a built-in scene \(corridor, floor, cube\) nor a file" -- "$persp" render nosuchscene -o "$tmp/x.png"
expect 2 "bad parameters in method 'subdiv:5' \(expected subdiv:N" -- "$persp" render --method subdiv:5 -o "$tmp/x.png"

# Without -o the image goes to out/SCENE.png, the folder created if needed.
mkdir "$tmp/fresh"
(cd "$tmp/fresh" && "$persp" render cube --size 16x12 -q) && [ -s "$tmp/fresh/out/cube.png" ] && ok || bad "default output out/cube.png not written"

# A valid PNG as --texture replaces the scene's texture: the image changes.
expect 0 "" -- "$persp" render floor --size 64x48 -q -o "$tmp/f1.png"
expect 0 "" -- "$persp" render floor --size 64x48 -q --texture "$tmp/c.png" -o "$tmp/f2.png"
cmp -s "$tmp/f1.png" "$tmp/f2.png" && bad "--texture did not change the image" || ok
# And a JPEG (64x64 checker made with libjpeg, tests/cli/data/checker.jpg).
jpg="$(cd "$(dirname "$0")" && pwd)/data/checker.jpg"
expect 0 "" -- "$persp" render floor --size 64x48 -q --texture "$jpg" -o "$tmp/f3.png"
[ -s "$tmp/f3.png" ] && ! cmp -s "$tmp/f1.png" "$tmp/f3.png" && ok || bad "--texture JPEG did not change the image"

# Every wrap mode renders; on the corridor (u up to 2, v up to 64) repeat and
# clamp-to-edge give different images.
for w in repeat clamp-to-edge mirrored-repeat clamp-to-border; do
    expect 0 "" -- "$persp" render corridor --size 64x48 -q --wrap "$w" -o "$tmp/w-$w.png"
done
cmp -s "$tmp/w-repeat.png" "$tmp/w-clamp-to-edge.png" && bad "--wrap clamp-to-edge had no effect" || ok

# Instrumented render: exact is one division per fragment; midpoint none per
# pixel (one per span at most).
expect 0 "operations per pixel computed \(3072 of 3072 fragments\): 1\.000 div" -- "$persp" render corridor --size 64x48 --count-ops -o "$tmp/ops.png"
# With overdraw (the soup), spans hidden whole run
# no method: still one division per pixel the method computed.
expect 0 "operations per pixel computed \([0-9]+ of [0-9]+ fragments\): 1\.000 div" -- \
    "$persp" render "$PERSP_SOURCE_DIR/scenes/bench/soup-200k.json" --size 64x48 --count-ops -o "$tmp/ops2.png"
out=$("$persp" render corridor --size 64x48 --method midpoint --count-ops -o "$tmp/ops.png" 2>&1)
d=$(sed -nE 's/.*per pixel computed [^:]*: ([0-9.]+) div.*/\1/p' <<<"$out")
awk -v d="${d:-9}" 'BEGIN { exit !(d < 0.5) }' && ok || bad "midpoint --count-ops: $out"

# The summary names the render time apart from encoding and writing, and
# the total.
expect 0 "render [0-9.]+ ms \([0-9.]+ Mpixels/s\), encode and write [0-9.]+ ms, total [0-9.]+ ms -> " -- \
    "$persp" render cube --size 32x24 -o "$tmp/timed.png"
# -o naming an input is refused before anything is written, whatever the
# spelling: the scene, a link to it, the --texture image.
printf '{"objects": [{"mesh": "plane", "transform": {"scale": [3, 1, 3]}}]}\n' >"$tmp/s.json"
cp "$tmp/s.json" "$tmp/s.orig"
expect 2 "-o '$tmp/s.json' is the input file" -- "$persp" render "$tmp/s.json" --format png -o "$tmp/s.json"
expect 2 "is the input file" -- "$persp" render "$tmp/s.json" --format png -o "$tmp/./s.json"
ln -s s.json "$tmp/s_link.json"
expect 2 "is the input file" -- "$persp" render "$tmp/s.json" --format png -o "$tmp/s_link.json"
if cmp -s "$tmp/s.json" "$tmp/s.orig"; then ok; else bad "-o over the scene changed it"; fi
"$persp" render cube --size 16x16 -q -o "$tmp/tex.png"
cp "$tmp/tex.png" "$tmp/tex.orig"
expect 2 "-o '$tmp/tex.png' is the input file '$tmp/tex.png'" -- \
    "$persp" render cube --size 16x12 --texture "$tmp/tex.png" -o "$tmp/tex.png"
if cmp -s "$tmp/tex.png" "$tmp/tex.orig"; then ok; else bad "-o over the texture changed it"; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

#!/usr/bin/env bash
# persp view --play: a checked-in camera path rendered headless twice gives
# identical frames, consecutive frames differ, and bad input is refused.
# ctest-labels: threads (persp view draws with one thread per CPU)
persp="$1"
. "$(dirname "$0")/lib.sh"
data="$PERSP_SOURCE_DIR/tests/cli/data"
path="$data/camera_path.json"

for run in a b; do
    if "$persp" view corridor --play "$path" --frames 4 --size 96x72 --method affine \
        --layout split -q -o "$tmp/$run" 2>"$tmp/err_$run"; then ok; else bad "play $run: $(cat "$tmp/err_$run")"; fi
done
n=$(ls "$tmp/a" | wc -l)
if [ "$n" -eq 4 ]; then ok; else bad "expected 4 frames, got $n"; fi
for i in 0 1 2 3; do
    f=$(printf 'frame_%04d.png' "$i")
    if cmp -s "$tmp/a/$f" "$tmp/b/$f"; then ok; else bad "$f differs between two plays"; fi
done
for i in 0 1 2; do
    a=$(printf 'frame_%04d.png' "$i") b=$(printf 'frame_%04d.png' "$((i + 1))")
    if cmp -s "$tmp/a/$a" "$tmp/a/$b"; then bad "$a and $b are identical"; else ok; fi
done

# The thread count does not change the frames (the library's guarantee).
"$persp" view corridor --play "$path" --frames 4 --size 96x72 --method affine --layout split \
    --threads 1 -o "$tmp/c/" >"$tmp/out_c" 2>&1 && ok || bad "play with one thread"
# (-o DIR/ names the frames without "//")
grep -q "$tmp/c/frame_0003.png" "$tmp/out_c" && ! grep -q "//" "$tmp/out_c" && ok || bad "-o DIR/: $(cat "$tmp/out_c")"
if cmp -s "$tmp/a/frame_0002.png" "$tmp/c/frame_0002.png"; then ok; else bad "threads changed a frame"; fi

# The diff layout of a method against itself is the dimmed image only, and
# the report names zero error.
expect 0 "error max 0, mean 0.000" -- "$persp" view corridor --play "$path" --frames 1 --size 64x48 \
    --method exact --layout diff -o "$tmp/d"
# The texel layout: a method against itself agrees everywhere; an
# approximation does not.
expect 0 "texel error max 0.00, mean 0.000" -- "$persp" view corridor --play "$path" --frames 1 \
    --size 64x48 --method exact --layout texel -o "$tmp/t1"
expect 0 "texel error max [1-9]" -- "$persp" view corridor --play "$path" --frames 1 \
    --size 64x48 --method affine --layout texel -o "$tmp/t2"
# Without --frames: one frame per key.
"$persp" view cube --play "$path" --size 64x48 -q -o "$tmp/e" && ok || bad "play per key"
n=$(ls "$tmp/e" | wc -l)
if [ "$n" -eq 3 ]; then ok; else bad "expected 3 frames (one per key), got $n"; fi

# A key at the scene's own camera (corridor: the origin looking down -z,
# 60 degrees, near 0.1f, far 100) renders what `persp render` does.
printf '{"keys": [{"t": 0, "eye": [0, 0, 0], "yaw": 0, "pitch": 0, "fovy": 60, "near": 0.10000000149011612, "far": 100}]}' >"$tmp/home.json"
"$persp" view corridor --play "$tmp/home.json" --layout single --method affine --size 120x90 -q \
    -o "$tmp/home" && ok || bad "play home.json"
"$persp" render corridor --method affine --size 120x90 -q -o "$tmp/home.png" && ok || bad "render"
if cmp -s "$tmp/home/frame_0000.png" "$tmp/home.png"; then ok; else bad "the scene's camera as a key differs from persp render"; fi

# --mip-levels: the left side shows flat level colours (level 0 white).
"$persp" view corridor --play "$path" --frames 1 --size 64x48 --layout single --mip-levels \
    --filter nearest-mip-nearest -q -o "$tmp/mip" && ok || bad "play --mip-levels"
"$persp" view corridor --play "$path" --frames 1 --size 64x48 --layout single \
    --filter nearest-mip-nearest -q -o "$tmp/nomip" && ok || bad "play without --mip-levels"
if cmp -s "$tmp/mip/frame_0000.png" "$tmp/nomip/frame_0000.png"; then bad "--mip-levels changed nothing"; else ok; fi

# Bad input.
printf '{"keys": []}' >"$tmp/empty.json"
expect 1 "non-empty array" -- "$persp" view --play "$tmp/empty.json" -o "$tmp/x"
printf '{"keys": [{"t": 0, "eye": [0, 0], "yaw": 0, "pitch": 0}]}' >"$tmp/short.json"
expect 1 "key 0" -- "$persp" view --play "$tmp/short.json" -o "$tmp/x"
printf '{"keys": [' >"$tmp/broken.json"
expect 1 "broken.json:" -- "$persp" view --play "$tmp/broken.json" -o "$tmp/x"
expect 1 "no-such-path" -- "$persp" view --play "$tmp/no-such-path.json" -o "$tmp/x"
expect 2 "bad --layout" -- "$persp" view --play "$path" --layout sideways
# Keys and versions the format does not have are refused with file, line
# and key, as scene files refuse theirs.
printf '{"version": 1,\n "keys": [{"t": 0, "eye": [0, 0, 0], "yaw": 0, "pitch": 0},\n          {"t": 1, "eye": [0, 0, 0], "yaw": 0, "pitch": 0,\n           "roll": 5}]}\n' >"$tmp/roll.json"
expect 1 "roll.json:4: keys\[1\].roll: unknown key \(expected one of: t, eye, yaw, pitch, fovy, near, far\)" -- \
    "$persp" view --play "$tmp/roll.json" -o "$tmp/x"
printf '{"version": 1,\n "speed": 2,\n "keys": [{"t": 0, "eye": [0, 0, 0], "yaw": 0, "pitch": 0}]}\n' >"$tmp/speed.json"
expect 1 "speed.json:2: speed: unknown key \(expected one of: version, keys\)" -- \
    "$persp" view --play "$tmp/speed.json" -o "$tmp/x"
printf '{"version": 2,\n "keys": [{"t": 0, "eye": [0, 0, 0], "yaw": 0, "pitch": 0}]}\n' >"$tmp/v2.json"
expect 1 "v2.json:1: version: unsupported camera path version \(expected 1\)" -- \
    "$persp" view --play "$tmp/v2.json" -o "$tmp/x"
mkdir -p "$tmp/pathdir"
expect 1 "pathdir: cannot read: Is a directory" -- "$persp" view --play "$tmp/pathdir" -o "$tmp/x"
# Without --method the split compares something: affine against exact on
# a scene that names no method (exact against exact showed nothing).
expect 0 "played .* \(affine \| exact\).*" -- "$persp" view corridor --play "$path" --frames 1 --size 64x48 \
    -o "$tmp/dflt"
expect 0 "error max [1-9]" -- "$persp" view corridor --play "$path" --frames 1 --size 64x48 --layout diff \
    -o "$tmp/dflt2"
# A model whose material file is missing plays without it, and says so.
printf 'mtllib missing.mtl\nv 0 0 -2\nv 1 0 -2\nv 0 1 -2\nusemtl m\nf 1 2 3\n' >"$tmp/nomtl.obj"
expect 0 "warning: .*missing.mtl" -- "$persp" view "$tmp/nomtl.obj" --play "$path" --frames 1 --size 32x24 \
    -q -o "$tmp/nomtl"
expect 2 "subdiv" -- "$persp" view --play "$path" --compare subdiv:3
expect 0 "usage: persp view" -- "$persp" view --help

echo "view play: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

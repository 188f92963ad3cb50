#!/usr/bin/env bash
# `persp render SCENE.json` end to end: both example scenes under every
# shading mode (distinct images, PNG written), and malformed scene, OBJ and
# MTL files rejected with exit 1, a message naming file, line and column, and
# no image written.
set -u
persp="$1"
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
. "$(dirname "$0")/lib.sh"

modes="none flat gouraud gouraud-pc phong phong-pc phong-pc:quad phong-pc:pwquad phong-pc:cubic phong-slerp phong-slerp-screen"
for scene in room spheres; do
    for m in $modes; do
        out="$tmp/${scene}_${m/:/_}.png"
        if "$persp" render "$src/scenes/$scene.json" --shading "$m" --size 160x120 -q -o "$out" 2>"$tmp/err" \
            && [ -s "$out" ]; then ok; else bad "render $scene --shading $m: $(cat "$tmp/err")"; fi
    done
    # The modes differ: flat, gouraud and phong-pc give three different images.
    a=$(cksum <"$tmp/${scene}_flat.png") b=$(cksum <"$tmp/${scene}_gouraud.png") c=$(cksum <"$tmp/${scene}_phong-pc.png")
    [ "$a" != "$b" ] && [ "$b" != "$c" ] && [ "$a" != "$c" ] && ok || bad "$scene: shading modes give identical images"
done

# reject CODE PATTERN FILE...: render the first file, expect the exit code,
# the message and no output image.
reject() {
    local code="$1" pattern="$2" scene="$3" out rc
    out=$("$persp" render "$scene" -o "$tmp/never.png" 2>&1); rc=$?
    if [ "$rc" -ne "$code" ]; then bad "$scene exited $rc, expected $code: $out"; return; fi
    if ! grep -qE -- "$pattern" <<<"$out"; then bad "$scene: output lacks /$pattern/: $out"; return; fi
    if [ -e "$tmp/never.png" ]; then bad "$scene: an image was written"; rm -f "$tmp/never.png"; return; fi
    ok
}
mkdir -p "$tmp/s"
printf '{\n  "objects": [{"mesh": "cube"}],\n  "camera": {"fovy": 50}\n}\n' >"$tmp/s/key.json"
reject 1 "key.json:3:14: camera.fovy: unknown key" "$tmp/s/key.json"
printf '{"objects": [{"mesh": "cube"}], "lights": [{"type": "point", "position": [0, 1]}]}' >"$tmp/s/vec.json"
reject 1 "vec.json:1:.*lights\[0\].position: expected an array of 3 numbers" "$tmp/s/vec.json"
printf '{"objects": [{"mesh": "m.obj"}]}' >"$tmp/s/obj.json"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n' >"$tmp/s/m.obj"
reject 1 "m.obj:4: vertex index 4 out of range" "$tmp/s/obj.json"
printf 'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$tmp/s/m.obj"
printf 'newmtl a\nKd 1 x 1\n' >"$tmp/s/m.mtl"
reject 1 "m.obj \\(via m.mtl:2\\): malformed number after 'Kd'" "$tmp/s/obj.json"
printf '{"objects": [{"mesh": "cube"}]' >"$tmp/s/trunc.json"
reject 1 "trunc.json:1:.*invalid JSON" "$tmp/s/trunc.json"
expect_out=$("$persp" render "$src/scenes/room.json" --shading glossy -o "$tmp/never.png" 2>&1); rc=$?
[ "$rc" -eq 2 ] && grep -q "glossy" <<<"$expect_out" && [ ! -e "$tmp/never.png" ] && ok || bad "--shading glossy: rc $rc: $expect_out"

echo "render scenes: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

#!/usr/bin/env bash
# `persp render MODEL` and `persp bench MODEL` for model files without a
# scene file: an OBJ with its MTL and texture, a glTF with an embedded
# texture, PLY and STL; a missing texture is a warning (the model is drawn
# untextured); a model with nothing to draw and a file that is no model fail
# with exit 1 and one line naming the file, writing no image.
set -u
persp="$1"
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
. "$(dirname "$0")/lib.sh"

m="$tmp/m"
mkdir -p "$m/tex"
cp "$src/tests/data/images/ramp8.png" "$m/tex/wall.png"
printf 'newmtl wall paper\nKd 1 1 1\nKm 0.5\nmap_Kd tex\\wall.png\n' >"$m/box.mtl"
printf 'mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n' >"$m/box.obj"
printf 'vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl wall paper\n' >>"$m/box.obj"
printf 'f 1/1 4/4 3/3 2/2\nf 5/1 6/2 7/3 8/4\nf 1/1 2/2 6/3 5/4\nf 4/1 8/2 7/3 3/4\nf 1/1 5/2 8/3 4/4\nf 2/1 3/2 7/3 6/4\n' >>"$m/box.obj"

# renders, textured, without warnings
out=$("$persp" render "$m/box.obj" --size 64x48 -o "$tmp/box.png" 2>&1); rc=$?
if [ "$rc" -eq 0 ] && [ -s "$tmp/box.png" ] && grep -q "filter bilinear" <<<"$out" && ! grep -q warning <<<"$out"
then ok; else bad "render box.obj: rc $rc: $out"; fi
# render options apply to models as to scenes
expect 0 "shading flat" -- "$persp" render "$m/box.obj" --size 64x48 --shading flat --filter trilinear -o "$tmp/flat.png"
[ "$(cksum <"$tmp/box.png")" != "$(cksum <"$tmp/flat.png")" ] && ok || bad "--shading flat changed nothing"
expect 0 "rendered .*embedded.gltf: 64x48, .*filter bilinear" -- \
    "$persp" render "$src/tests/data/models/embedded.gltf" --size 64x48 -o "$tmp/g.png"
# persp found on PATH (argv[0] without a folder), run from another folder,
# still finds its importer
bindir=$(cd "$(dirname "$persp")" && pwd)
expect 0 "rendered .*embedded.gltf" -- env -C "$tmp" PATH="$bindir:$PATH" "$(basename "$persp")" render \
    "$src/tests/data/models/embedded.gltf" --size 32x24 -o "$tmp/path.png"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$m/t.ply"
expect 0 "1 triangles in" -- "$persp" render "$m/t.ply" --size 32x24 -o "$tmp/p.png"
printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' >"$m/t.stl"
expect 0 "1 triangles in" -- "$persp" render "$m/t.stl" --size 32x24 -o "$tmp/s.png"
# --up z turns a +z-up model (STL, 3DS) to stand on +y: another image; a
# bad axis is a usage error
printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 2\nendloop\nendfacet\nendsolid t\n' >"$m/up.stl"
expect 0 "1 triangles in" -- "$persp" render "$m/up.stl" --size 32x24 -o "$tmp/up_y.png"
expect 0 "1 triangles in" -- "$persp" render "$m/up.stl" --size 32x24 --up z -o "$tmp/up_z.png"
cmp -s "$tmp/up_y.png" "$tmp/up_z.png" && bad "--up z changed nothing" || ok
expect 2 "bad --up 'w'" -- "$persp" render "$m/up.stl" --up w -o "$tmp/up_w.png"
# bench takes models too
expect 0 "^bench .*box.obj 32x24" -- "$persp" bench "$m/box.obj" --size 32x24 --frames 1 --reps 1

# a missing texture: one warning naming model and texture, drawn untextured
rm "$m/tex/wall.png"
out=$("$persp" render "$m/box.obj" --size 64x48 -o "$tmp/untex.png" 2>&1); rc=$?
if [ "$rc" -eq 0 ] && [ -s "$tmp/untex.png" ] && [ "$(grep -c 'persp: warning: .*box.obj (via box.mtl:4): .*tex/wall.png' <<<"$out")" -eq 1 ] \
    && grep -q "untextured" <<<"$out"
then ok; else bad "missing texture: rc $rc: $out"; fi

# --texture on a scene with nothing textured: drawn, and a warning that it
# changed nothing (it replaces textures; it does not add one)
out=$("$persp" render "$m/t.stl" --size 32x24 --texture "$src/scenes/bench/checker.png" -o "$tmp/t2.png" 2>&1); rc=$?
if [ "$rc" -eq 0 ] && grep -q "persp: warning: --texture .*checker.png: the scene has no textured object" <<<"$out"
then ok; else bad "--texture without textured objects: rc $rc: $out"; fi
out=$("$persp" render "$src/tests/data/models/embedded.gltf" --size 32x24 --texture "$src/scenes/bench/checker.png" -o "$tmp/t3.png" 2>&1)
grep -q "no textured object" <<<"$out" && bad "--texture on a textured model warned: $out" || ok

# reject PATTERN FILE: exit 1, one line of error naming the file, no image
reject() {
    local pattern="$1" model="$2" out rc
    out=$("$persp" render "$model" -o "$tmp/never.png" 2>&1); rc=$?
    if [ "$rc" -ne 1 ]; then bad "$model exited $rc, expected 1: $out"; return; fi
    if [ "$(wc -l <<<"$out")" -ne 1 ]; then bad "$model: more than one line: $out"; return; fi
    if ! grep -qE -- "$pattern" <<<"$out"; then bad "$model: output lacks /$pattern/: $out"; return; fi
    if [ -e "$tmp/never.png" ]; then bad "$model: an image was written"; rm -f "$tmp/never.png"; return; fi
    ok
}
printf 'v 0 0 0\nv 1 0 0\nl 1 2\n' >"$m/lines.obj"
reject "^persp: .*lines.obj: " "$m/lines.obj"
# (not a malformed STL: Assimp 5.2 leaks in that error path, which fails
# sanitised builds)
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n2\n3\n' >"$m/bad.ply"
reject "^persp: .*bad.ply: cannot import the model: " "$m/bad.ply"
printf 'glTF\002\000\000\000\377\377\000\000 not a binary glTF' >"$m/noise.glb"
reject "^persp: .*noise.glb: truncated GLB: the header declares 65535 bytes" "$m/noise.glb"

# A texture the file projects (LightWave's spherical mapping, no texture
# coordinates in the file) is drawn as the picture, not as one texel's
# colour: checked on Debian's assimp-testmodels when they are installed.
lwo=/usr/share/assimp/models/LWO/LWO2/MappingModes/earth_spherical_y.lwo
if [ -r "$lwo" ]; then
    expect 0 "" -- "$persp" render "$lwo" --size 64x48 --shading none --any-folder --formats all -o "$tmp/earth.png"
    colours=$(PYTHONPATH="$(dirname "$0")" python3 -c \
        'import sys; from png_rows import png; print(len({p for r in png(sys.argv[1])[2] for p in r}))' \
        "$tmp/earth.png")
    [ "${colours:-0}" -gt 100 ] && ok || bad "projected texture: $colours colours in earth.png"
fi
# Mirrored nodes (a negative scale in the file) keep their front faces with
# culling on: a scene of closed boxes, two of them mirrored, looks the same
# culled as not (glTF 2.0's winding rule, docs/SCENES.md).
fbx=/usr/share/assimp/models/FBX/cubes_with_mirroring_and_pivot.fbx
if [ -r "$fbx" ]; then
    for c in on off; do
        expect 0 "" -- "$persp" render "$fbx" --size 96x72 --shading gouraud-pc --cull "$c" --any-folder \
            -o "$tmp/mirror-$c.png"
    done
    cmp -s "$tmp/mirror-on.png" "$tmp/mirror-off.png" && ok || bad "mirrored FBX nodes: culling changed the image"
fi
# Vertex colours tint lit shading as they do unlit (ambient and diffuse
# times the colour, glColorMaterial's rule): a red-vertex quad lit white is
# red in every lit mode; the same quad with white vertices is grey.
quad='v -1 -1 0 R\nv 1 -1 0 R\nv 1 1 0 R\nv -1 1 0 R\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n'
printf "${quad//R/1 0 0}" >"$m/red.obj"
printf "${quad//R/1 1 1}" >"$m/white.obj"
for shading in phong phong-pc gouraud gouraud-pc flat phong-slerp; do
    for c in red white; do
        "$persp" render "$m/$c.obj" --size 32x24 --shading "$shading" -o "$tmp/$c-$shading.png" -q
    done
    verdict=$(PYTHONPATH="$(dirname "$0")" python3 -c '
import sys
from png_rows import png
def centre(path):
    return png(path)[2][12][16]
r, w = centre(sys.argv[1]), centre(sys.argv[2])
print("ok" if r[0] > 40 and r[1] <= 8 and r[2] <= 8 and w[0] == w[1] == w[2] and w[0] > 40
      else "red %s white %s" % (r, w))' "$tmp/red-$shading.png" "$tmp/white-$shading.png")
    [ "$verdict" = ok ] && ok || bad "vertex colours under $shading: $verdict"
done
echo "render models: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

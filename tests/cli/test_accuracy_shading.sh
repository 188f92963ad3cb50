#!/usr/bin/env bash
# CLI behaviour of `persp accuracy --shading`: the four report sections for
# every shading mode, the SVG figure (well-formed XML, three panels), a scene
# file for the lit-scene case, and bad usage or a bad scene exiting non-zero
# with a message naming the problem and leaving no SVG behind.
set -u
persp="$1"
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
. "$(dirname "$0")/lib.sh"

expect 0 "usage: persp accuracy --shading" -- "$persp" accuracy --shading --help
expect 0 "accuracy --shading" -- "$persp" accuracy --help
expect 2 "unknown option '--bogus'" -- "$persp" accuracy --shading --bogus
expect 2 "bad --triangles" -- "$persp" accuracy --shading --triangles 0
expect 2 "bad --size" -- "$persp" accuracy --shading --size 3
expect 2 "needs a value" -- "$persp" accuracy --shading --svg
expect 2 "unexpected argument 'x'" -- "$persp" accuracy --shading x
expect 1 "nope.json" -- "$persp" accuracy --shading --triangles 1 --scene "$tmp/nope.json" --svg "$tmp/no.svg"
[ ! -e "$tmp/no.svg" ] || bad "an SVG was written although the run failed"
# The scene's load settings reach the model import: a format outside the
# default ones is refused, and read (here: to its memory limit) with
# --formats all.
printf 'xof 0303txt 0032\nMesh m {\n1000000000;\n0.0;0.0;0.0;;\n}\n' >"$tmp/big.x"
expect 1 "big.x: 'x' models are not read by default" -- "$persp" accuracy --shading --triangles 1 --scene "$tmp/big.x"
# Only the isolated import holds Assimp to the budget; a build that imports
# in process (the emulated one) sees Assimp's own verdict on the file.
if [ "${PERSP_TEST_IMPORT_IN_PROCESS:-0}" = 1 ]; then
    expect 1 "big.x: cannot import the model" -- "$persp" accuracy --shading --triangles 1 --scene "$tmp/big.x" --formats all --max-memory 64M
else
    expect 1 "big.x: importing the model needs more than" -- "$persp" accuracy --shading --triangles 1 --scene "$tmp/big.x" --formats all --max-memory 64M
fi
expect 1 "--svg '.*missing/dir/f.svg': folder '.*missing/dir' does not exist" -- "$persp" accuracy --shading --triangles 1 --size 64x48 --svg "$tmp/missing/dir/f.svg"
[ -z "$(ls "$tmp/missing" 2>/dev/null)" ] || bad "a temporary SVG was left behind"

out="$tmp/report.txt"
if "$persp" accuracy --shading --triangles 2 --size 160x120 --svg "$tmp/fig.svg" >"$out" 2>"$tmp/err"; then
    ok
    for section in "1. Random lit triangles" "2. Lit scene" "3. t_w = " "4. Delta I"; do
        grep -qF "$section" "$out" && ok || bad "report lacks section '$section'"
    done
    # Every mode appears once per depth-ratio group (7) and once for the scene.
    for m in flat gouraud gouraud-pc phong phong-pc phong-pc:quad phong-pc:pwquad phong-pc:cubic \
             phong-slerp phong-slerp-screen; do
        n=$(grep -cE "^ *([0-9.]+ +)?$m +[0-9]" "$out")
        [ "$n" -eq 8 ] && ok || bad "mode $m appears $n times, expected 8"
    done
    # The extremum of Delta for z2/z1 = 2 is (sqrt 2 - 1)/(sqrt 2 + 1) = 0.1716.
    grep -qE "^ +2\.00 .* 0\.1716 0\.5858 +0\.1716" "$out" && ok || bad "Delta table row for z2/z1 = 2 is wrong"
    if python3 - "$tmp/fig.svg" <<'PY'
import sys, xml.dom.minidom
d = xml.dom.minidom.parse(sys.argv[1])
assert d.documentElement.tagName == "svg"
assert len(d.getElementsByTagName("polyline")) == 8 + 2 + 3
PY
    then ok; else bad "SVG is not well-formed or lacks its 13 curves"; fi
else
    bad "accuracy --shading failed: $(cat "$tmp/err")"
fi

# A scene file for the lit-scene case; its size is the default.
"$persp" accuracy --shading --triangles 1 --scene "$src/scenes/spheres.json" --size 200x150 >"$tmp/s.txt" 2>"$tmp/err" \
    && grep -qF "scenes/spheres.json at 200x150" "$tmp/s.txt" && ok || bad "scene run failed: $(cat "$tmp/err")"

# A model whose material file is missing: the scene is measured without it,
# and the library's warning reaches the user.
printf 'mtllib missing.mtl\nv 0 0 -2\nv 1 0 -2\nv 0 1 -2\nusemtl m\nf 1 2 3\n' >"$tmp/nomtl.obj"
expect 0 "warning: .*missing.mtl" -- "$persp" accuracy --shading --triangles 1 --scene "$tmp/nomtl.obj" --size 32x24
# The report and the figures never go over the scene they measure.
cp "$tmp/nomtl.obj" "$tmp/keep.obj"
expect 2 "-o '$tmp/nomtl.obj' is the input file" -- "$persp" accuracy --shading --scene "$tmp/nomtl.obj" -o "$tmp/nomtl.obj"
expect 2 "--svg '$tmp/nomtl.obj' is the input file" -- "$persp" accuracy --shading --scene "$tmp/nomtl.obj" \
    --svg "$tmp/nomtl.obj"
if cmp -s "$tmp/nomtl.obj" "$tmp/keep.obj"; then ok; else bad "accuracy --shading wrote over its scene"; fi
# --shading chooses the command wherever it stands among the options.
"$persp" accuracy --seed 3 --triangles 1 --shading --size 32x24 >"$tmp/late.txt" 2>"$tmp/err" && ok ||
    bad "--shading after other options: $(cat "$tmp/err")"
"$persp" accuracy --shading --seed 3 --triangles 1 --size 32x24 >"$tmp/early.txt" 2>&1
if cmp -s "$tmp/late.txt" "$tmp/early.txt"; then ok; else bad "--shading's place changed the report"; fi
expect 2 "--shading takes no value" -- "$persp" accuracy --shading=phong

echo "accuracy --shading: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

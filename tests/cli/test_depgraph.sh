#!/usr/bin/env bash
# The module graph of src/ (scripts/depgraph.py, docs/DESIGN.md "Layers"):
# no cycle and nothing depending on analysis, from the #include lines and,
# where nm is at hand, from the symbols the built objects reference. Then
# the same check on copies of src/ with one dependency added, which it must
# refuse. (The persp binary in $1 is not used.)
set -u
. "$(dirname "$0")/lib.sh"

graph=(python3 "$PERSP_SOURCE_DIR/scripts/depgraph.py")
objects=()
command -v nm >/dev/null && objects=(--objects "$PERSP_BINARY_DIR")
expect 0 "^core +\(layer 0\) -> -$" -- "${graph[@]}" "${objects[@]}"
expect 0 "^analysis .* render" -- "${graph[@]}" "${objects[@]}"
expect 0 '^  "render" -> "raster";$' -- "${graph[@]}" --dot
# The file formats: codecs on text and output files alone, model import on
# the codecs, scene files on model import (docs/DESIGN.md, "Layers").
expect 0 "^image +\(layer [0-9]+\) -> core io$" -- "${graph[@]}" "${objects[@]}"
expect 0 "^model +\(layer [0-9]+\) -> .*image" -- "${graph[@]}" "${objects[@]}"
expect 0 "^scene +\(layer [0-9]+\) -> .*model" -- "${graph[@]}" "${objects[@]}"

# A checkout and build under a folder named src (~/src/persp): the objects
# are still found (only the src/ inside the build folder counts).
if command -v nm >/dev/null; then
    mkdir -p "$tmp/src/persp"
    cp -r "$PERSP_SOURCE_DIR/src" "$tmp/src/persp/src"
    ln -s "$PERSP_BINARY_DIR" "$tmp/src/build"
    expect 0 "^core +\(layer 0\) -> -$" -- "${graph[@]}" --src "$tmp/src/persp/src" --objects "$tmp/src/build"
fi
# core including a header of the renderer closes a cycle.
cp -r "$PERSP_SOURCE_DIR/src" "$tmp/cycle"
printf '#include "render/render.h"\n' >>"$tmp/cycle/core/pool.h"
expect 1 "^cycle: core -> .*render" -- "${graph[@]}" --src "$tmp/cycle"
expect 1 'core/pool.h includes render/' -- "${graph[@]}" --src "$tmp/cycle"
# A new module using analysis, in no cycle, is refused all the same.
cp -r "$PERSP_SOURCE_DIR/src" "$tmp/top"
mkdir "$tmp/top/extra"
printf '#include "analysis/analysis.h"\n' >"$tmp/top/extra/extra.c"
expect 1 "^extra depends on top module analysis" -- "${graph[@]}" --src "$tmp/top"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

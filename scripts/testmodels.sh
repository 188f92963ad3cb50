#!/usr/bin/env bash
# Renders every model of Debian's assimp-testmodels in a format persp reads
# by default (docs/SCENES.md, "Tested on") with `persp render FILE`, one
# small image each, and counts per format what rendered, what was refused
# (exit 1 with a message) and what ended otherwise (a crash, a hang past the
# time limit, any other status). The images are left in OUT for looking at;
# OUT/summary.tsv holds format, file, outcome, warnings and the first line
# of the messages.
#
#   scripts/testmodels.sh [--persp PATH] [--out DIR] [--size WxH] [--models DIR]
set -eu

persp=build/persp
out=out/testmodels
size=160x120
models=/usr/share/assimp/models
while [ $# -gt 0 ]; do
    case "$1" in
    --persp) persp=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --models) models=$2; shift 2 ;;
    *) echo "testmodels.sh: unknown option '$1'" >&2; exit 2 ;;
    esac
done
[ -x "$persp" ] || { echo "testmodels.sh: no persp at '$persp' (--persp PATH)" >&2; exit 2; }
[ -d "$models" ] || { echo "testmodels.sh: no models at '$models' (apt-get install assimp-testmodels)" >&2; exit 2; }
mkdir -p "$out"
summary="$out/summary.tsv"
printf 'format\tfile\toutcome\twarnings\tmessage\n' >"$summary"

# The format a file is counted under: glTF 1.0 lives in models/glTF/.
format_of() {
    local f=$1 ext=${1##*.}
    ext=$(printf '%s' "$ext" | tr 'A-Z' 'a-z')
    case "$ext" in
    obj) echo OBJ ;;
    gltf | glb) case "$f" in */models/glTF/*) echo "glTF 1.0" ;; *) echo "glTF 2.0 .$ext" ;; esac ;;
    ply) echo PLY ;;
    stl) echo STL ;;
    fbx) echo FBX ;;
    dae) echo COLLADA ;;
    3ds) echo 3DS ;;
    off) echo OFF ;;
    *) echo "" ;;
    esac
}

n=0
while IFS= read -r -d '' f; do
    fmt=$(format_of "$f")
    [ -n "$fmt" ] || continue
    n=$((n + 1))
    rel=${f#"$models"/}
    png="$out/$(printf '%s' "$rel" | tr '/ ' '__').png"
    set +e
    msg=$(timeout 120 "$persp" render "$f" --size "$size" -o "$png" 2>&1 >/dev/null)
    rc=$?
    set -e
    case $rc in
    0) outcome=rendered ;;
    1) outcome=refused ;;
    124) outcome=timeout ;;
    *) outcome="exit $rc" ;;
    esac
    warnings=$(printf '%s\n' "$msg" | grep -c 'warning' || true)
    first=$(printf '%s\n' "$msg" | grep -v '^$' | head -n 1 | tr '\t' ' ')
    printf '%s\t%s\t%s\t%s\t%s\n' "$fmt" "$rel" "$outcome" "$warnings" "$first" >>"$summary"
done < <(find "$models" -type f -print0 | sort -z)

echo "$n files; images and $summary in $out"
printf '%-16s %6s %9s %8s %6s\n' format tried rendered refused other
awk -F'\t' 'NR > 1 {
        tried[$1]++
        if ($3 == "rendered") ok[$1]++; else if ($3 == "refused") no[$1]++; else other[$1]++
    }
    END { for (f in tried) printf "%-16s %6d %9d %8d %6d\n", f, tried[f], ok[f], no[f], other[f] }' "$summary" | sort

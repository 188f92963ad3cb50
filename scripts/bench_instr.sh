#!/usr/bin/env bash
# Instructions per pixel of persp on the workloads of scripts/bench.sh,
# counted by Valgrind's callgrind: a figure that a busy or shared machine
# does not move, to judge a change by beside the time ratios of `make bench`
# (docs/PERFORMANCE.md, "Instructions per pixel").
#
# Each row is run twice, `persp bench --frames 1 --reps 1` and `--frames 3
# --reps 1` (one warm-up and one calibration frame each, then the frames);
# the difference of the two totals is what two frames cost, without loading,
# set-up and exit. Divided by 2·width·height it is instructions per frame
# pixel, the unit of the fill rate. One thread; valgrind runs no AVX-512,
# so the variants are those below it.
#
#   scripts/bench_instr.sh [PERSP] [OUTFILE]   (defaults: build/persp, out/bench-instr.md)
#   SIZE=1024x768 SIMDS="baseline avx2" ROWS="torus-2k:none corridor:trilinear" scripts/bench_instr.sh
set -eu
persp="${1:-build/persp}"
outfile="${2:-out/bench-instr.md}"
root="$(cd "$(dirname "$0")/.." && pwd)"
size="${SIZE:-1024x768}"
simds="${SIMDS:-baseline avx2}"
command -v valgrind >/dev/null || { echo "bench_instr.sh: valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
default_rows=""
for w in torus-2k torus-20k torus-200k torus-2m soup-200k; do
    for s in none gouraud-pc phong-pc; do default_rows+=" $w:$s"; done
done
for f in nearest bilinear trilinear; do default_rows+=" corridor:$f"; done
rows="${ROWS:-$default_rows}"
w=${size%x*} h=${size#*x}
mkdir -p "$(dirname "$outfile")"

count() { # frames, then the bench arguments: prints the instructions callgrind counted
    local frames="$1"; shift
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$persp" bench "$@" --size "$size" \
        --threads 1 --reps 1 --frames "$frames" 2>&1 >/dev/null |
        sed -n 's/^==[0-9]*== Collected : \([0-9]*\)$/\1/p'
}

{
    cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
    commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo "not a git checkout")
    echo "Instructions per frame pixel (callgrind, 1 thread, $size; CPU $cpu; persp commit $commit)"
    echo
    printf '| workload | shading / filter |'; for s in $simds; do printf ' %s |' "$s"; done; echo
    printf '|---|---|'; for _ in $simds; do printf -- '---:|'; done; echo
} >"$outfile"
for row in $rows; do
    name=${row%%:*} what=${row#*:}
    if [ "$name" = corridor ]; then args=(corridor --filter "$what"); else args=("$root/scenes/bench/$name.json" --shading "$what"); fi
    line="| $name | $what |"
    for s in $simds; do
        a=$(count 1 "${args[@]}" --simd "$s") b=$(count 3 "${args[@]}" --simd "$s")
        if [ -z "$a" ] || [ -z "$b" ]; then line+=" error |"; continue; fi
        line+=$(python3 -c "import sys; a, b, p = map(int, sys.argv[1:]); print(f' {(b - a) / (2 * p):.1f} |')" "$a" "$b" $((w * h)))
    done
    echo "$line" >>"$outfile"
    echo "bench_instr: $line" >&2
done
cat "$outfile"

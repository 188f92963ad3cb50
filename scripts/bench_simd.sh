#!/usr/bin/env bash
# The sampler variants and the thread scaling of docs/PERFORMANCE.md,
# "On an Intel Xeon: samplers with gathers, 16 threads", on whatever CPU runs it:
#   1. corridor 1024x768, one thread, nearest / bilinear / trilinear, with
#      every --simd variant this CPU runs (auto first), each against the peer
#      in the same `persp bench` run;
#   2. corridor 3840x2160 (nearest, bilinear, trilinear) at 1, 2, 4, 8, ...
#      up to all threads, the peer at one and at all threads;
#   3. the 2M-triangle torus (gouraud-pc) at 1, 4 and all threads, with the
#      peer at each;
#   4. the 2M-triangle torus at one thread, unlit, gouraud-pc and phong-pc,
#      with auto, avx2 and avx512 (the vertex stage and the lighting loops
#      follow --simd: does 512-bit arithmetic cost this CPU its clock?).
# Prints Markdown tables; the raw JSON of every run is kept in OUTDIR.
#
#   scripts/bench_simd.sh [PERSP] [OUTDIR]    (defaults: build/persp, out/bench-simd)
#   REPS=3 TIME=0.3 PEER=llvmpipe PARTS="1 2 3 4" scripts/bench_simd.sh
#   VARIANTS="auto avx512" (part 1) and THREAD_LIST="1 16" (part 2) narrow the runs.
set -u
persp="${1:-build/persp}"
outdir="${2:-out/bench-simd}"
root="$(cd "$(dirname "$0")/.." && pwd)"
reps="${REPS:-3}" run_time="${TIME:-0.3}" peer="${PEER:-llvmpipe}" parts="${PARTS:-1 2 3 4}"
all=$(nproc 2>/dev/null || echo 2)
mkdir -p "$outdir"
peer_args=(--peer "$peer")
if "$persp" bench --help | grep -q "not built with OSMesa"; then peer_args=(); fi

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
# ARM Linux names no model: its implementer and part numbers stand for it.
[ -n "$cpu" ] || cpu="$(uname -m), CPU implementer $(sed -n 's/^CPU implementer[[:space:]]*: //p' /proc/cpuinfo | head -1), part $(sed -n 's/^CPU part[[:space:]]*: //p' /proc/cpuinfo | head -1)"
echo "CPU: $cpu, $all threads; REPS=$reps TIME=$run_time"

run() { # out-name, then bench arguments
    local name="$1"
    shift
    "$persp" bench "$@" --reps "$reps" --time "$run_time" --json >"$outdir/$name.json" \
        2>"$outdir/$name.err" || echo "failed: $name ($(head -c 300 "$outdir/$name.err"))"
}

table() { # files...: scene, size, filter/shading, threads, simd, persp, peer, ratio
    python3 - "$@" <<'EOF'
import json, sys
print("| scene | size | filter / shading | threads | simd | persp Mpix/s | peer Mpix/s | ratio |")
print("|---|---|---|---:|---|---:|---:|---:|")
base = {}
for path in sys.argv[1:]:
    try:
        j = json.load(open(path))
    except (OSError, ValueError):
        continue
    name = j["scene"].rsplit("/", 1)[-1].removesuffix(".json")
    what = j["filter"] if name == "corridor" else j["shading"]
    r = j["results"][0]
    m = r.get("mpix_median")
    if m is None:
        continue
    key = (name, j["width"], what)
    base.setdefault(key, m if j["threads"] == 1 else None)
    p = j.get("peer")
    pm = f"{p['mpix_median']:.1f}" if p else "–"
    ratio = f"{m / p['mpix_median']:.2f}" if p else "–"
    up = f" ({m / base[key]:.1f}× 1 thread)" if base.get(key) and j["threads"] > 1 else ""
    simd = j.get("simd", "?")
    if j.get("simd_asked") == "auto":
        simd = f"auto: {simd}"
    print(f"| {name} | {j['width']}x{j['height']} | {what} | {j['threads']} | {simd} "
          f"| {m:.1f}{up} | {pm} | {ratio} |")
EOF
}

if [[ " $parts " == *" 1 "* ]]; then
    files=()
    for f in nearest bilinear trilinear; do
        for s in ${VARIANTS:-auto avx2 avx2-gather avx512 avx512-gather}; do
            "$persp" bench --simd "$s" --frames 1 --reps 1 >/dev/null 2>&1 || continue
            run "variant-$f-$s" corridor --filter "$f" --simd "$s" "${peer_args[@]}"
            files+=("$outdir/variant-$f-$s.json")
        done
    done
    echo
    echo "Sampler variants, corridor 1024x768, one thread:"
    table "${files[@]}"
fi

if [[ " $parts " == *" 2 "* ]]; then
    files=()
    for f in nearest bilinear trilinear; do
        list="${THREAD_LIST:-}"
        if [ -z "$list" ]; then
            t=1
            while [ "$t" -le "$all" ]; do
                list="$list $t"
                if [ "$t" -lt "$all" ] && [ $((t * 2)) -gt "$all" ]; then t=$all; else t=$((t * 2)); fi
            done
        fi
        for t in $list; do
            p=()
            if [ "$t" = 1 ] || [ "$t" = "$all" ]; then p=("${peer_args[@]}" --peer-threads "$t"); fi
            run "scale-$f-t$t" corridor --size 3840x2160 --filter "$f" --threads "$t" "${p[@]}"
            files+=("$outdir/scale-$f-t$t.json")
        done
    done
    echo
    echo "Thread scaling, corridor 3840x2160:"
    table "${files[@]}"
fi

if [[ " $parts " == *" 3 "* ]]; then
    files=()
    for t in 1 4 "$all"; do
        run "torus2m-t$t" "$root/scenes/bench/torus-2m.json" --shading gouraud-pc --threads "$t" \
            "${peer_args[@]}" --peer-threads "$t"
        files+=("$outdir/torus2m-t$t.json")
    done
    echo
    echo "Thread scaling, 2M-triangle torus, gouraud-pc, 1024x768:"
    table "${files[@]}"
fi

if [[ " $parts " == *" 4 "* ]]; then
    files=()
    for sh in none gouraud-pc phong-pc; do
        for s in auto avx2 avx512; do
            "$persp" bench --simd "$s" --frames 1 --reps 1 >/dev/null 2>&1 || continue
            run "torus2m-$sh-$s" "$root/scenes/bench/torus-2m.json" --shading "$sh" --simd "$s" \
                --threads 1 "${peer_args[@]}"
            files+=("$outdir/torus2m-$sh-$s.json")
        done
    done
    echo
    echo "Vector width, 2M-triangle torus, 1024x768, one thread:"
    table "${files[@]}"
fi

#!/usr/bin/env bash
# The workload table of docs/PERFORMANCE.md: the benchmark tori (2k, 20k,
# 200k, 2M triangles) and the 200k-triangle soup, each unlit (none),
# gouraud-pc and phong-pc, plus corridor with nearest, bilinear and
# trilinear; every row at 1 thread and at all threads, with Mesa's peer
# drawing the same scene in the same `persp bench` run (runs interleaved,
# medians) and the PSNR of its image against persp's over the covered
# pixels. Prints a Markdown table, with the range of the cross-core round
# trips `persp bench` measured around the multi-thread rows (the host's
# placement of the vCPUs moves the two-thread figures); the raw JSON of
# each run is kept in OUTDIR.
#
#   scripts/bench.sh [--quick] [PERSP] [OUTDIR]   (defaults: build/persp, out/bench)
#   SIZE=1024x768 THREADS="1 N" PEER=llvmpipe REPS=5 TIME=0.5 SIMD=auto FAR_NS=200 SORT_FIRST=auto scripts/bench.sh
#
# FAR_NS: a multi-thread run next to a cross-core round trip above this
# many ns counts as run with the vCPUs far apart; rows with such runs are
# listed under the table with their near and far runs apart.
#
# SORT_FIRST: persp's --sort-first for every multi-thread row (auto: sort
# first only for two threads whose cores hand each other data slowly,
# docs/DESIGN.md "Threads"); the per-row lines say how many frames of each
# run it drew sort first.
#
# SIMD (make bench SIMD=avx2) is persp's --simd variant for every row: avx2
# on a machine with AVX-512 stands in for a CPU without it (llvmpipe's
# vectors are 256 bits wide either way). Each row is printed to standard
# error as it is measured; the table follows at the end.
#
# --quick: 128x96, one frame per run, one run, one thread: every workload
# once, to check that the table is produced (tests/cli/test_bench_script.sh).
set -eu
quick=0
if [ "${1:-}" = "--quick" ]; then quick=1; shift; fi
persp="${1:-build/persp}"
outdir="${2:-out/bench}"
root="$(cd "$(dirname "$0")/.." && pwd)"
all_threads=$(nproc 2>/dev/null || echo 2)
if [ "$quick" = 1 ]; then
    size="${SIZE:-128x96}" threads="${THREADS:-1}" reps="${REPS:-1}" frames=(--frames 1)
else
    size="${SIZE:-1024x768}" threads="${THREADS:-1 $all_threads}" reps="${REPS:-5}" frames=()
fi
peer="${PEER:-llvmpipe}"
simd="${SIMD:-auto}"
run_time="${TIME:-0.5}"
sort_first="${SORT_FIRST:-auto}"
mkdir -p "$outdir"

peer_args=(--peer "$peer")
if "$persp" bench --help | grep -q "not built with OSMesa"; then
    echo "bench.sh: $persp has no OSMesa peer; measuring persp alone" >&2
    peer_args=()
fi

# scene|--shading or --filter value|row label
rows=()
for w in torus-2k torus-20k torus-200k torus-2m soup-200k; do
    for s in none gouraud-pc phong-pc; do rows+=("$root/scenes/bench/$w.json|--shading $s|$w"); done
done
for f in nearest bilinear trilinear; do rows+=("corridor|--filter $f|corridor"); done

files=()
for row in "${rows[@]}"; do
    IFS='|' read -r scene setting label <<<"$row"
    for t in $threads; do
        out="$outdir/$label-${setting##* }-$size-$simd-t$t.json"
        # shellcheck disable=SC2086  # $setting is an option and its value
        "$persp" bench "$scene" --size "$size" $setting --threads "$t" --reps "$reps" \
            --time "$run_time" --simd "$simd" --sort-first "$sort_first" "${frames[@]}" "${peer_args[@]}" --json >"$out"
        files+=("$out")
        python3 - "$out" "$label" "${setting##* }" <<'EOF' >&2
import json, sys
j = json.load(open(sys.argv[1]))
r, p = j["results"][0], j.get("peer")
head = f"bench: {sys.argv[2]} {sys.argv[3]}, simd {j['simd']}, {j['threads']} thread(s):"
if "error" in r:
    print(head, r["error"])
else:
    m = r["mpix_median"]
    x = j.get("xcore_round_trip_ns")
    xs = (f"; cross-core round trip before each run " + ", ".join(f"{v[1]:.0f}" for v in x.get("runs", []))
          + f", after {x['after'][1]:.0f} ns") if x else ""
    sf = r.get("sort_first_frames")
    sfs = f"; frames drawn sort first, each run of {r['frames']}: " + ", ".join(map(str, sf)) if sf else ""
    print(head, f"{m:.1f} Mpix/s" + (f", {m / p['mpix_median']:.2f}x {p['renderer']}" if p else "") + xs + sfs)
EOF
    done
done

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
# ARM Linux names no model: its implementer and part numbers stand for it.
[ -n "$cpu" ] || cpu="$(uname -m), CPU implementer $(sed -n 's/^CPU implementer[[:space:]]*: //p' /proc/cpuinfo | head -1), part $(sed -n 's/^CPU part[[:space:]]*: //p' /proc/cpuinfo | head -1)"
# A downloaded archive (or a machine without git) has no commit: the
# version stands for it.
if commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null); then
    dirty=$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null | head -1)
    built="commit $commit${dirty:+ (modified)}"
else
    built="version $("$persp" --version | sed 's/^persp //'), not a git checkout"
fi
python3 - "$cpu" "$built" "$size" "$reps" "${files[@]}" <<'EOF'
import json, os, statistics, sys
cpu, built, size, reps = sys.argv[1:5]
runs = [json.load(open(p)) for p in sys.argv[5:]]
def fmt(x):
    return f"{x:.1f}" if x >= 10 else f"{x:.2f}" if x >= 0.1 else f"{x:.3f}"
peer = next((j["peer"] for j in runs if "peer" in j), None)
print(f"CPU: {cpu}, {len({j['threads'] for j in runs})} thread count(s); persp {built}; "
      f"--simd {runs[0]['simd_asked']} (samplers {runs[0]['simd']}, lighting {runs[0].get('simd_lighting', runs[0]['simd'])}); {size}, method exact, medians of {reps} run(s) interleaved with the peer's"
      + (f"; peer {peer['renderer']}, {peer['version']}" if peer else ""))
print()
print("| workload | shading / filter | threads | persp Mpix/s | llvmpipe Mpix/s | ratio | PSNR dB | covered |")
print("|---|---|---:|---:|---:|---:|---:|---:|")
for j in runs:
    name = j["scene"].rsplit("/", 1)[-1].removesuffix(".json")
    what = j["filter"] if name == "corridor" else j["shading"]
    r = j["results"][0]
    if "error" in r:
        print(f"| {name} | {what} | {j['threads']} | error: {r['error']} | | | | |")
        continue
    p = j.get("peer")
    d = j.get("peer_image")
    pm = fmt(p['mpix_median']) if p else "–"
    ratio = f"**{r['mpix_median'] / p['mpix_median']:.2f}**" if p else "–"
    psnr = "–" if not d else ("inf" if d["psnr_db"] is None else f"{d['psnr_db']:.1f}")
    cov = f"{d['covered_pct']:.0f} %" if d else "–"
    print(f"| {name} | {what} | {j['threads']} | {fmt(r['mpix_median'])} | {pm} | {ratio} | {psnr} | {cov} |")
# The host may place the vCPUs near each other or far apart (tools/persp/xcore.c):
# the round trips measured around each multi-thread row, the most over the pairs.
xs = [v for j in runs if "xcore_round_trip_ns" in j for k in ("before", "after")
      for v in [j["xcore_round_trip_ns"][k][1]] if v is not None]
if xs:
    print()
    print(f"Cross-core round trip of a cache line around the multi-thread rows: {min(xs):.0f}-{max(xs):.0f} ns.")
# A run between two round trips of which either exceeds far_ns ran with the
# vCPUs (possibly) far apart: such rows are listed with the medians of
# their near and far runs apart; the table above keeps all runs.
far_ns = float(os.environ.get("FAR_NS", "200"))
notes = []
for j in runs:
    x, r, p = j.get("xcore_round_trip_ns"), j["results"][0], j.get("peer")
    if not x or "error" in r or len(x.get("runs", [])) != len(r["mpix_runs"]):
        continue
    edges = [v[1] for v in x["runs"]] + [x["after"][1]]
    far = [any(e is None or e > far_ns for e in edges[k:k + 2]) for k in range(len(r["mpix_runs"]))]
    if not any(far):
        continue
    def part(flag):
        v = [m for m, f in zip(r["mpix_runs"], far) if f == flag]
        if not v:
            return "none"
        med = statistics.median(v)
        return f"{fmt(med)} Mpix/s" + (f" ({med / p['mpix_median']:.2f}x)" if p else "")
    name = j["scene"].rsplit("/", 1)[-1].removesuffix(".json")
    what = j["filter"] if name == "corridor" else j["shading"]
    notes.append(f"- {name} {what}, {j['threads']} threads: {sum(far)} of {len(far)} runs next to a round trip "
                 f"over {far_ns:.0f} ns; near runs {part(False)}, far runs {part(True)}")
if notes:
    print()
    print("Rows with runs while the vCPUs were far apart (ratios to the peer's median):")
    print("\n".join(notes))
EOF

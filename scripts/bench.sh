#!/usr/bin/env bash
# The table of docs/PERFORMANCE.md: every method × filter × thread count on
# `corridor`, each row with Mesa llvmpipe measured in the same `persp bench`
# run. Prints a Markdown table; the raw JSON of each run is kept in OUTDIR.
#
#   scripts/bench.sh [PERSP] [OUTDIR]      (defaults: build/persp, out/bench)
#   SIZE=1024x768 FILTERS="nearest bilinear trilinear" THREADS="1 2" PEER=llvmpipe
#   REPS=5 TIME=0.5 scripts/bench.sh
set -eu
persp="${1:-build/persp}"
outdir="${2:-out/bench}"
size="${SIZE:-1024x768}"
filters="${FILTERS:-nearest bilinear trilinear}"
threads="${THREADS:-1 2}"
peer="${PEER:-llvmpipe}"
reps="${REPS:-5}"
run_time="${TIME:-0.5}"
mkdir -p "$outdir"

peer_args=(--peer "$peer")
if "$persp" bench --help | grep -q "not built with OSMesa"; then
    echo "bench.sh: $persp has no OSMesa peer; measuring persp alone" >&2
    peer_args=()
fi

files=()
for f in $filters; do
    for t in $threads; do
        out="$outdir/corridor-$size-${f//:/}-t$t.json"
        "$persp" bench corridor --size "$size" --method all --filter "$f" --threads "$t" \
            --reps "$reps" --time "$run_time" "${peer_args[@]}" --json >"$out"
        files+=("$out")
    done
done

python3 - "${files[@]}" <<'EOF'
import json, sys
runs = [json.load(open(p)) for p in sys.argv[1:]]
print("| filter | threads | method | Mpix/s median | min – max | vs exact | vs peer |")
print("|---|---:|---|---:|---:|---:|---:|")
for j in runs:
    for r in j["results"]:
        if "error" in r:
            print(f"| {j['filter']} | {j['threads']} | {r['method']} | error: {r['error']} | | | |")
            continue
        vp = f"{r['vs_peer']:.2f}" if "vs_peer" in r else "–"
        ve = f"{r['vs_exact']:.2f}" if "vs_exact" in r else "–"
        print(f"| {j['filter']} | {j['threads']} | {r['method']} | {r['mpix_median']:.1f} | "
              f"{r['mpix_min']:.1f} – {r['mpix_max']:.1f} | {ve} | {vp} |")
    if "peer" in j:
        p = j["peer"]
        print(f"| {j['filter']} | {j['threads']} | **{p['driver']}** (LP_NUM_THREADS={p['lp_num_threads']}) | "
              f"{p['mpix_median']:.1f} | {p['mpix_min']:.1f} – {p['mpix_max']:.1f} | | 1.00 |")
print()
for j in runs:
    line = f"- {j['filter']}, {j['threads']} thread(s): persp peak RSS {j['peak_rss_mib']:.1f} MiB " \
           f"({j['peak_rss_mib'] - j['rss_at_start_mib']:.1f} MiB above start)"
    if "peer" in j:
        line += f"; peer {j['peer']['renderer']} peak RSS {j['peer']['peak_rss_mib']:.1f} MiB"
    print(line)
EOF

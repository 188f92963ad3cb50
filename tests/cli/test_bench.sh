#!/usr/bin/env bash
# CLI behaviour of `persp bench`: a tiny run prints a parsable table and valid
# JSON, `--method all` covers the registry with exact as the unit of the
# ratios, bad options exit 2 naming the problem, and --peer either measures
# Mesa through OSMesa (and matches persp's image) or, in a build without
# OSMesa, fails clearly. The peer draws JSON scenes with every shading mode's
# GL state, and its image matches persp's over the covered pixels. No
# assertion depends on timings.
# ctest-labels: threads (persp runs with --threads > 1)
set -u
persp="$1"
src="${PERSP_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
. "$(dirname "$0")/lib.sh"

# check_json FILE PYTHON-EXPR: the file is valid JSON and the expression
# (over the parsed object `j`) holds.
check_json() {
    local file="$1" expr="$2"
    if ! python3 -m json.tool "$file" >/dev/null 2>&1; then bad "$file is not valid JSON: $(cat "$file")"; return; fi
    if python3 -c "import json,sys,math; j=json.load(open(sys.argv[1])); sys.exit(0 if ($expr) else 1)" "$file"; then ok
    else bad "$file fails: $expr: $(cat "$file")"; fi
}

tiny=(--size 32x24 --frames 1 --reps 1)

expect 0 "usage: persp bench" -- "$persp" bench --help

# Text table: header, then "exact FRAMES MEDIAN MIN MAX ..." with numbers.
out=$("$persp" bench corridor "${tiny[@]}" 2>&1); rc=$?
if [ "$rc" -ne 0 ]; then bad "tiny bench exited $rc: $out"
else
    row=$(awk '$1 == "exact"' <<<"$out")
    if awk '{ exit !($2 == 1 && $3 > 0 && $4 > 0 && $5 > 0 && $4 <= $3 && $3 <= $5 && $6 == 1.000) }' <<<"$row"
    then ok; else bad "no parsable exact row (frames 1, min <= median <= max, vs_exact 1): $out"; fi
    grep -qE "^bench corridor 32x24 filter bilinear threads 1 simd [a-z0-9-]+ reps 1$" <<<"$out" && ok || bad "header line: $out"
    grep -qE "^peak resident memory: persp [0-9.]+ MiB" <<<"$out" && ok || bad "no peak memory line: $out"
    # One thread: no cross-core figure.
    grep -q "cross-core" <<<"$out" && bad "cross-core line at one thread: $out" || ok
fi

# JSON, single method, several runs: median between min and max, one entry per run.
if "$persp" bench --size 40x30 --frames 2 --reps 3 --filter nearest --threads 2 --json >"$tmp/one.json" 2>"$tmp/err"; then
    check_json "$tmp/one.json" "j['width'] == 40 and j['height'] == 30 and j['threads'] == 2 and j['filter'] == 'nearest' \
        and len(j['results']) == 1 and j['results'][0]['method'] == 'exact' and j['results'][0]['frames'] == 2 \
        and len(j['results'][0]['mpix_runs']) == 3 \
        and min(j['results'][0]['mpix_runs']) == j['results'][0]['mpix_min'] \
        and max(j['results'][0]['mpix_runs']) == j['results'][0]['mpix_max'] \
        and j['results'][0]['mpix_min'] <= j['results'][0]['mpix_median'] <= j['results'][0]['mpix_max'] \
        and sorted(j['results'][0]['mpix_runs'])[1] == j['results'][0]['mpix_median'] \
        and j['peak_rss_mib'] > 0"
    # Two threads: the cross-core round trip, from the first processor to
    # each other one the process may run on (none with one processor).
    cpus=$(nproc)
    pairs=$(( cpus > 64 ? 63 : cpus - 1 ))
    if [ "$pairs" -gt 0 ]; then
        check_json "$tmp/one.json" "all(0 < x['before'][0] <= x['before'][1] < 1e6 and 0 < x['after'][0] <= x['after'][1] < 1e6 \
            for x in [j['xcore_round_trip_ns']]) and j['xcore_round_trip_ns']['pairs'] == $pairs"
        # One figure before each run, the first the one before the runs.
        check_json "$tmp/one.json" "len(x['runs']) == 3 and x['runs'][0] == x['before'] \
            and all(0 < a <= b < 1e6 for a, b in x['runs']) for x in [j['xcore_round_trip_ns']]"
    else
        check_json "$tmp/one.json" "'xcore_round_trip_ns' not in j"
    fi
else bad "bench --json exited non-zero: $(cat "$tmp/err")"; fi

# --sort-first: on, every frame of every run is drawn sort first, off none;
# the text names the choice and gives each run's count.
for m in on off; do
    if "$persp" bench "$src/scenes/bench/torus-2k.json" --size 200x150 --frames 3 --reps 2 --threads 2 --sort-first $m --json \
        >"$tmp/sf-$m.json" 2>"$tmp/err"; then
        want=$([ $m = on ] && echo 3 || echo 0)
        check_json "$tmp/sf-$m.json" "j['results'][0]['sort_first_frames'] == [$want, $want]"
    else bad "bench --sort-first $m exited non-zero: $(cat "$tmp/err")"; fi
done
out=$("$persp" bench "$src/scenes/bench/torus-2k.json" --size 200x150 --frames 3 --reps 2 --threads 2 --sort-first on 2>&1)
grep -qE "^frames drawn sort first \(--sort-first on\), each run of exact, of 3: 3, 3$" <<<"$out" && ok \
    || bad "no sort-first line: $out"
expect 2 "bad --sort-first 'sometimes'" -- "$persp" bench --sort-first sometimes

# --method all: one entry per method `persp methods` lists, exact's ratio 1.
# (Methods whose parameters have no default are left out.)
methods=$("$persp" methods | awk '/^[a-z]/ { sub(/:.*/, "", $1); print $1 }' | tr '\n' ' ')
if "$persp" bench --method all "${tiny[@]}" --json >"$tmp/all.json" 2>"$tmp/err"; then
    check_json "$tmp/all.json" "set(r['method'] for r in j['results']) <= set('$methods'.split()) \
        and len(set(r['method'] for r in j['results'])) == len(j['results']) \
        and {'exact', 'affine'} <= set(r['method'] for r in j['results']) \
        and all(r['vs_exact'] > 0 for r in j['results']) \
        and [r['vs_exact'] for r in j['results'] if r['method'] == 'exact'] == [1]"
else bad "bench --method all exited non-zero: $(cat "$tmp/err")"; fi

# The table grows as it is measured: exact's row (first) is out while the
# other methods are still running, not printed with all the rest once the
# last one is done. Held to proportions, not to times, so that a sanitizer
# build or a loaded machine passes as well: exact is one method of about
# thirty, so most of the run lies after its row.
t0=$(date +%s%N)
exec {rows}< <("$persp" bench --method all --size 128x96 --reps 1 --frames 30 2>/dev/null; echo "end $?")
line=""
for _ in 1 2 3 4; do IFS= read -r -t 600 line <&"$rows"; done
t_row=$(date +%s%N)
case "$line" in exact\ *) ok ;; *) bad "bench --method all: the fourth line is not exact's row: '$line'" ;; esac
while IFS= read -r -t 600 line <&"$rows" && [ "${line%% *}" != end ]; do :; done
t_end=$(date +%s%N)
[ "$line" = "end 0" ] && ok || bad "bench --method all (streamed) ended with '$line'"
after=$(((t_end - t_row) / 1000000)) total=$(((t_end - t0) / 1000000))
[ $((2 * after)) -ge "$total" ] && ok ||
    bad "bench --method all: only ${after} of ${total} ms came after exact's row (the rows printed at the end?)"
exec {rows}<&-

# --simd: each sampler variant this CPU runs is used as asked and draws the
# same image (every filter of the vectorised samplers, both wraps; the
# vertex stage and the lighting loops, which follow it too, with every lit
# mode, culling off so that Gouraud's back faces are lit in the vertex
# stage, and on); one it cannot run fails naming it; auto resolves to a
# variant.
expect 2 "bad --simd 'sse9'" -- "$persp" bench --simd sse9
ran=0
for s in baseline avx2 avx2-gather avx512 avx512-gather; do
    if "$persp" bench --simd "$s" "${tiny[@]}" --json >"$tmp/simd.json" 2>"$tmp/err"; then
        ran=$((ran + 1))
        check_json "$tmp/simd.json" "j['simd'] == '$s' and j['simd_asked'] == '$s' and j['simd_lighting'] == '$s'"
        for f in nearest bilinear nearest-mip-nearest bilinear-mip-nearest nearest-mip-linear trilinear aniso; do
            for w in repeat clamp-to-edge; do
                "$persp" render corridor --size 96x64 --filter "$f" --wrap "$w" --simd "$s" \
                    -o "$tmp/simd-$s-$f-$w.png" -q 2>>"$tmp/err" || bad "render --simd $s --filter $f failed: $(cat "$tmp/err")"
                if [ "$s" != baseline ]; then
                    cmp -s "$tmp/simd-baseline-$f-$w.png" "$tmp/simd-$s-$f-$w.png" && ok \
                        || bad "--simd $s --filter $f --wrap $w draws another image than baseline"
                fi
            done
        done
        for sh in flat gouraud gouraud-pc phong phong-pc; do
            for cull in on off; do
                "$persp" render "$src/scenes/bench/torus-2k.json" --size 96x72 --shading "$sh" --cull "$cull" \
                    --simd "$s" -o "$tmp/simd-$s-$sh-$cull.png" -q 2>>"$tmp/err" \
                    || bad "render --simd $s --shading $sh failed: $(cat "$tmp/err")"
                if [ "$s" != baseline ]; then
                    cmp -s "$tmp/simd-baseline-$sh-$cull.png" "$tmp/simd-$s-$sh-$cull.png" && ok \
                        || bad "--simd $s --shading $sh --cull $cull draws another image than baseline"
                fi
            done
        done
    else
        grep -q "cannot run --simd $s" "$tmp/err" && ok || bad "--simd $s: $(cat "$tmp/err")"
    fi
done
[ "$ran" -ge 1 ] && ok || bad "no --simd variant ran"
if "$persp" bench "${tiny[@]}" --json >"$tmp/auto.json" 2>"$tmp/err"; then
    check_json "$tmp/auto.json" "j['simd_asked'] == 'auto' and j['simd'] in ('baseline', 'avx2', 'avx2-gather', 'avx512', 'avx512-gather') \
        and j['simd_lighting'] in ('baseline', 'avx2', 'avx512')"
else bad "bench --json exited non-zero: $(cat "$tmp/err")"; fi

expect 2 "unknown option '--bogus'" -- "$persp" bench --bogus
expect 2 "bad --frames '0'" -- "$persp" bench --frames 0
expect 2 "bad --reps '1000'" -- "$persp" bench --reps 1000
expect 2 "bad --time 'x'" -- "$persp" bench --time x
expect 2 "bad --threads '0'" -- "$persp" bench --threads 0
expect 2 "bad --size '0x10'" -- "$persp" bench --size 0x10
expect 2 "unknown filter 'blurry'" -- "$persp" bench --filter blurry
expect 2 "unknown method 'nosuch'" -- "$persp" bench --method nosuch
expect 2 "bad --peer 'mesa'" -- "$persp" bench --peer mesa
expect 2 "unknown shading 'glossy'" -- "$persp" bench --shading glossy
expect 2 "needs --peer" -- "$persp" bench --peer-image "$tmp/p.png"
expect 2 "needs a value" -- "$persp" bench --frames
expect 2 "more than one scene" -- "$persp" bench corridor cube
expect 1 "missing.json" -- "$persp" bench "$tmp/missing.json" "${tiny[@]}"

if "$persp" bench --help | grep -q "not built with OSMesa"; then
    # Build without the peer: --peer fails with exit 1 and says why.
    expect 1 "not built with OSMesa" -- "$persp" bench "${tiny[@]}" --peer llvmpipe
    expect 1 "not built with OSMesa" -- "$persp" bench "${tiny[@]}" --peer softpipe --json
else
    # A lit JSON scene, per shading mode: the peer draws the same torus
    # (meshes, mip chain, camera, lights, materials), so the images agree
    # closely over the pixels either covers. Gouraud is looser: GL clamps
    # the lit vertex colour before modulating (docs/PERFORMANCE.md).
    for case in none:40 phong-pc:40 phong:40 gouraud-pc:30; do
        sh=${case%%:*} min=${case##*:}
        if "$persp" bench "$src/scenes/bench/torus-2k.json" "${tiny[@]:2}" --size 96x72 --shading "$sh" \
            --peer llvmpipe --json >"$tmp/lit-$sh.json" 2>"$tmp/err"; then
            check_json "$tmp/lit-$sh.json" "j['shading'] == '$sh' and j['results'][0]['vs_peer'] > 0 \
                and j['peer']['mpix_median'] > 0 and j['peer_image']['covered_pct'] > 30 \
                and j['peer_image']['psnr_db'] is not None and j['peer_image']['psnr_db'] > $min"
        else bad "bench torus-2k --shading $sh --peer llvmpipe exited non-zero: $(cat "$tmp/err")"; fi
    done
    # The comparison sees a real difference: flat shading lights a triangle
    # at its centroid in persp and at its provoking vertex in GL, which on
    # one large floor quad near a point light differs across the image.
    cat >"$tmp/flat.json" <<'EOS'
{"camera": {"position": [0, 1, 3], "target": [0, 0, 0]},
 "render": {"size": [96, 72], "shading": "flat"},
 "lights": [{"type": "point", "position": [0.9, 0.3, 0.9], "attenuation": [0, 0, 1]}],
 "objects": [{"mesh": "plane", "transform": {"scale": [3, 1, 3]}}]}
EOS
    if "$persp" bench "$tmp/flat.json" --frames 1 --reps 1 --peer llvmpipe --json >"$tmp/flat-out.json" 2>"$tmp/err"; then
        check_json "$tmp/flat-out.json" "j['peer_image']['covered_pct'] > 30 and j['peer_image']['psnr_db'] < 25"
    else bad "bench flat floor --peer llvmpipe exited non-zero: $(cat "$tmp/err")"; fi
    # Text form: the shading, the peer's GL pipeline and the PSNR line.
    out=$("$persp" bench "$src/scenes/bench/torus-2k.json" "${tiny[@]:2}" --size 64x48 --shading gouraud-pc \
          --peer llvmpipe 2>&1); rc=$?
    if [ "$rc" -ne 0 ]; then bad "bench torus-2k --peer llvmpipe exited $rc: $out"
    else
        grep -qE "^shading gouraud-pc$" <<<"$out" && ok || bad "no shading line: $out"
        grep -qE "^peer pipeline: fixed-function lighting, GL_SMOOTH, GL_MODULATE" <<<"$out" && ok \
            || bad "no peer pipeline line: $out"
        grep -qE "covered pixels: .*PSNR [0-9.]+ dB$" <<<"$out" && ok || bad "no PSNR line: $out"
    fi
    # The peer's frame is written and compared with persp's: with nearest
    # sampling both pick the same texel except on the one-pixel lines where
    # two walls meet at equal depth (which wall wins is a depth tie) and
    # where a pixel centre lies within rounding distance of a texel edge.
    # A wrong projection, texture orientation or wrap mode differs in far
    # more pixels.
    out=$("$persp" bench "${tiny[@]:2}" --size 128x96 --filter nearest --peer llvmpipe \
          --peer-image "$tmp/peer.png" 2>&1); rc=$?
    if [ "$rc" -ne 0 ]; then bad "bench --peer llvmpipe exited $rc: $out"
    else
        grep -qE "^peer:llvmpipe +1 +[0-9.]+ " <<<"$out" && ok || bad "no peer row: $out"
        grep -qE "^peer renderer: llvmpipe" <<<"$out" && ok || bad "no peer renderer line: $out"
        [ "$(head -c 8 "$tmp/peer.png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] && ok \
            || bad "peer image is not a PNG"
        pct=$(sed -nE 's/.*>8: ([0-9.]+)%.*/\1/p' <<<"$out")
        awk -v p="${pct:-100}" 'BEGIN { exit !(p < 2.0) }' && ok \
            || bad "persp and llvmpipe nearest images differ by >8 levels in ${pct:-?}% of pixels: $out"
    fi
    if "$persp" bench "${tiny[@]}" --peer softpipe --peer-threads 0 --json >"$tmp/peer.json" 2>"$tmp/err"; then
        check_json "$tmp/peer.json" "j['peer']['driver'] == 'softpipe' and 'softpipe' in j['peer']['renderer'] \
            and j['peer']['frames'] == 1 and j['peer']['mpix_median'] > 0 and j['peer']['lp_num_threads'] == 0 \
            and j['results'][0]['vs_peer'] > 0"
    else bad "bench --peer softpipe --json exited non-zero: $(cat "$tmp/err")"; fi
    # A filter without an OpenGL counterpart is refused before anything runs.
    expect 2 "no OpenGL counterpart" -- "$persp" bench "${tiny[@]}" --filter ewa --peer llvmpipe
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

#!/usr/bin/env bash
# Long fuzzing run of every harness of a PERSP_FUZZ=ON build, then corpus
# minimisation back into tests/fuzz/corpus/.
#   scripts/fuzz-long.sh BUILD_DIR
# Environment:
#   FUZZ_RUNS      executions per harness (default 10000000)
#   FUZZ_MAX_TIME  seconds per harness at most, 0: no limit (default 0); a
#                  harness stopped by it reports the executions it reached
#   FUZZ_JOBS      harnesses run at once (default: nproc)
#   FUZZ_ONLY      space-separated harness names (default: all)
#   FUZZ_NICE      nice level of the runs (default 19)
# Each harness runs at `nice` from a copy of its committed corpus in
# BUILD_DIR/fuzz-long/NAME/ (log.txt, artifacts/). Afterwards the corpus is
# minimised with libFuzzer's -merge=1 into a fresh folder that starts with
# the committed seeds whose names were given by hand (regression inputs are
# kept whatever they cover) and receives the other inputs only where they
# add coverage; that folder replaces tests/fuzz/corpus/NAME/. Inputs that
# contain the top folder of this checkout's absolute path are dropped from
# it: the fuzzer learns the path of tests/fuzz/files/ from the comparisons
# it watches, and a corpus must not name the machine it was made on. Prints per
# harness: executions, seconds, coverage (edges, features), corpus size and
# findings (crash, leak, timeout, out-of-memory reproducers). Exits non-zero
# if any harness had a finding.
set -u
build=${1:?usage: scripts/fuzz-long.sh BUILD_DIR}
runs=${FUZZ_RUNS:-10000000}
max_time=${FUZZ_MAX_TIME:-0}
jobs=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}
nice_level=${FUZZ_NICE:-19}
root=$(cd "$(dirname "$0")/.." && pwd)
work_root="$build/fuzz-long"
top="/$(cut -d/ -f2 <<<"$root")/"

names=()
for bin in "$build"/fuzz_*; do
    [ -x "$bin" ] || continue
    name=$(basename "$bin")
    name=${name#fuzz_}
    if [ -n "${FUZZ_ONLY:-}" ] && ! [[ " $FUZZ_ONLY " == *" $name "* ]]; then continue; fi
    names+=("$name")
done
if [ "${#names[@]}" -eq 0 ]; then
    echo "no fuzz_* binaries in $build (configure with -DPERSP_FUZZ=ON and clang)" >&2
    exit 2
fi

# Per harness: the longest input and extra flags. The model harnesses take
# inputs up to 1 MiB, since readers crash on nesting that needs some 450 KB
# of glTF or COLLADA. fuzz_model runs Assimp's readers in this process under
# the sanitizers to find their bugs, which persp contains by running them in
# persp-import (src/model/import_run.c): it keeps going past a crash in a reader
# (-fork, -ignore_crashes; each is kept in artifacts/ for a look).
# fuzz_model_isolated takes the same inputs through persp-import, where any
# finding is persp's.
harness_flags() {
    case $1 in
    model) echo "-max_len=1048576 -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1" ;;
    model_isolated) echo "-max_len=1048576" ;;
    *) echo "-max_len=65536" ;;
    esac
}

# One harness: fuzz, then record the seconds it took.
run_one() {
    local name=$1 work="$work_root/$1"
    rm -rf "$work"
    mkdir -p "$work/corpus" "$work/artifacts"
    cp "$root/tests/fuzz/corpus/$name"/* "$work/corpus/" 2>/dev/null || true
    local start end
    start=$(date +%s)
    # -close_fd_mask=2: the harnesses' own stderr (the CLI parser's
    # messages) is dropped; libFuzzer and the sanitizers keep reporting.
    # -malloc_limit_mb: one allocation over 1 GiB from a small input is a
    # finding (libFuzzer sees allocations through the sanitizer allocator,
    # so only ASan builds enforce it).
    nice -n "$nice_level" "$build/fuzz_$name" -runs="$runs" -max_total_time="$max_time" \
        -rss_limit_mb=2048 -malloc_limit_mb=1024 $(harness_flags "$name") -timeout=30 -close_fd_mask=2 -print_final_stats=1 \
        -artifact_prefix="$work/artifacts/" "$work/corpus" >"$work/log.txt" 2>&1
    echo $? >"$work/status"
    end=$(date +%s)
    echo $((end - start)) >"$work/seconds"
}
export -f run_one harness_flags
export build runs max_time nice_level root work_root

echo "== fuzzing ${names[*]}: $runs executions each (time limit ${max_time}s, 0: none), $jobs at once"
printf '%s\n' "${names[@]}" | xargs -P "$jobs" -I{} bash -c 'run_one {}'

status=0
printf '%-8s %12s %8s %8s %8s %7s %9s  %s\n' harness executions seconds edges features files bytes findings
for name in "${names[@]}"; do
    work="$work_root/$name"
    log="$work/log.txt"
    execs=$(grep -a 'stat::number_of_executed_units' "$log" | tail -n 1 | awk '{print $2}')
    covline=$(grep -aE '^#[0-9]+.*cov: ' "$log" | tail -n 1)
    edges=$(sed -n 's/.*cov: \([0-9]*\).*/\1/p' <<<"$covline")
    feats=$(sed -n 's/.*ft: \([0-9]*\).*/\1/p' <<<"$covline")
    findings=$(cd "$work/artifacts" && ls 2>/dev/null | grep -E '^(crash|leak|timeout|oom|slow-unit)-' | tr '\n' ' ')

    # Minimise: the hand-named seeds first, then what adds coverage to them.
    fresh="$work/minimised"
    rm -rf "$fresh"
    mkdir -p "$fresh"
    for f in "$root/tests/fuzz/corpus/$name"/*; do
        [ -f "$f" ] || continue
        [[ $(basename "$f") =~ ^[0-9a-f]{40}$ ]] || cp "$f" "$fresh/"
    done
    nice -n "$nice_level" "$build/fuzz_$name" -merge=1 -rss_limit_mb=2048 -max_len=65536 \
        -timeout=30 -close_fd_mask=2 "$fresh" "$work/corpus" >"$work/merge.txt" 2>&1
    grep -l -a -i -F -e "$top" -r "$fresh" | xargs -r rm -f
    if [ "$(ls "$fresh" | wc -l)" -gt 0 ]; then
        rm -rf "$root/tests/fuzz/corpus/$name"
        mkdir -p "$root/tests/fuzz/corpus/$name"
        cp "$fresh"/* "$root/tests/fuzz/corpus/$name/"
    fi
    files=$(ls "$root/tests/fuzz/corpus/$name" | wc -l)
    bytes=$(du -sb "$root/tests/fuzz/corpus/$name" | awk '{print $1}')
    printf '%-8s %12s %8s %8s %8s %7s %9s  %s\n' "$name" "${execs:-?}" "$(cat "$work/seconds")" \
        "${edges:-?}" "${feats:-?}" "$files" "$bytes" "${findings:-none}"
    if [ -n "$findings" ] || [ "$(cat "$work/status")" != 0 ]; then
        echo "!! $name: see $log and $work/artifacts/"
        grep -aE 'ERROR|invariant broken|SUMMARY' "$log" | head -n 5
        status=1
    fi
    if [ "$files" -gt 500 ] || [ "$bytes" -gt 2000000 ]; then
        echo "!! $name: corpus over 500 files or 2 MB; prune it before committing"
    fi
done
exit $status

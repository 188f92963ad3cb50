#!/usr/bin/env bash
# Runs every libFuzzer harness of a PERSP_FUZZ=ON build for a bounded time.
#   scripts/fuzz.sh BUILD_DIR [SECONDS_PER_HARNESS]     (default 60)
# Each harness starts from a copy of its corpus tests/fuzz/corpus/NAME/ (the
# committed corpus is left as it is); new inputs and crash reproducers go to
# BUILD_DIR/fuzz-work/NAME/. Exits non-zero if any harness found a crash.
set -u
build=${1:?usage: scripts/fuzz.sh BUILD_DIR [SECONDS]}
seconds=${2:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
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
status=0
found=0
for bin in "$build"/fuzz_*; do
    [ -x "$bin" ] || continue
    name=$(basename "$bin")
    corpus=${name#fuzz_}
    work="$build/fuzz-work/$corpus"
    mkdir -p "$work/corpus" "$work/artifacts"
    if [ -d "$root/tests/fuzz/corpus/$corpus" ]; then
        cp -n "$root/tests/fuzz/corpus/$corpus"/* "$work/corpus/" 2>/dev/null || true
    fi
    found=$((found + 1))
    echo "== $name: ${seconds}s, corpus $work/corpus"
    if ! "$bin" -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=1024 $(harness_flags "$corpus") -close_fd_mask=2 -print_final_stats=1 \
            -artifact_prefix="$work/artifacts/" "$work/corpus" >"$work/log.txt" 2>&1; then
        echo "!! $name failed; see $work/log.txt and $work/artifacts/"
        tail -n 30 "$work/log.txt"
        status=1
    else
        grep -E "stat::number_of_executed_units|cov:" "$work/log.txt" | tail -n 2
    fi
done
if [ "$found" -eq 0 ]; then
    echo "no fuzz_* binaries in $build (configure with -DPERSP_FUZZ=ON and clang)" >&2
    exit 2
fi
exit $status

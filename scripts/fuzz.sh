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
    if ! "$bin" -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=65536 -close_fd_mask=2 -print_final_stats=1 \
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

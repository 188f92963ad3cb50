#!/usr/bin/env bash
# The ThreadSanitizer pass (`make test TSAN=1`): runs the tests labelled
# `threads` in a PERSP_TSAN build and fails if any process reported a race.
#   scripts/tsan.sh BUILD_DIR [JOBS]
#
# Reports go to files (TSAN_OPTIONS log_path, one per process) rather than
# to stderr: a CLI test that expects a command to fail, or throws its stderr
# away, would otherwise hide a report. halt_on_error stops a process at its
# first report, so that a race also fails the test that ran it.
set -u
build="${1:?usage: scripts/tsan.sh BUILD_DIR [JOBS]}"
jobs="${2:-2}"
reports="$(cd "$build" && pwd)/tsan-reports"
rm -rf "$reports"
mkdir -p "$reports"

export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 log_path=$reports/report ${TSAN_OPTIONS:-}"
(cd "$build" && ctest --output-on-failure -j "$jobs" -L threads)
rc=$?

found=$(find "$reports" -type f | sort)
if [ -n "$found" ]; then
    for f in $found; do
        echo "---- $f"
        cat "$f"
    done
    echo "tsan.sh: ThreadSanitizer reported problems (above)" >&2
    exit 1
fi
if [ "$rc" -ne 0 ]; then
    echo "tsan.sh: tests failed" >&2
    exit "$rc"
fi
n=$(cd "$build" && ctest -N -L threads | sed -n 's/^Total Tests: //p')
echo "tsan.sh: $n tests labelled threads, no ThreadSanitizer report"

#!/usr/bin/env bash
# A sharded `persp accuracy` sweep on Slurm (docs/SWEEPS.md): slice K of N
# measures every N-th row; the merge puts the slices back into the JSON the
# unsharded run writes, and builds the page from it.
#
#   scripts/slurm_sweep.sh submit N [SLICES]   # on the login node: checks the binary,
#                                              # queues the slices and the merge
#   sbatch --array=SLICES scripts/slurm_sweep.sh N      # task K of the array: slice K of N
#   sbatch scripts/slurm_sweep.sh K/N                   # slice K of N alone
#   sbatch --dependency=afterany:JOB scripts/slurm_sweep.sh merge N
#
# SLICES is a Slurm array spec of slice numbers (default 1-N): "3", "2,5",
# "1-15:2", "9-16", "1-64%8". The array task id is the slice number, so any
# spec measures exactly the slices it names.
#
# Environment: PERSP (the binary; default: persp on the path), SWEEP_DIR
# (the folder, shared by the nodes; default: sweep), SWEEP_ARGS (the
# options of `persp accuracy`, the same for every slice), SWEEP_SBATCH
# (more sbatch options for submit, e.g. "--partition=short"), SWEEP_PAGE=0
# (merge without building the page).
#
# Files: SWEEP_DIR/shard-K-of-N.ID.json, where ID names SWEEP_ARGS, so that
# the slices of another sweep in the same folder are never merged with
# these; SWEEP_DIR/accuracy.json and SWEEP_DIR/page/ from the merge;
# SWEEP_DIR/logs/shard-K-of-N.JOB.log and SWEEP_DIR/logs/merge-of-N.JOB.log.
#SBATCH --job-name=persp-sweep
#SBATCH --cpus-per-task=1
#SBATCH --time=01:00:00
#SBATCH --output=persp-sweep-%j.log
set -eu
persp="${PERSP:-persp}"
dir="${SWEEP_DIR:-sweep}"
args="${SWEEP_ARGS:---case paper-quad,random-triangles,corridor,floor --triangles 400}"
# Inside a job $0 is Slurm's copy of this file: the messages name the one
# that was submitted.
script="${SWEEP_SCRIPT:-scripts/slurm_sweep.sh}"

die() { echo "slurm_sweep: $*" >&2; exit 1; }

is_count() { case "$1" in '' | *[!0-9]* | 0*) return 1 ;; esac; [ "$1" -le 1000000 ]; }

# The sweep's id: SWEEP_ARGS hashed (sha256), 8 hex digits.
sweep_id() { printf '%s' "$args" | sha256sum | cut -c1-8; }

shard_file() { echo "$dir/shard-$1-of-$2.$(sweep_id).json"; }

# The binary as an absolute path, and proof that it runs here.
check_binary() {
    local p
    p=$(command -v -- "$persp" 2>/dev/null) ||
        die "PERSP='$persp' is not an executable file here (set PERSP to the persp binary, e.g. \$HOME/persp/build/persp)"
    [ -f "$p" ] && [ -x "$p" ] || die "PERSP='$persp' is not an executable file"
    case "$p" in /*) ;; *) p="$(cd "$(dirname "$p")" && pwd)/$(basename "$p")" ;; esac
    "$p" --version >/dev/null 2>&1 || die "'$p' does not run on $(hostname): $("$p" --version 2>&1 | head -n 1)"
    persp="$p"
}

# Checks an array spec of slice numbers against N; prints nothing.
check_slices() {
    local spec="${1%%\%*}" n="$2" part a b
    [ -n "$spec" ] || die "no slices in '$1'"
    local IFS=,
    for part in $spec; do
        part="${part%%:*}"
        a="${part%%-*}" b="${part#*-}"
        is_count "$a" && is_count "$b" && [ "$a" -le "$b" ] && [ "$b" -le "$n" ] ||
            die "bad slices '$1': each of them must be a number from 1 to $n (the sweep's slice count)"
    done
}

# The slices of 1..N whose file is missing, as an array spec ("2,5-7").
missing_slices() {
    local n="$1" k from=0 list=""
    for ((k = 1; k <= n + 1; k++)); do
        if [ "$k" -le "$n" ] && [ ! -s "$(shard_file "$k" "$n")" ]; then
            [ "$from" -gt 0 ] || from=$k
        elif [ "$from" -gt 0 ]; then
            list="$list${list:+,}$from"
            [ "$from" -eq $((k - 1)) ] || list="$list-$((k - 1))"
            from=0
        fi
    done
    echo "$list"
}

case "${1:-}" in
submit)
    n="${2:-}"
    is_count "$n" || die "usage: $script submit N [SLICES] (N: the sweep's slice count)"
    slices="${3:-1-$n}"
    check_slices "$slices" "$n"
    check_binary
    command -v sbatch >/dev/null 2>&1 || die "sbatch not found: run this where Slurm's commands are"
    mkdir -p "$dir/logs" || die "cannot create '$dir/logs'"
    dir="$(cd "$dir" && pwd)"
    here="$(cd "$(dirname "$0")" && pwd)/$(basename "$0")"
    export PERSP="$persp" SWEEP_DIR="$dir" SWEEP_ARGS="$args" SWEEP_SCRIPT="$here"
    # shellcheck disable=SC2086
    jid=$(sbatch --parsable ${SWEEP_SBATCH:-} --array="$slices" --job-name=persp-sweep \
        --output="$dir/logs/shard-%a-of-$n.%A.log" "$here" "$n") || die "sbatch refused the slices"
    jid="${jid%%;*}"
    # afterany: the merge runs however the slices end, and says which ones
    # failed; afterok would leave it pending forever (DependencyNeverSatisfied).
    # shellcheck disable=SC2086
    mid=$(sbatch --parsable ${SWEEP_SBATCH:-} --dependency=afterany:"$jid" \
        --job-name=persp-sweep-merge --output="$dir/logs/merge-of-$n.%j.log" "$here" merge "$n") ||
        die "sbatch refused the merge (the slices are queued as job $jid)"
    mid="${mid%%;*}"
    echo "slices $slices of $n: job $jid; merge: job $mid; sweep id $(sweep_id); logs in $dir/logs"
    echo "$jid $mid" >"$dir/logs/jobs-of-$n"
    exit 0
    ;;
merge)
    n="${2:-}"
    is_count "$n" || die "usage: $script merge N (N: the sweep's slice count)"
    check_binary
    missing=$(missing_slices "$n")
    if [ -n "$missing" ]; then
        what="slice $missing"
        case "$missing" in *[,-]*) what="slices $missing" ;; esac
        echo "slurm_sweep: missing $what of $n (failed, cancelled or not run: see" \
            "$dir/logs/shard-K-of-$n.*.log). To measure just those and merge again:" >&2
        extra=""
        [ -z "${SWEEP_SBATCH:-}" ] || extra=$(printf 'SWEEP_SBATCH=%q ' "$SWEEP_SBATCH")
        printf '  %sPERSP=%q SWEEP_DIR=%q SWEEP_ARGS=%q %q submit %s %s\n' "$extra" "$persp" "$dir" \
            "$args" "$script" "$n" "$missing" >&2
        exit 1
    fi
    files=()
    for ((k = 1; k <= n; k++)); do files+=("$(shard_file "$k" "$n")"); done
    "$persp" merge -o "$dir/accuracy.json" "${files[@]}"
    [ "${SWEEP_PAGE:-1}" = 0 ] || "$persp" report --from "$dir" -o "$dir/page"
    echo "merged $n slices into $dir/accuracy.json"
    exit 0
    ;;
*/*)
    k="${1%/*}" n="${1#*/}"
    is_count "$k" && is_count "$n" && [ "$k" -le "$n" ] || die "bad slice '$1': K/N with 1 <= K <= N"
    [ -z "${SLURM_ARRAY_TASK_ID:-}" ] ||
        die "K/N names one slice: submit it without --array (or give N alone with --array=K)"
    ;;
*)
    n="${1:-}"
    is_count "$n" || die "usage: sbatch --array=SLICES $script N (or: $script submit N)"
    k="${SLURM_ARRAY_TASK_ID:-}"
    is_count "$k" || die "N alone needs an array job (sbatch --array=SLICES); one slice: $script K/N"
    [ "$k" -le "$n" ] || die "array task $k is past the sweep's $n slices (--array takes slice numbers 1..$n)"
    ;;
esac

check_binary
mkdir -p "$dir"
# shellcheck disable=SC2086
# -o puts the file in place only once it is complete: a failed or cancelled
# slice leaves no file, which is how the merge finds it.
"$persp" accuracy $args --json --shard "$k/$n" -o "$(shard_file "$k" "$n")"

#!/usr/bin/env bash
# ctest-labels: slurm (starts a one-node Slurm: munged, slurmctld, slurmd)
# scripts/slurm_sweep.sh on a real Slurm (Debian's slurm-wlm and munge,
# scripts/deps.sh --slurm): a one-node cluster on 127.0.0.1 whose key,
# configuration, state, spool and logs lie in this test's temporary folder,
# its daemons stopped by their PIDs on exit. The commands are those of
# docs/SWEEPS.md: a full sweep gives the unsharded JSON byte for byte; a
# cancelled slice makes the merge name it and the command that re-runs it
# alone; a stepped, throttled or offset array measures the slices it
# names; slices of other sweeps in the folder are left out; a binary that
# does not run is refused before anything is queued. Skipped (77) only where the daemons cannot run:
# not installed, or not root.
set -u
persp="$1"
. "$(dirname "$0")/lib.sh"
script="$(cd "$(dirname "$0")/../.." && pwd)/scripts/slurm_sweep.sh"
export PATH="$PATH:/usr/sbin:/sbin"

skip() { echo "skipped: $*"; exit 77; }
for c in munged mungekey slurmctld slurmd sbatch squeue scontrol scancel python3; do
    command -v "$c" >/dev/null 2>&1 || skip "$c not found (Debian slurm-wlm and munge: scripts/deps.sh --slurm)"
done
# slurmd starts each job as its owner, which takes root.
[ "$(id -u)" -eq 0 ] || skip "slurmd must run as root to start jobs, and this test runs as $(id -un)"

# --------------------------------------------------------------- the cluster
echo "[${SECONDS}s] the cluster"
sl="$tmp/slurm"
mkdir -p "$sl/munge" "$sl/state" "$sl/spool" "$sl/log" "$tmp/work"
chmod 700 "$sl/munge"
daemons_stop() {
    scancel --quiet --full --user=root >/dev/null 2>&1
    local p pids=""
    for f in "$sl/slurmd.pid" "$sl/slurmctld.pid" "$sl/munge/munged.pid"; do
        [ -s "$f" ] && p=$(cat "$f") && kill "$p" 2>/dev/null && pids="$pids $p"
    done
    for _ in $(seq 50); do
        local alive=0
        for p in $pids; do kill -0 "$p" 2>/dev/null && [ "$(ps -o stat= -p "$p")" != Z ] && alive=1; done
        [ "$alive" -eq 0 ] && break
        sleep 0.1
    done
    for p in $pids; do kill -0 "$p" 2>/dev/null && kill -9 "$p" 2>/dev/null; done
}
trap 'daemons_stop; rm -rf "$tmp"' EXIT

# Two free ports, held together while chosen so that they differ.
read -r port_ctld port_d < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for k in s: k.bind(("127.0.0.1", 0))
print(*[k.getsockname()[1] for k in s])')
# Installed and run as root, the daemons are expected to start: a failure
# is this test's (its configuration), reported with their logs.
fail_start() { echo "FAIL: $1 does not start: $(tail -n 5 "$2" 2>/dev/null)"; exit 1; }
host=$(hostname -s)
mungekey --create --keyfile="$sl/munge/munge.key" >/dev/null 2>&1 || fail_start mungekey /dev/null
munged --force --socket="$sl/munge/sock" --key-file="$sl/munge/munge.key" --log-file="$sl/log/munged.log" \
    --pid-file="$sl/munge/munged.pid" --seed-file="$sl/munge/seed" >/dev/null 2>&1 ||
    fail_start munged "$sl/log/munged.log"
cat >"$sl/slurm.conf" <<EOF
ClusterName=persptest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port_ctld
SlurmdPort=$port_d
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sl/munge/sock
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$sl/state
SlurmdSpoolDir=$sl/spool
SlurmctldPidFile=$sl/slurmctld.pid
SlurmdPidFile=$sl/slurmd.pid
SlurmctldLogFile=$sl/log/slurmctld.log
SlurmdLogFile=$sl/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
# Batch jobs start at once, not at the default 3 s cadence: the test waits on
# a dozen of them one after another (slurm.conf(5), SchedulerParameters).
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
NodeName=persp-node NodeHostname=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$sl/slurm.conf"
slurmctld -i >/dev/null 2>&1 || fail_start slurmctld "$sl/log/slurmctld.log"
slurmd -N persp-node >/dev/null 2>&1 || fail_start slurmd "$sl/log/slurmd.log"
for _ in $(seq 100); do
    [ "$(sinfo -h -o %T 2>/dev/null)" = idle ] && break
    sleep 0.2
done
[ "$(sinfo -h -o %T 2>/dev/null)" = idle ] || fail_start "the node ($(sinfo -h -o %T 2>&1))" "$sl/log/slurmd.log"

# ---------------------------------------------------------------- helpers
echo "[${SECONDS}s] helpers"
args="--case paper-quad,random-triangles,floor --size 96x72 --triangles 3"
# shellcheck disable=SC2086
"$persp" accuracy $args --json -o "$tmp/full.json" || bad "unsharded run"
export PERSP="$persp" SWEEP_ARGS="$args"
unset SWEEP_SBATCH SWEEP_PAGE
cd "$tmp/work" || exit 1

# wait_jobs ID...: until none is pending or running (60 s at most).
wait_jobs() {
    for _ in $(seq 300); do
        [ -z "$(squeue -h -j "$(tr ' ' ',' <<<"$*")" 2>/dev/null)" ] && return 0
        sleep 0.2
    done
    bad "jobs $* still queued after 60 s: $(squeue 2>&1)"
    scancel "$@"
}
state() { scontrol show job "$1" | grep -o 'JobState=[A-Z_]*' | head -n 1 | cut -d= -f2; }
# submit DIR N [SLICES]: the script's submit; sets jid and mid.
submit() {
    local out
    out=$(SWEEP_DIR="$1" bash "$script" submit "${@:2}" 2>&1) || { bad "submit ${*:2}: $out"; jid= mid=; return 1; }
    read -r jid mid <"$1/logs/jobs-of-$2"
}
same() { cmp -s "$tmp/full.json" "$1/accuracy.json" && ok || bad "$2: $1/accuracy.json differs from the unsharded run"; }

# ------------------------------------------------ a full sweep, 4 slices
echo "[${SECONDS}s] a full sweep, 4 slices"
d="$tmp/a"
submit "$d" 4 1-4%2 && wait_jobs "$jid" "$mid"
scontrol show job "$jid" | grep -q 'ArrayTaskThrottle=2' && ok || bad "the array is not throttled to 2"
[ "$(state "$mid")" = COMPLETED ] && ok || bad "full sweep: merge job $(state "$mid"): $(cat "$d"/logs/merge-* 2>&1)"
same "$d" "full sweep"
[ -s "$d/page/index.html" ] && ok || bad "full sweep: no page"
for k in 1 2 3 4; do
    [ -s "$d/logs/shard-$k-of-4.$jid.log" ] || [ -e "$d/logs/shard-$k-of-4.$jid.log" ] && ok ||
        bad "no log $d/logs/shard-$k-of-4.$jid.log: $(ls "$d/logs")"
done
grep -q "merged 4 slices" "$d/logs/merge-of-4.$mid.log" && ok || bad "merge log: $(ls "$d/logs")"
[ -z "$(ls -A "$tmp/work")" ] && ok || bad "files left where the sweep was submitted: $(ls -A "$tmp/work")"
ls "$d/logs" | grep -q 4294967294 && bad "a log named after Slurm's NO_VAL: $(ls "$d/logs")" || ok

# ------------------------- a cancelled slice: named, then re-run alone
echo "[${SECONDS}s] a cancelled slice: named, then re-run alone"
# Slice 2 runs long the first time (a binary that waits until told to
# stop), and is cancelled while it runs; the wait ends with the test even
# where the cancel leaves it running.
d="$tmp/b"
cat >"$tmp/slow-persp" <<EOF
#!/bin/sh
case "\$*" in *"--shard 2/3"*)
    if [ ! -e "$tmp/slow" ]; then
        touch "$tmp/slow"
        while [ -d "$tmp" ] && [ ! -e "$tmp/stop" ]; do sleep 0.2; done
        exit 1
    fi ;;
esac
exec "$persp" "\$@"
EOF
chmod +x "$tmp/slow-persp"
PERSP="$tmp/slow-persp" submit "$d" 3 && {
    for _ in $(seq 100); do [ -e "$tmp/slow" ] && break; sleep 0.1; done
    [ "$(squeue -h -j "${jid}_2" -o %T)" = RUNNING ] && ok || bad "slice 2 is not running: $(squeue)"
    scancel "${jid}_2"
    wait_jobs "$jid" "$mid"
    touch "$tmp/stop"
}
[ "$(state "$mid")" = FAILED ] && ok || bad "cancelled slice: merge job $(state "$mid"), expected FAILED"
log="$d/logs/merge-of-3.$mid.log"
grep -q "missing slice 2 of 3" "$log" && ok || bad "merge does not name the cancelled slice: $(cat "$log")"
[ ! -e "$d/accuracy.json" ] && ok || bad "a merge of a cancelled sweep wrote accuracy.json"
rerun=$(grep -E '^  PERSP=.*slow-persp .* submit 3 2$' "$log")
[ -n "$rerun" ] && ok || bad "no re-run command in: $(cat "$log")"
eval "$rerun" >/dev/null && read -r jid2 mid2 <"$d/logs/jobs-of-3" && wait_jobs "$jid2" "$mid2"
[ "$(scontrol show job "$jid2" | grep -c 'ArrayTaskId=')" -le 1 ] && ok || bad "the re-run ran more than slice 2"
same "$d" "cancelled slice re-run"

# --------------------- a stepped array, then the rest by sbatch itself
echo "[${SECONDS}s] a stepped array, then the rest by sbatch itself"
d="$tmp/c"
submit "$d" 4 1-3:2 && wait_jobs "$jid" "$mid"
grep -q "missing slices 2,4 of 4" "$d/logs/merge-of-4.$mid.log" && ok ||
    bad "stepped array: $(cat "$d/logs/merge-of-4.$mid.log")"
for k in 1 3; do [ -s "$d/shard-$k-of-4."*.json ] && ok || bad "stepped array: slice $k not measured"; done
# The documented sbatch forms: an array of slice numbers with N, and K/N.
export SWEEP_DIR="$d"
j1=$(sbatch --parsable --array=4 -o "$d/logs/shard-%a-of-4.%A.log" "$script" 4)
j2=$(sbatch --parsable -o "$d/logs/shard-2-of-4.%j.log" "$script" 2/4)
j3=$(sbatch --parsable --array=5 -o "$d/logs/bad-%a.%A.log" "$script" 4)
m=$(sbatch --parsable --dependency=afterany:"$j1:$j2" -o "$d/logs/merge-of-4.%j.log" "$script" merge 4)
wait_jobs "$j1" "$j2" "$j3" "$m"
unset SWEEP_DIR
[ "$(state "$m")" = COMPLETED ] && ok || bad "stepped array completed by sbatch: $(cat "$d/logs/merge-of-4.$m.log")"
same "$d" "stepped array"
grep -q "array task 5 is past the sweep's 4 slices" "$d/logs/bad-5.$j3.log" && ok ||
    bad "array task 5 of a 4-slice sweep: $(cat "$d/logs/bad-5.$j3.log")"

# ------------- a folder holding slices of other sweeps: left out
echo "[${SECONDS}s] a folder holding slices of other sweeps: left out"
d="$tmp/d"
mkdir -p "$d"
submit "$d" 3 && wait_jobs "$jid" "$mid"
SWEEP_DIR="$d" SWEEP_ARGS="--case paper-quad --size 96x72" bash "$script" 2/4 || bad "a slice run outside Slurm"
echo '{"rows": 3}' >"$d/shard-1-of-4.json"
rm -f "$d/accuracy.json"
# In two parts, the second half first (an array that does not start at 1).
submit "$d" 4 3-4 && wait_jobs "$jid" "$mid"
grep -q "missing slices 1-2 of 4" "$d/logs/merge-of-4.$mid.log" && ok ||
    bad "offset array: $(cat "$d/logs/merge-of-4.$mid.log")"
submit "$d" 4 1-2 && wait_jobs "$jid" "$mid"
[ "$(state "$mid")" = COMPLETED ] && ok || bad "stale folder: $(cat "$d/logs/merge-of-4.$mid.log")"
same "$d" "stale folder"

# ---------------------------- refused before anything is queued
echo "[${SECONDS}s] refused before anything is queued"
before=$(squeue -h | wc -l)
expect 1 "PERSP='$tmp/none' is not an executable" -- env PERSP="$tmp/none" SWEEP_DIR="$tmp/e" bash "$script" submit 2
printf '#!/bin/sh\necho "cannot execute binary file" >&2\nexit 126\n' >"$tmp/broken"
chmod +x "$tmp/broken"
expect 1 "does not run on .*cannot execute" -- env PERSP="$tmp/broken" SWEEP_DIR="$tmp/e" bash "$script" submit 2
expect 1 "bad slices '5'" -- env SWEEP_DIR="$tmp/e" bash "$script" submit 4 5
expect 1 "usage: .* submit N" -- env SWEEP_DIR="$tmp/e" bash "$script" submit
[ "$(squeue -h | wc -l)" -eq "$before" ] && [ ! -e "$tmp/e/logs/jobs-of-2" ] && ok || bad "a refused submit queued jobs"

echo "test_slurm: $pass passed, $fail failed"
[ "$fail" -eq 0 ]

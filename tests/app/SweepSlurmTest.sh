#!/bin/sh
# The slope-friction study on a real Slurm: starts munged, slurmctld and slurmd on this machine (Debian's packages,
# a configuration written into a temporary folder: loopback only, ports of its own, state and logs in the folder,
# no accounting), submits the study with `masse sweep --slurm --wait`, collects, compares results.csv with a local
# run of the same study, and stops the daemons it started.
#
# usage: SweepSlurmTest.sh MASSE SOURCE_DIR
set -u
masse=$1
source_dir=$2
study="$source_dir/tests/studies/slope-friction.json"

for program in munged slurmctld slurmd sbatch sinfo; do
    if ! command -v "$program" >/dev/null 2>&1; then
        echo "FAIL: $program is missing: .ci/build installs munge, slurmctld, slurmd and slurm-client"
        exit 1
    fi
done

work=$(mktemp -d "${TMPDIR:-/tmp}/masse-slurm.XXXXXX")
chmod 700 "$work"
munged_pid=""
slurmctld_pid=""
slurmd_pid=""

stop_daemons() {
    # Only the daemons this script started, by their process ids.
    for pid in $slurmd_pid $slurmctld_pid $munged_pid; do
        kill "$pid" 2>/dev/null
    done
    for pid in $slurmd_pid $slurmctld_pid $munged_pid; do
        for _ in 1 2 3 4 5 6 7 8 9 10; do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.5
        done
        kill -9 "$pid" 2>/dev/null
    done
}

fail() {
    echo "FAIL: $*"
    for log in slurmctld.log slurmd.log munged.log; do
        if [ -f "$work/$log" ]; then
            echo "--- last lines of $log"
            tail -n 20 "$work/$log"
        fi
    done
    stop_daemons
    rm -rf "$work"
    exit 1
}
trap 'stop_daemons; rm -rf "$work"' INT TERM

# A TCP port nobody listens on (from /proc/net/tcp, which lists listening sockets as state 0A).
port_is_free() {
    hex=$(printf '%04X' "$1")
    ! awk -v p=":$hex" 'NR > 1 && $4 == "0A" && substr($2, length($2) - 4) == p { found = 1 } END { exit !found }' \
        /proc/net/tcp /proc/net/tcp6 2>/dev/null
}
free_port() {
    candidate=$(( 20000 + ($$ * 7 + $1) % 20000 ))
    while ! port_is_free "$candidate"; do
        candidate=$((candidate + 1))
    done
    echo "$candidate"
}
ctld_port=$(free_port 0)
slurmd_port=$(free_port 101)
[ "$slurmd_port" = "$ctld_port" ] && slurmd_port=$((ctld_port + 1))

# munge: a key of our own and a socket in the work folder.
dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 2>/dev/null
chmod 600 "$work/munge.key"
munged --force --key-file="$work/munge.key" --socket="$work/munge.socket" --pid-file="$work/munged.pid" \
    --log-file="$work/munged.log" --seed-file="$work/munged.seed" || fail "munged did not start"
for _ in $(seq 1 50); do
    [ -s "$work/munged.pid" ] && break
    sleep 0.1
done
munged_pid=$(cat "$work/munged.pid" 2>/dev/null)
[ -n "$munged_pid" ] || fail "munged wrote no pid file"

user=$(id -un)
cpus=$(nproc)
mkdir -p "$work/state" "$work/spool"
cat >"$work/slurm.conf" <<CONF
ClusterName=massetest
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge.socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
ReturnToService=2
MaxArraySize=1000
NodeName=massenode NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=masse Nodes=massenode Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"

slurmctld -D -i -f "$SLURM_CONF" >"$work/slurmctld.out" 2>&1 &
slurmctld_pid=$!
slurmd -D -N massenode -f "$SLURM_CONF" >"$work/slurmd.out" 2>&1 &
slurmd_pid=$!

# Wait for the node to come up idle.
state=""
for _ in $(seq 1 120); do
    state=$(sinfo -h -n massenode -o %T 2>/dev/null)
    [ "$state" = "idle" ] && break
    kill -0 "$slurmctld_pid" 2>/dev/null || fail "slurmctld stopped: $(cat "$work/slurmctld.out")"
    kill -0 "$slurmd_pid" 2>/dev/null || fail "slurmd stopped: $(cat "$work/slurmd.out")"
    sleep 0.5
done
[ "$state" = "idle" ] || fail "the node did not come up (state '$state')"
echo "ok   single-node Slurm up (slurmctld port $ctld_port, slurmd port $slurmd_port)"

# The study on Slurm: submitted as a job array, waited for, collected.
if ! "$masse" sweep "$study" --out "$work/on-slurm" --slurm --wait --throttle 2 --time 10 --no-plots \
    >"$work/slurm-sweep.txt" 2>&1; then
    cat "$work/slurm-sweep.txt"
    ls -R "$work/on-slurm/slurm" 2>/dev/null
    cat "$work"/on-slurm/slurm/*.out 2>/dev/null | tail -n 20
    fail "masse sweep --slurm failed"
fi
cat "$work/slurm-sweep.txt"
grep -q "#SBATCH --array=0-7%2" "$work/on-slurm/sweep.sbatch" || fail "the sbatch script has no array over 8 cases"
echo "ok   the job array ran every case"

# The same study here, and the results compared.
"$masse" sweep "$study" --out "$work/here" --jobs 2 --no-plots >"$work/local-sweep.txt" 2>&1 ||
    { cat "$work/local-sweep.txt"; fail "the local sweep failed"; }
if ! cmp -s "$work/on-slurm/results.csv" "$work/here/results.csv"; then
    diff "$work/on-slurm/results.csv" "$work/here/results.csv"
    fail "results.csv from Slurm differs from the local run"
fi
echo "ok   results.csv from Slurm is the same as from the local run"

# --collect reads the Slurm folder the same way.
"$masse" sweep --collect "$work/on-slurm" --no-plots >"$work/collect.txt" 2>&1 || fail "--collect failed"
grep -q "8 case(s): 8 done, 0 failed, 0 not run" "$work/collect.txt" || { cat "$work/collect.txt"; fail "collect"; }
echo "ok   --collect on the Slurm folder"

stop_daemons
rm -rf "$work"
echo "passed"

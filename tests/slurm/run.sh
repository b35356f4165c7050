#!/usr/bin/env bash
# A real single-node Slurm cluster, started here, runs a sweep plan as a job array; its
# sweep.csv must equal the local run's, value for value (the `cpu` rows aside: CPU time
# is measured, not computed), and so must orders.csv.
#
#   tests/slurm/run.sh [PLAN]        # default: cases/sweeps/convergence.toml
#
# Needs root (it starts munged, slurmctld and slurmd) and Debian's packages:
#   apt-get install -y slurm-wlm munge
# and the release binary (cargo build --release). Everything it starts is stopped on exit;
# its configuration, state, logs and outputs are in a temporary folder (kept on failure).
# Not part of .ci/run: it needs root, two daemons and the packages.
set -euo pipefail
cd "$(dirname "$0")/../.."
plan=${1:-cases/sweeps/convergence.toml}
bin=$PWD/target/release/floebench
[ -x "$bin" ] || { echo "build first: cargo build --release" >&2; exit 2; }
for tool in munged slurmctld slurmd sbatch squeue sinfo; do
    command -v "$tool" >/dev/null || { echo "missing $tool: apt-get install -y slurm-wlm munge" >&2; exit 2; }
done
[ "$(id -u)" = 0 ] || { echo "run as root (it starts munged, slurmctld and slurmd)" >&2; exit 2; }

work=$(mktemp -d /tmp/floebench-slurm.XXXXXX)
host=$(hostname -s)
cpus=$(nproc)
mem=$(awk '/MemTotal/ {print int($2 / 1024)}' /proc/meminfo)
mkdir -p "$work"/{state,spool,log,munge,munge-key}
chmod 755 "$work" "$work/log"
pids=()
cleanup() {
    status=$?
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    for p in "${pids[@]}"; do
        for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    done
    if [ "$status" = 0 ]; then rm -rf "$work"; else echo "kept $work (logs in $work/log)" >&2; fi
}
trap cleanup EXIT

# munge: our own key, socket and daemon (not the system's).
# The key folder is private to munge; the socket's must be open to all.
key=$work/munge-key/munge.key
dd if=/dev/urandom of="$key" bs=1024 count=1 status=none
touch "$work/log/munged.log"
chown -R munge:munge "$work/munge" "$work/munge-key" "$work/log/munged.log"
chmod 700 "$work/munge-key"
chmod 755 "$work/munge"
chmod 400 "$key"
socket=$work/munge/munge.socket
runuser -u munge -- munged --key-file="$key" --socket="$socket" \
    --pid-file="$work/munge/munged.pid" --log-file="$work/log/munged.log" --seed-file="$work/munge-key/seed"
sleep 0.5
pids+=("$(cat "$work/munge/munged.pid")")

conf=$work/slurm.conf
cat > "$conf" <<EOF
ClusterName=floebench
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
SlurmctldPort=16817
SlurmdPort=16818
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
MaxArraySize=1001
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$conf
slurmctld -f "$conf"
sleep 1
pids+=("$(cat "$work/slurmctld.pid")")
slurmd -f "$conf"
sleep 1
pids+=("$(cat "$work/slurmd.pid")")
for _ in $(seq 60); do
    state=$(sinfo -h -o %T 2>/dev/null | head -1)
    [ "$state" = idle ] && break
    sleep 1
done
[ "$state" = idle ] || { echo "the node is not idle: $state" >&2; exit 1; }
echo "slurm: node $host idle ($cpus CPUs)"

start=$(date +%s)
"$bin" sweep "$plan" -o "$work/local" --quiet > "$work/local.log"
echo "local: $(grep '^sweep:' "$work/local.log")"
"$bin" sweep "$plan" -o "$work/cluster" --slurm "$work/job" --chunk 8 > "$work/job.log"
tail -1 "$work/job.log"
sh "$work/job/submit.sh"
for _ in $(seq 600); do
    [ -z "$(squeue -h -o %i)" ] && break
    sleep 1
done
[ -z "$(squeue -h -o %i)" ] || { echo "the jobs did not finish in 10 minutes" >&2; exit 1; }
if grep -l -i error "$work"/job/logs/*.out; then echo "a task failed (above)" >&2; exit 1; fi
"$bin" sweep "$plan" -o "$work/cluster" --collect > "$work/collect.log" 2>&1
end=$(date +%s)
if grep -q 'not finished' "$work/collect.log"; then cat "$work/collect.log" >&2; exit 1; fi

grep -v ',cpu,' "$work/local/sweep.csv" > "$work/local.csv"
grep -v ',cpu,' "$work/cluster/sweep.csv" > "$work/cluster.csv"
rows=$(wc -l < "$work/local.csv")
cmp "$work/local.csv" "$work/cluster.csv"
cmp "$work/local/orders.csv" "$work/cluster/orders.csv"
tasks=$(ls "$work"/job/logs/*.out | wc -l)
echo "ok: $tasks array tasks; sweep.csv ($((rows - 1)) rows without cpu) and orders.csv identical to the local run; $((end - start)) s"

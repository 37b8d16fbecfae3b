#!/usr/bin/env bash
# A one-node Slurm cluster in a scratch folder, for trying the job script
# (scripts/slurm/gonio-simulate.sbatch) on one machine and for its test
# (tests/tools/slurm_job_test.cpp, ctest label `slurm`). Debian 12's munge,
# slurmctld and slurmd (scripts/setup.sh installs them); nothing under /etc,
# /run or /var is used or changed, so it runs beside a real installation.
#
#   local-cluster.sh start DIR [OWNER_PID]   # prints the SLURM_CONF to export
#   local-cluster.sh stop DIR
#
# start writes DIR/slurm.conf (free ports picked at start, this machine's
# cores as one node named after the host, one partition), starts munged,
# slurmctld and slurmd with their sockets, state, spool and logs under DIR,
# and waits until the node is idle. With OWNER_PID, a watcher stops the
# cluster when that process ends (a test that crashes or is killed leaves no
# daemons behind). stop ends the daemons it started (by the pids in DIR) and
# any job still running on them; it is safe to call twice. Runs as root
# (SlurmUser and SlurmdUser are the caller).
set -euo pipefail

usage() { echo "usage: $0 start DIR [OWNER_PID] | stop DIR" >&2; exit 2; }
[ $# -ge 2 ] || usage
action=$1
dir=$2

log() { echo "local-cluster: $*" >&2; }

stop_cluster() {
  local d=$1
  [ -d "$d" ] || return 0
  # Jobs first (slurmd ends their steps), then the daemons.
  if [ -f "$d/slurm.conf" ] && [ -f "$d/slurmctld.pid" ]; then
    # Their slurmstepd processes end with them (up to KillWait, 5 s).
    export SLURM_CONF="$d/slurm.conf"
    timeout 10 scancel --quiet --user="$(id -un)" 2>/dev/null || true
    for _ in $(seq 100); do
      [ -z "$(timeout 5 squeue -h -t R,CG,PD -o %i 2>/dev/null)" ] && break
      sleep 0.1
    done
  fi
  # The daemons together (each takes a second or two to stop), then by force.
  local name pid pids=()
  for name in watcher slurmd slurmctld munged; do
    [ -f "$d/$name.pid" ] || continue
    pid=$(cat "$d/$name.pid" 2>/dev/null || true)
    rm -f "$d/$name.pid"
    # (The watcher runs this very script when its owner has ended.)
    [ -n "$pid" ] && [ "$pid" != "$$" ] || continue
    kill -TERM "$pid" 2>/dev/null && pids+=("$pid")
  done
  for pid in "${pids[@]}"; do
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.05; done
    kill -KILL "$pid" 2>/dev/null || true
  done
}

free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

case "$action" in
  stop)
    stop_cluster "$dir"
    exit 0
    ;;
  start) ;;
  *) usage ;;
esac

owner=${3:-}
for tool in munged mungekey slurmctld slurmd sbatch sinfo scontrol; do
  command -v "$tool" >/dev/null 2>&1 || {
    log "$tool not found (scripts/setup.sh installs munge, slurmctld, slurmd and slurm-client)"
    exit 3
  }
done

stop_cluster "$dir"
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
rm -rf "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
mkdir -p "$dir/munge" "$dir/state" "$dir/spool/slurmd" "$dir/log" "$dir/tmp"
chmod 700 "$dir/munge"

mungekey --create --keyfile="$dir/munge/munge.key" --force
chmod 400 "$dir/munge/munge.key"
munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
  --pid-file="$dir/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge/seed"

host=$(hostname -s)
# This machine as slurmd sees it (CPUs, sockets, cores, threads), less its
# memory: a node configured with more than it has would be drained.
node=$(slurmd -C | head -1 | sed -e 's/ RealMemory=[0-9]*//' -e "s/^NodeName=[^ ]*/NodeName=$host/")
first_job=$(( (RANDOM << 8 | RANDOM & 255) % 4000000 + 1000 ))
ctld_port=$(free_port)
slurmd_port=$(free_port)
while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port=$(free_port); done

cat >"$dir/slurm.conf" <<EOF
# Written by scripts/slurm/local-cluster.sh: a one-node cluster in $dir.
ClusterName=gonio-local
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/slurmd
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
PlugStackConfig=$dir/plugstack.conf
# Several clusters on one machine (tests run in parallel): job ids of their
# own, and the steps' temporary files (PMIx's among them) in this folder.
FirstJobId=$first_job
TmpFS=$dir/tmp
ReturnToService=2
KillWait=5
MinJobAge=300
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE OverSubscribe=NO State=UP
EOF
: >"$dir/plugstack.conf"
export SLURM_CONF="$dir/slurm.conf"

slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF" -N "$host"

if [ -n "$owner" ]; then
  # Stops the cluster when the owner ends, whatever way it ends.
  nohup bash -c 'while kill -0 "$1" 2>/dev/null; do sleep 1; done; exec bash "$2" stop "$3"' \
    watcher "$owner" "$0" "$dir" >/dev/null 2>&1 &
  echo $! >"$dir/watcher.pid"
fi

for _ in $(seq 300); do
  state=$(sinfo -h -N -o '%t' 2>/dev/null | head -1 || true)
  case "$state" in
    idle) echo "$SLURM_CONF"; exit 0 ;;
  esac
  sleep 0.1
done
log "the node did not become idle in 30 s (state '${state:-none}'); logs in $dir/log"
tail -n 20 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 || true
stop_cluster "$dir"
exit 1

#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A real single-node Slurm cluster in a folder, for the tests and benchmarks of array jobs:
# Debian's munged, slurmctld and slurmd, configured and started there, on free ports, leaving
# the machine's own Slurm and munge (if any) alone.
#   tools/slurm_local.sh start DIR   starts it; prints "export SLURM_CONF=DIR/slurm.conf" to eval
#   tools/slurm_local.sh stop DIR    cancels its jobs and stops it
# Needs root (slurmd starts jobs as their user) and the packages slurmctld slurmd slurm-client munge.
set -euo pipefail
command=${1:-} dir=${2:-}
[ -n "$command" ] && [ -n "$dir" ] || { echo "usage: $0 start|stop DIR" >&2; exit 1; }
dir=$(cd "$dir" && pwd)
conf=$dir/slurm.conf

if [ "$command" = stop ]; then
  export SLURM_CONF=$conf
  if kill -0 "$(cat "$dir/slurmctld.pid" 2> /dev/null || echo none)" 2> /dev/null; then
    timeout 10 scancel --user="$(id -un)" 2> /dev/null || true
    timeout 10 scontrol shutdown 2> /dev/null || true
  fi
  for pidfile in slurmctld.pid slurmd.pid; do
    pid=$(cat "$dir/$pidfile" 2> /dev/null || true)
    [ -n "$pid" ] || continue
    for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2> /dev/null || true
  done
  munged --socket="$dir/munge.socket" --stop > /dev/null 2>&1 || true
  exit 0
fi
[ "$command" = start ] || { echo "usage: $0 start|stop DIR" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || { echo "slurm_local.sh: needs root (slurmd runs jobs as their user)" >&2; exit 77; }
for program in munged mungekey slurmctld slurmd sbatch; do
  command -v "$program" > /dev/null || { echo "slurm_local.sh: $program is not installed" >&2; exit 77; }
done

# munge refuses a socket in a folder others cannot reach, or can write to.
chmod 0755 "$dir"
for parent in "$dir"/..; do
  [ "$(stat -c %a "$(cd "$parent" && pwd)")" != 700 ] || {
    echo "slurm_local.sh: $(cd "$parent" && pwd) is closed to others (mode 700): munge needs a folder all can reach" >&2
    exit 1
  }
done
mkdir -p "$dir/state" "$dir/spool"
mungekey --create --keyfile="$dir/munge.key" --force
chmod 0600 "$dir/munge.key"
munged --key-file="$dir/munge.key" --socket="$dir/munge.socket" --pid-file="$dir/munged.pid" \
  --log-file="$dir/munged.log" --seed-file="$dir/munged.seed"

# Two free ports, from one process holding both while it asks, so they differ.
read -r ctld_port slurmd_port < <(python3 -c 'import socket
a, b = socket.socket(), socket.socket()
a.bind(("127.0.0.1", 0)); b.bind(("127.0.0.1", 0))
print(a.getsockname()[1], b.getsockname()[1])')
node=lasmeshnode
# The machine's cores and memory as slurmd sees them, for the node's line.
cpus=$(nproc)
cat > "$conf" <<CONF
ClusterName=lasmeshlocal
SlurmctldHost=$(hostname -s)(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
# No cgroups: in a container they are not ours to configure (jobs hang waiting on them).
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerParameters=batch_sched_delay=1
MinJobAge=4
ReturnToService=2
MpiDefault=none
NodeName=$node NodeAddr=127.0.0.1 NodeHostname=$(hostname -s) CPUs=$cpus RealMemory=500 State=UNKNOWN
PartitionName=local Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$conf
setsid slurmctld -D -i -f "$conf" > "$dir/slurmctld.out" 2>&1 < /dev/null &
setsid slurmd -D -N "$node" -f "$conf" > "$dir/slurmd.out" 2>&1 < /dev/null &
for _ in $(seq 300); do
  if sinfo -h -N -o '%t' 2> /dev/null | grep -qE '^(idle|mix|alloc)'; then
    echo "export SLURM_CONF=$conf"
    exit 0
  fi
  sleep 0.2
done
echo "slurm_local.sh: the node did not come up in 60 s; the logs:" >&2
tail -5 "$dir/slurmctld.log" "$dir/slurmd.log" "$dir"/*.out >&2 || true
exit 1

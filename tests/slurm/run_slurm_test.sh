#!/usr/bin/env bash
# End-to-end test of the Slurm job-array recipe (scripts/slurm/) on a real single-node Slurm:
# installs Debian's slurm-wlm and munge when missing, starts munged, slurmctld and slurmd with a
# configuration of their own under a temporary directory (nothing under /etc is changed), submits
# a sharded EVA sweep and its merge, and compares the merged eva.csv with the unsharded run byte
# for byte. Needs root (the daemons run as root here). Usage: run_slurm_test.sh PCSIM_EXECUTABLE
set -euo pipefail
pcsim=$(readlink -f "$1")
root=$(cd "$(dirname "$0")/../.." && pwd)
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y -q slurm-wlm munge >/dev/null 2>&1 \
    || { apt-get update -q >/dev/null && apt-get install -y -q slurm-wlm munge >/dev/null; }
fi
work=$(mktemp -d /tmp/pcsim-slurm.XXXXXX)
host=$(hostname -s)
mkdir -p "$work"/{state,spool,munge,run}
cleanup() {
  for p in slurmd slurmctld munged; do
    [ -f "$work/run/$p.pid" ] && kill "$(cat "$work/run/$p.pid")" 2>/dev/null || true
  done
  sleep 1
  rm -rf "$work"
}
trap cleanup EXIT
# munge: a key and a daemon of our own.
dd if=/dev/urandom of="$work/munge/munge.key" bs=1 count=1024 2>/dev/null
chmod 400 "$work/munge/munge.key"
chmod 700 "$work/munge"
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.socket" \
  --pid-file="$work/run/munged.pid" --log-file="$work/munge/munged.log" --seed-file="$work/munge/seed"
cat > "$work/slurm.conf" <<CONF
ClusterName=pcsimtest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/run/slurmctld.pid
SlurmdPidFile=$work/run/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=2 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld -i
slurmd
for _ in $(seq 60); do
  sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)' && break
  sleep 1
done
sinfo -h -o %T | grep -qE '^(idle|mixed|allocated)' || { echo "slurm did not come up"; cat "$work"/*.log; exit 1; }
echo "slurm is up: $(sinfo -h -o '%P %D %T %c')"
# The sweep: unsharded, and as a 3-task array plus merge.
args=(--preset syt-7.0-9.8 --speed 150,222 --tension 9.8,15.8)
"$pcsim" eva "${args[@]}" --jobs 1 --no-plot --quiet --out "$work/unsharded" >/dev/null
export PCSIM=$pcsim
merge=$("$root/scripts/slurm/submit_eva.sh" 3 "$work/array" -- "${args[@]}")
for _ in $(seq 600); do
  squeue -h | grep -q . || break
  sleep 1
done
state=$(sacct -n -j "$merge" -o State 2>/dev/null | head -1 | tr -d ' ' || true)
if [ ! -f "$work/array/merged/eva.csv" ]; then
  echo "the merge job ($merge, $state) left no eva.csv"; ls -R "$work/array" | head -50
  cat "$work"/array/*.out 2>/dev/null | tail -30; exit 1
fi
cmp "$work/unsharded/eva.csv" "$work/array/merged/eva.csv"
for f in "$work"/unsharded/cases/*; do cmp "$f" "$work/array/merged/cases/$(basename "$f")"; done
echo "slurm: 3 array tasks and the merge give the unsharded eva.csv and case files byte for byte"

# A design search whose batches run as job arrays (scripts/slurm/design_batch.sh): the same
# journal and answer as the local search, byte for byte.
"$pcsim" design "$root/tests/design/swarm.toml" --jobs 1 --no-plot --quiet --out "$work/design-local" >/dev/null
"$pcsim" design "$root/tests/design/swarm.toml" --no-plot --quiet --out "$work/design-slurm" \
  --evaluate-with "$root/scripts/slurm/design_batch.sh" >/dev/null
n_batches=$(ls -d "$work"/design-slurm-batches/batch-* | wc -l)
cmp "$work/design-local/design.csv" "$work/design-slurm/design.csv"
cmp "$work/design-local/design.json" "$work/design-slurm/design.json"
echo "slurm: a design search over $n_batches job arrays gives the local journal and answer byte for byte"

#!/usr/bin/env bash
# The sweep on a real Slurm cluster: installs slurm-wlm and munge (Debian), starts a one-node
# cluster on this machine (munged as the munge user with its own key and socket; slurmctld and
# slurmd as root, state and spool in a temporary folder, ports of their own), submits a 4-task
# array of scenarios/sweeps/aisle-rows.yaml with tools/slurm/sweep.sbatch and sbatch --wait, then
# the dependent merge job, and compares the merged table with a local run byte for byte. It stops
# exactly the daemons it started. Exit 77 (ctest: skipped, with the reason) where it cannot be root.
# usage: run.sh SSCS_BINARY REPOSITORY_ROOT
set -euo pipefail
sscs=$(realpath "$1")
root=$(realpath "$2")
if [[ $(id -u) -ne 0 ]]; then
  echo "SKIPPED: the Slurm test installs slurm-wlm and munge and starts their daemons, which needs root"
  exit 77
fi
missing=()
for p in slurm-wlm munge; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

t=$(mktemp -d /tmp/sscs-slurm.XXXXXX)
chmod 755 "$t"
pids=()
stop() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  rm -rf "$t"
}
trap stop EXIT
fail() {
  echo "FAIL: $*"
  for f in "$t"/slurm/*.log "$t"/munge/munged.log "$t"/out/*.out; do [[ -f $f ]] && { echo "--- $f"; tail -n 30 "$f"; }; done
  exit 1
}
wait_pidfile() {  # the pid a daemon wrote, once it has
  for _ in $(seq 100); do [[ -s $1 ]] && { cat "$1"; return; }; sleep 0.1; done
  fail "no pid file $1"
}

# munge: a key and socket of our own, run as the munge user.
mkdir -p "$t/munge"
dd if=/dev/urandom of="$t/munge/munge.key" bs=1024 count=1 status=none
chown -R munge:munge "$t/munge"
chmod 755 "$t/munge"  # munged wants its socket's folder searchable by all, writable by it alone
chmod 400 "$t/munge/munge.key"
runuser -u munge -- munged --key-file="$t/munge/munge.key" --socket="$t/munge/munge.socket" \
  --pid-file="$t/munge/munged.pid" --log-file="$t/munge/munged.log" --seed-file="$t/munge/munged.seed" ||
  fail "munged did not start"
pids+=("$(wait_pidfile "$t/munge/munged.pid")")

# slurm: one node, this machine, every CPU.
host=$(hostname -s)
mkdir -p "$t/slurm/state" "$t/slurm/spool" "$t/out"
cat > "$t/slurm/slurm.conf" <<CONF
ClusterName=sscs-test
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
AuthInfo=socket=$t/munge/munge.socket
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
StateSaveLocation=$t/slurm/state
SlurmdSpoolDir=$t/slurm/spool
SlurmctldPidFile=$t/slurm/slurmctld.pid
SlurmdPidFile=$t/slurm/slurmd.pid
SlurmctldLogFile=$t/slurm/slurmctld.log
SlurmdLogFile=$t/slurm/slurmd.log
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$t/slurm/slurm.conf"
slurmctld -i || fail "slurmctld did not start"
pids+=("$(wait_pidfile "$t/slurm/slurmctld.pid")")
slurmd || fail "slurmd did not start"
pids+=("$(wait_pidfile "$t/slurm/slurmd.pid")")
for _ in $(seq 300); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -1 || true)
  [[ $state == idle* ]] && break
  sleep 0.2
done
[[ ${state:-} == idle* ]] || fail "the node did not become idle (state '${state:-}')"

# The study locally, then as a 4-task array and the dependent merge job.
study=scenarios/sweeps/aisle-rows.yaml
cd "$root"
status=0
"$sscs" sweep "$study" --out "$t/local" --quiet || status=$?
((status <= 1)) || fail "the local sweep exited $status"
status=0
array=$(SSCS="$sscs" sbatch --parsable --wait --array=0-3 --chdir="$root" --output="$t/out/sweep-%A_%a.out" \
  tools/slurm/sweep.sbatch "$study" "$t/results") || status=$?
((status <= 1)) || fail "the array job exited $status"
array=${array%%;*}
status=0
SSCS="$sscs" sbatch --parsable --wait --dependency="afterany:$array" --chdir="$root" --output="$t/out/merge-%j.out" \
  tools/slurm/merge.sbatch "$t/results" >/dev/null || status=$?
((status <= 1)) || fail "the merge job exited $status"
shards=$(ls -d "$t/results"/shard-* | wc -l)
((shards == 4)) || fail "expected 4 shard folders, found $shards"
for f in results.csv results.json sweep.json; do
  cmp "$t/local/$f" "$t/results/merged/$f" || fail "$f of the merged shards differs from the local run's"
done
# tools/slurm/submit.sh: the array and the dependent merge in one command, as docs/sweeps.md shows.
SSCS="$sscs" tools/slurm/submit.sh "$study" "$t/submitted" 2 --chdir="$root" --output="$t/out/submit-%j.out" ||
  fail "submit.sh failed"
for _ in $(seq 600); do [[ -f $t/submitted/merged/results.csv ]] && break; sleep 0.2; done
cmp "$t/local/results.csv" "$t/submitted/merged/results.csv" || fail "submit.sh's merged table differs from the local run's"
echo "ok slurm: a 4-task array (job $array) and its merge job, and submit.sh with 2 shards, give the local run's table, byte for byte"

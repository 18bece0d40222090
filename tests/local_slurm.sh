# A one-node Slurm cluster on this machine, for tests (source this file): munged, slurmctld and
# slurmd with a minimal configuration in a folder of their own (localhost only, two free ports,
# no accounting, no cgroups), and everything stopped and removed again by stop_local_slurm (or,
# if the test is killed before it can call it, by a watchdog).
#   start_local_slurm DIR   starts it; exports SLURM_CONF; waits (bounded) for the node to be idle
#   stop_local_slurm        cancels what is left, stops the daemons, removes DIR

install_slurm_if_missing() {
  if command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v munged >/dev/null \
     && command -v mungekey >/dev/null && command -v sbatch >/dev/null; then
    return 0
  fi
  if [ "$(id -u)" != 0 ]; then
    echo "Slurm and munge are not installed, and installing them needs root: apt-get install slurm-wlm munge" >&2
    return 1
  fi
  echo "installing Debian's slurm-wlm and munge"
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y -q --no-install-recommends slurm-wlm munge >/dev/null ||
    { apt-get update -q >/dev/null && apt-get install -y -q --no-install-recommends slurm-wlm munge >/dev/null; }
}

free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

start_local_slurm() {
  LOCAL_SLURM_DIR=$1
  local d=$LOCAL_SLURM_DIR host user ctld_port d_port cpus
  mkdir -p "$d/state" "$d/spool" "$d/log"
  chmod 700 "$d"
  host=$(hostname -s)
  user=$(id -un)
  ctld_port=$(free_port)
  d_port=$(free_port)
  while [ "$d_port" = "$ctld_port" ]; do d_port=$(free_port); done
  cpus=$(nproc)
  mungekey --create --keyfile="$d/munge.key" --force
  chmod 600 "$d/munge.key"
  munged --key-file="$d/munge.key" --socket="$d/munge.sock" --pid-file="$d/munged.pid" \
    --log-file="$d/log/munged.log" --seed-file="$d/munge.seed" --force
  cat > "$d/slurm.conf" <<CONF
ClusterName=oitreftest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$d/munge.sock
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/log/slurmctld.log
SlurmdLogFile=$d/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=oitref Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$d/slurm.conf
  slurmctld -f "$SLURM_CONF"
  slurmd -f "$SLURM_CONF"
  # Whatever ends the test — an error, a signal, even SIGKILL from a timeout — a watchdog outside
  # its process group stops the daemons and removes the folder once the test's shell is gone.
  local owner=$$
  setsid bash -c '
    while kill -0 "$1" 2>/dev/null; do sleep 1; done
    for p in slurmd slurmctld munged; do [ -f "$2/$p.pid" ] && kill "$(cat "$2/$p.pid")" 2>/dev/null; done
    sleep 2
    for p in slurmd slurmctld munged; do [ -f "$2/$p.pid" ] && kill -9 "$(cat "$2/$p.pid")" 2>/dev/null; done
    rm -rf "$2"' watchdog "$owner" "$d" > /dev/null 2>&1 < /dev/null &
  local i
  for i in $(seq 1 60); do
    if sinfo -h -o %t 2>/dev/null | grep -qx idle; then
      echo "local Slurm up: node $host, $cpus CPUs, slurmctld port $ctld_port, slurmd port $d_port"
      return 0
    fi
    sleep 0.5
  done
  echo "local Slurm did not come up in 30 s; its logs:" >&2
  tail -n 20 "$d"/log/*.log >&2
  return 1
}

stop_local_slurm() {
  local d=${LOCAL_SLURM_DIR:-} p
  [ -n "$d" ] || return 0
  if [ -n "${SLURM_CONF:-}" ]; then scancel --user="$(id -un)" 2>/dev/null || true; fi
  for p in slurmd slurmctld munged; do
    if [ -f "$d/$p.pid" ]; then kill "$(cat "$d/$p.pid" 2>/dev/null)" 2>/dev/null || true; fi
  done
  for p in slurmd slurmctld munged; do
    local i
    for i in $(seq 1 20); do
      [ -f "$d/$p.pid" ] && kill -0 "$(cat "$d/$p.pid" 2>/dev/null)" 2>/dev/null || break
      sleep 0.25
    done
    if [ -f "$d/$p.pid" ]; then kill -9 "$(cat "$d/$p.pid" 2>/dev/null)" 2>/dev/null || true; fi
  done
  rm -rf "$d"
  LOCAL_SLURM_DIR=
}

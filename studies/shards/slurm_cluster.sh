#!/usr/bin/env bash
# A private single-node SLURM cluster on this machine, for testing the job array
# (studies/shards/slurm_array.sh): munged, slurmctld and slurmd started by hand on loopback, with
# their key, configuration, state, logs and pid files in one folder. Nothing is written under
# /etc: the daemons get the configuration by -f / command-line options and the clients by
# SLURM_CONF. The daemons need root (slurmd starts the jobs as their users): run it as root, or as a
# user with passwordless sudo (it then runs itself through sudo, and the jobs run as that user).
# Installs slurm-wlm and munge (apt) if missing.
#
# Usage: bash studies/shards/slurm_cluster.sh up|down|status|env
#   up      install if missing, write the configuration, start the daemons, wait until the node is
#           idle (at most SLURM_CLUSTER_WAIT seconds, default 60); exits 0 when the cluster is up,
#           4 when the packages cannot be installed, 5 without root or sudo, 1 on any other failure
#           (then the daemons it started are stopped again)
#   down    cancel the cluster's jobs, stop ONLY the daemons this script started (by the pid files
#           in the folder, each checked to be that daemon with this folder's configuration)
#   status  the daemons' pids and sinfo
#   env     print `export SLURM_CONF=...` for the clients: eval "$(bash slurm_cluster.sh env)"
# Settings (environment): SLURM_CLUSTER_DIR (default <repo>/out/slurm-cluster),
# SLURM_CLUSTER_PORT (slurmctld port, default 17817; slurmd uses the next one).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
dir="${SLURM_CLUSTER_DIR:-$root/out/slurm-cluster}"
port="${SLURM_CLUSTER_PORT:-17817}"
wait_s="${SLURM_CLUSTER_WAIT:-60}"
conf="$dir/slurm.conf"
socket="$dir/munge/munge.socket"
node="$(hostname -s)"

say() { echo "slurm_cluster: $*" >&2; }

# the daemons run as root; a user with passwordless sudo (CI runners) gets them through sudo, while
# the clients (sbatch, squeue) and the jobs run as that user
if [ "$(id -u)" != 0 ] && { [ "${1:-}" = up ] || [ "${1:-}" = down ]; }; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    exec sudo -n env SLURM_CLUSTER_DIR="$dir" SLURM_CLUSTER_PORT="$port" SLURM_CLUSTER_WAIT="$wait_s" \
      PATH="$PATH:/usr/sbin:/sbin" bash "$root/studies/shards/slurm_cluster.sh" "$@"
  fi
  if [ "$1" = up ]; then say "needs root or passwordless sudo (slurmd starts the jobs as their users)"; exit 5; fi
fi

# pid of a running daemon we started, from its pid file; empty when none. The process must be
# `name` and carry this folder's path on its command line (so a reused pid is never taken for ours).
daemon_pid() {
  local name="$1" file="$2" pid
  [ -s "$file" ] || return 0
  pid="$(tr -dc '0-9' < "$file")"
  [ -n "$pid" ] && [ -r "/proc/$pid/cmdline" ] || return 0
  [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$name" ] || return 0
  tr '\0' ' ' < "/proc/$pid/cmdline" | grep -qF -- "$dir/" || return 0
  echo "$pid"
}
munged_pid() { daemon_pid munged "$dir/run/munged.pid"; }
slurmctld_pid() { daemon_pid slurmctld "$dir/run/slurmctld.pid"; }
slurmd_pid() { daemon_pid slurmd "$dir/run/slurmd.pid"; }

stop_daemon() {
  local name="$1" pid
  pid="$("${name}_pid")"
  if [ -z "$pid" ]; then rm -f "$dir/run/$name.pid"; return 0; fi
  kill -TERM "$pid" 2>/dev/null || true
  for _ in $(seq 1 100); do [ -d "/proc/$pid" ] || break; sleep 0.2; done
  if [ -d "/proc/$pid" ]; then say "$name ($pid) did not stop on TERM: KILL"; kill -KILL "$pid" 2>/dev/null || true; sleep 0.5; fi
  if [ -d "/proc/$pid" ]; then say "$name ($pid) is still running"; return 1; fi
  say "stopped $name ($pid)"
  rm -f "$dir/run/$name.pid"
}

down() {
  local ok=0
  if [ -n "$(slurmctld_pid)" ] && [ -n "$(munged_pid)" ]; then
    # jobs first, so that no slurmstepd outlives slurmd
    local jobs
    jobs="$(SLURM_CONF="$conf" squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ')"
    if [ -n "${jobs// /}" ]; then
      say "cancelling jobs $jobs"
      # shellcheck disable=SC2086
      SLURM_CONF="$conf" scancel $jobs 2>/dev/null || true
      for _ in $(seq 1 50); do
        [ -z "$(SLURM_CONF="$conf" squeue -h -o %A 2>/dev/null)" ] && break
        sleep 0.2
      done
    fi
  fi
  stop_daemon slurmd || ok=1
  stop_daemon slurmctld || ok=1
  stop_daemon munged || ok=1
  # started through sudo: the folder goes back to the user who asked
  if [ -n "${SUDO_UID:-}" ] && [ "$(id -u)" = 0 ]; then chown -R "$SUDO_UID:${SUDO_GID:-$SUDO_UID}" "$dir" 2>/dev/null || true; fi
  return "$ok"
}

status() {
  local n pid rc=0
  for n in munged slurmctld slurmd; do
    pid="$("${n}_pid")"
    if [ -n "$pid" ]; then echo "$n: running, pid $pid"; else echo "$n: not running"; rc=3; fi
  done
  if [ "$rc" = 0 ]; then SLURM_CONF="$conf" sinfo -N -o '%N %T %c %m' || rc=3; fi
  return "$rc"
}

install_packages() {
  command -v slurmctld >/dev/null 2>&1 && command -v slurmd >/dev/null 2>&1 \
    && command -v sbatch >/dev/null 2>&1 && command -v munged >/dev/null 2>&1 && return 0
  command -v apt-get >/dev/null 2>&1 || { say "slurm-wlm/munge missing and no apt-get"; return 4; }
  say "installing slurm-wlm munge (apt)"
  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge; } \
    > "$dir/apt.log" 2>&1 || { say "apt-get could not install slurm-wlm munge (see $dir/apt.log)"; return 4; }
  hash -r
}

write_config() {
  local hw
  mkdir -p "$dir/munge" "$dir/run" "$dir/log" "$dir/state" "$dir/spool"
  # daemon files belong to root (munged checks its key's owner); clients of other users need to
  # reach the munge socket (x on its folder) and read slurm.conf
  chown -R 0:0 "$dir/munge" "$dir/run" "$dir/log" "$dir/state" "$dir/spool"
  chmod 711 "$dir/munge"
  chmod 700 "$dir/state" "$dir/spool"
  if [ ! -s "$dir/munge/munge.key" ]; then
    if command -v mungekey >/dev/null 2>&1; then
      mungekey --create --keyfile="$dir/munge/munge.key"
    else
      dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
    fi
  fi
  chmod 400 "$dir/munge/munge.key"
  # this machine's CPUs, boards, sockets, cores, threads and memory as slurmd sees them
  hw="$(slurmd -C | head -n 1 | sed 's/^NodeName=[^ ]* //')"
  : > "$dir/plugstack.conf"
  cat > "$conf" <<EOF
# Written by studies/shards/slurm_cluster.sh: a private single-node test cluster on loopback.
ClusterName=mpm1dtest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
PlugStackConfig=$dir/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MailProg=/bin/true
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
KillWait=5
MinJobAge=600
InactiveLimit=0
NodeName=$node NodeAddr=127.0.0.1 $hw State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
}

up() {
  mkdir -p "$dir"
  dir="$(cd "$dir" && pwd)"; conf="$dir/slurm.conf"; socket="$dir/munge/munge.socket"
  if [ ${#socket} -gt 100 ]; then say "folder path too long for a socket: set SLURM_CLUSTER_DIR"; return 1; fi
  install_packages || return $?
  if [ -n "$(munged_pid)$(slurmctld_pid)$(slurmd_pid)" ]; then
    if [ -n "$(munged_pid)" ] && [ -n "$(slurmctld_pid)" ] && [ -n "$(slurmd_pid)" ]; then
      say "already up ($dir)"; return 0
    fi
    say "partly up: stopping what runs first"; down
  fi
  write_config
  # on any failure from here, stop what was started
  trap 'say "start failed: stopping the daemons started"; down; exit 1' ERR
  munged --key-file="$dir/munge/munge.key" --socket="$socket" --pid-file="$dir/run/munged.pid" \
    --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed" --force
  for _ in $(seq 1 50); do [ -n "$(munged_pid)" ] && [ -S "$socket" ] && break; sleep 0.1; done
  [ -n "$(munged_pid)" ] || { say "munged did not start (see $dir/log/munged.log)"; false; }
  # -c: no state from an earlier run (no old jobs)
  SLURM_CONF="$conf" slurmctld -c -f "$conf"
  SLURM_CONF="$conf" slurmd -c -f "$conf" -N "$node"
  local t0=$SECONDS st=""
  while [ $((SECONDS - t0)) -lt "$wait_s" ]; do
    st="$(SLURM_CONF="$conf" sinfo -h -n "$node" -o %T 2>/dev/null || true)"
    [ "$st" = idle ] && break
    sleep 0.5
  done
  if [ "$st" != idle ]; then
    say "node not idle after ${wait_s} s (state '${st}'); logs in $dir/log"
    tail -n 5 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 || true
    false
  fi
  trap - ERR
  say "up in $((SECONDS - t0)) s: node $node idle ($dir); clients: export SLURM_CONF=$conf"
}

case "${1:-}" in
  up) up ;;
  down) down ;;
  status) status ;;
  env) echo "export SLURM_CONF=$(cd "$dir" 2>/dev/null && pwd || echo "$dir")/slurm.conf" ;;
  *) echo "usage: bash $0 up|down|status|env" >&2; exit 2 ;;
esac

# shellcheck shell=bash
# Sourced by the Slurm tests: starts a private single-node Slurm (slurmctld + slurmd on localhost, no
# munge, no cgroups; a minimal slurm.conf written here) in a temporary directory and stops it
# again. Usage:
#   source tests/drivers/slurm_cluster.sh
#   slurm_cluster_start DIR || exit 77     # sets SLURM_CONF; on failure prints why and returns 1
#   ... sbatch / squeue / scontrol ...
#   slurm_cluster_stop                     # scancel everything, wait for an empty queue, stop the daemons
# slurm_cluster_start installs slurm-wlm through scripts/install_deps.sh (if present, as root) when it is missing.

export SLURM_CLUSTER_DIR=""
SLURM_CTLD_PID=""
SLURM_D_PID=""

slurm_cluster_start() {
  local dir=$1 host mem state root
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
  if ! command -v slurmctld > /dev/null || ! command -v slurmd > /dev/null || ! command -v sbatch > /dev/null; then
    if [ -f "$root/scripts/install_deps.sh" ] && [ "$(id -u)" = 0 ]; then
      echo "slurm: slurm-wlm is not installed; installing it with scripts/install_deps.sh"
      bash "$root/scripts/install_deps.sh" > "$dir.install.log" 2>&1 || true
    fi
    if ! command -v slurmctld > /dev/null || ! command -v slurmd > /dev/null || ! command -v sbatch > /dev/null; then
      echo "SKIP: Slurm is not installed (slurmctld, slurmd, sbatch from Debian's slurm-wlm; scripts/install_deps.sh installs it)"
      return 1
    fi
  fi
  SLURM_CLUSTER_DIR=$dir   # for callers: where the configuration, state and logs are
  mkdir -p "$dir/state" "$dir/spool"
  host=$(hostname -s)
  mem=$(awk '/MemAvailable/ { printf "%d", $2 / 1024 * 0.9 }' /proc/meminfo)
  # Ports: SLURM_TEST_PORT (default 16817) and the next one; two test clusters at once need different ones.
  local port=${SLURM_TEST_PORT:-16817}
  cat > "$dir/slurm.conf" <<CONF
ClusterName=clothsimtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/none
CredType=cred/none
SlurmUser=root
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SchedulerParameters=batch_sched_delay=0
DependencyParameters=kill_invalid_depend
MailProg=/bin/true
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/jobcomp.log
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$dir/slurm.conf
  slurmctld -D -i -f "$SLURM_CONF" > "$dir/slurmctld.out" 2>&1 &
  SLURM_CTLD_PID=$!
  slurmd -D -f "$SLURM_CONF" > "$dir/slurmd.out" 2>&1 &
  SLURM_D_PID=$!
  for _ in $(seq 1 100); do
    state=$(sinfo -h -o %T 2> /dev/null | head -n 1)
    [ "$state" = idle ] && return 0
    if ! kill -0 "$SLURM_CTLD_PID" 2> /dev/null || ! kill -0 "$SLURM_D_PID" 2> /dev/null; then break; fi
    sleep 0.2
  done
  echo "SKIP: Slurm cannot run here: the node did not become idle within 20 s (state '${state:-none}'); logs:"
  tail -n 5 "$dir/slurmctld.log" "$dir/slurmd.log" "$dir/slurmctld.out" "$dir/slurmd.out" 2> /dev/null
  slurm_cluster_stop
  return 1
}

slurm_cluster_stop() {
  if [ -n "$SLURM_CTLD_PID" ] && kill -0 "$SLURM_CTLD_PID" 2> /dev/null; then
    scancel --full --user="$(id -un)" 2> /dev/null || true
    for _ in $(seq 1 100); do
      [ -z "$(squeue -h -o %i 2> /dev/null)" ] && break
      sleep 0.2
    done
  fi
  for pid in $SLURM_D_PID $SLURM_CTLD_PID; do
    kill "$pid" 2> /dev/null || true
  done
  for pid in $SLURM_D_PID $SLURM_CTLD_PID; do
    for _ in $(seq 1 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2> /dev/null || true
  done
  SLURM_CTLD_PID="" SLURM_D_PID=""
}

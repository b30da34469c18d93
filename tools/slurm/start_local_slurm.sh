#!/usr/bin/env bash
# Start a real one-node SLURM cluster on this machine (for tests and demos).
#
#   sudo tools/slurm/start_local_slurm.sh        # install if needed, start, wait for the node
#   sudo tools/slurm/stop_local_slurm.sh         # stop what this script started
#
# What it does (idempotent; a second call with the cluster up only checks it):
#   1. installs Debian's `slurm-wlm` and `munge` with apt-get if they are missing;
#   2. writes slurm.conf from `slurmd -C` (one node at 127.0.0.1, RealMemory ~90 % of
#      MemTotal, proctrack/linuxproc, task/none, select/cons_tres + CR_Core_Memory,
#      ReturnToService=2, no cgroups, no accounting) to the state dir AND to
#      /etc/slurm/slurm.conf (the executor plugin's job step clears SLURM_CONF before
#      its nested srun, so the default path must hold the config);
#   3. starts munged, slurmctld and slurmd in the foreground-mode under this script's
#      control, writes their PIDs to $STATE_DIR/pids, and waits until `sinfo` shows the
#      node idle; prints how long installing and starting took.
#
# Environment:
#   MORPHLEARN_SLURM_STATE       state dir (default /tmp/morphlearn-slurm)
#   MORPHLEARN_SLURM_NO_INSTALL  set to 1 to fail instead of installing packages
#   MORPHLEARN_SLURM_WAIT        seconds to wait for the node to become idle (default 60)
#
# Exit status: 0 up; 2 not root; 3 packages missing and cannot be installed;
#              4 daemons did not come up (log tails are printed).
set -euo pipefail

STATE_DIR="${MORPHLEARN_SLURM_STATE:-/tmp/morphlearn-slurm}"
WAIT_S="${MORPHLEARN_SLURM_WAIT:-60}"
SYS_CONF=/etc/slurm/slurm.conf
MARKER="# managed by morphlearn tools/slurm/start_local_slurm.sh"
PARTITION=debug

die() {
    local code=$1
    shift
    echo "start_local_slurm: ERROR: $*" >&2
    exit "$code"
}
log() { echo "start_local_slurm: $*"; }
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

T0=$(now)

# --- 0. preconditions --------------------------------------------------------------
[ "$(id -u)" -eq 0 ] || die 2 "must run as root (it installs packages, writes $SYS_CONF and starts daemons)"

# --- already running? ----------------------------------------------------------------
alive() { [ -n "${1:-}" ] && kill -0 "$1" 2>/dev/null; }
node_state() { sinfo -h -N -o '%t' 2>/dev/null | head -n1 | tr -d '*~#!%$@^-' || true; }

if [ -f "$STATE_DIR/pids" ]; then
    all_alive=1
    while read -r _name pid; do
        alive "$pid" || all_alive=0
    done <"$STATE_DIR/pids"
    if [ "$all_alive" = 1 ]; then
        case "$(node_state)" in
        idle | mix | alloc)
            log "already running (PIDs in $STATE_DIR/pids); node state: $(node_state)"
            exit 0
            ;;
        esac
    fi
    log "stale state in $STATE_DIR; stopping leftovers first"
    "$(dirname "$0")/stop_local_slurm.sh" || true
fi

# --- 1. packages ---------------------------------------------------------------------
T_INSTALL0=$(now)
need_install=0
for cmd in slurmctld slurmd sinfo sbatch squeue srun munged munge; do
    command -v "$cmd" >/dev/null 2>&1 || [ -x "/usr/sbin/$cmd" ] || need_install=1
done
if [ "$need_install" = 1 ]; then
    [ "${MORPHLEARN_SLURM_NO_INSTALL:-0}" = 1 ] && die 3 "slurm-wlm/munge are not installed and MORPHLEARN_SLURM_NO_INSTALL=1"
    command -v apt-get >/dev/null 2>&1 || die 3 "slurm-wlm/munge are not installed and there is no apt-get to install them (install SLURM + munge yourself)"
    log "installing slurm-wlm and munge with apt-get ..."
    export DEBIAN_FRONTEND=noninteractive
    if ! apt-get install -y -q --no-install-recommends slurm-wlm munge >"/tmp/morphlearn-slurm-apt.log" 2>&1; then
        log "apt-get install failed; running apt-get update and retrying"
        apt-get update -q >>"/tmp/morphlearn-slurm-apt.log" 2>&1 || true
        apt-get install -y -q --no-install-recommends slurm-wlm munge >>"/tmp/morphlearn-slurm-apt.log" 2>&1 ||
            { tail -n 20 /tmp/morphlearn-slurm-apt.log >&2; die 3 "apt-get install slurm-wlm munge failed (log: /tmp/morphlearn-slurm-apt.log)"; }
    fi
fi
export PATH="$PATH:/usr/sbin:/sbin"
T_INSTALL1=$(now)

# --- 2. configuration ----------------------------------------------------------------
mkdir -p "$STATE_DIR"/{ctld,spool,log}
: >"$STATE_DIR/pids"

host=$(hostname -s)
# Hardware line as slurmd sees it, e.g.
# NodeName=h CPUs=2 Boards=1 SocketsPerBoard=1 CoresPerSocket=2 ThreadsPerCore=1 RealMemory=24105
hw=$(slurmd -C 2>/dev/null | grep '^NodeName=' | head -n1) || true
[ -n "$hw" ] || die 4 "slurmd -C printed no hardware line"
hw_fields=$(echo "$hw" | tr ' ' '\n' | grep -v -E '^(NodeName|RealMemory)=' | tr '\n' ' ')
mem_total_mb=$(awk '/^MemTotal:/ { printf "%d", $2 / 1024 }' /proc/meminfo)
real_mem=$((mem_total_mb * 9 / 10))

cat >"$STATE_DIR/slurm.conf" <<EOF
$MARKER
# One-node test cluster: written $(date -Is) from \`slurmd -C\` on $host.
ClusterName=morphlearn
SlurmctldHost=$host(127.0.0.1)
AuthType=auth/munge
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
SlurmctldPort=6817
SlurmdPort=6818
StateSaveLocation=$STATE_DIR/ctld
SlurmdSpoolDir=$STATE_DIR/spool
SlurmctldPidFile=$STATE_DIR/slurmctld.pid
SlurmdPidFile=$STATE_DIR/slurmd.pid
SlurmctldLogFile=$STATE_DIR/log/slurmctld.log
SlurmdLogFile=$STATE_DIR/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# no cgroups: plain Linux process tracking, no task affinity/containment
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
MpiDefault=none
# no accounting database: sacct cannot answer, use squeue for job status (MinJobAge
# keeps finished jobs visible to squeue; keep it >= 3 x the plugin's status interval)
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MinJobAge=600
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=60
InactiveLimit=0
KillWait=5
Waittime=0
NodeName=$host NodeAddr=127.0.0.1 NodeHostname=$host ${hw_fields}RealMemory=$real_mem State=UNKNOWN
PartitionName=$PARTITION Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

mkdir -p /etc/slurm
if [ -f "$SYS_CONF" ] && ! grep -qF "$MARKER" "$SYS_CONF"; then
    cp -p "$SYS_CONF" "$STATE_DIR/slurm.conf.orig"
    log "saved the existing $SYS_CONF to $STATE_DIR/slurm.conf.orig (stop_local_slurm.sh restores it)"
fi
cp "$STATE_DIR/slurm.conf" "$SYS_CONF"

# --- 3. daemons ----------------------------------------------------------------------
T_START0=$(now)
start_bg() { # name logfile cmd...   (runs cmd in its own session, records its PID)
    local name=$1 logf=$2
    shift 2
    setsid "$@" >"$logf" 2>&1 </dev/null &
    echo "$name $!" >>"$STATE_DIR/pids"
}
fail_with_logs() {
    for f in "$STATE_DIR"/log/*.log; do
        [ -f "$f" ] && { echo "---- $f (tail)" >&2; tail -n 15 "$f" >&2; }
    done
    die 4 "$*"
}

# munge: reuse a munged that already answers; otherwise start one (as the munge user)
if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
    log "munged already running; reusing it"
else
    if [ ! -s /etc/munge/munge.key ]; then
        if command -v mungekey >/dev/null 2>&1; then
            mungekey --create --keyfile=/etc/munge/munge.key >/dev/null 2>&1 || true
        fi
        [ -s /etc/munge/munge.key ] || dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 2>/dev/null
    fi
    mkdir -p /run/munge /var/lib/munge /var/log/munge
    if id munge >/dev/null 2>&1; then
        chown munge:munge /etc/munge /etc/munge/munge.key /run/munge /var/lib/munge /var/log/munge
        chmod 0700 /etc/munge
        chmod 0400 /etc/munge/munge.key
        chmod 0755 /run/munge
        start_bg munged "$STATE_DIR/log/munged.out" \
            setpriv --reuid=munge --regid=munge --init-groups munged --foreground
    else
        start_bg munged "$STATE_DIR/log/munged.out" munged --foreground --force
    fi
    for _ in $(seq 1 50); do
        munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && break
        sleep 0.1
    done
    munge -n 2>/dev/null | unmunge >/dev/null 2>&1 || fail_with_logs "munged did not come up (see $STATE_DIR/log/munged.out)"
fi

start_bg slurmctld "$STATE_DIR/log/slurmctld.out" slurmctld -D -i -f "$SYS_CONF"
start_bg slurmd "$STATE_DIR/log/slurmd.out" slurmd -D -f "$SYS_CONF"

state=""
deadline=$(($(date +%s) + WAIT_S))
while [ "$(date +%s)" -lt "$deadline" ]; do
    state=$(node_state)
    [ "$state" = idle ] && break
    while read -r name pid; do
        alive "$pid" || fail_with_logs "$name (PID $pid) exited during start-up"
    done <"$STATE_DIR/pids"
    sleep 0.2
done
[ "$state" = idle ] || fail_with_logs "node $host not idle after ${WAIT_S}s (state: '${state:-none}')"

T_END=$(now)
log "cluster up: node $host idle in partition '$PARTITION' ($(sinfo -h -N -o '%c CPUs, %m MB'))"
log "PIDs: $(tr '\n' ' ' <"$STATE_DIR/pids")(in $STATE_DIR/pids)"
log "timing: install $(elapsed "$T_INSTALL0" "$T_INSTALL1") s, start $(elapsed "$T_START0" "$T_END") s, total $(elapsed "$T0" "$T_END") s"

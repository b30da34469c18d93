#!/usr/bin/env bash
# Stop the one-node SLURM cluster started by tools/slurm/start_local_slurm.sh.
#
# Cancels the cluster's jobs, then stops slurmd, slurmctld and munged by the PIDs the start
# script recorded in $MORPHLEARN_SLURM_STATE/pids (default /tmp/morphlearn-slurm/pids);
# nothing else is touched. A munged that was already running before (not started by the
# start script) is left alone. Restores a pre-existing /etc/slurm/slurm.conf if the start
# script had saved one. Safe to call when nothing is running.
set -uo pipefail

STATE_DIR="${MORPHLEARN_SLURM_STATE:-/tmp/morphlearn-slurm}"
SYS_CONF=/etc/slurm/slurm.conf
MARKER="# managed by morphlearn tools/slurm/start_local_slurm.sh"
export PATH="$PATH:/usr/sbin:/sbin"

log() { echo "stop_local_slurm: $*"; }

if [ ! -s "$STATE_DIR/pids" ]; then
    log "nothing to stop (no $STATE_DIR/pids)"
    exit 0
fi

# Cancel the jobs of this (private) cluster so no job steps outlive it.
if command -v squeue >/dev/null 2>&1; then
    jobs=$(timeout 10 squeue -h -o '%A' 2>/dev/null || true)
    if [ -n "$jobs" ]; then
        # shellcheck disable=SC2086
        timeout 10 scancel $jobs 2>/dev/null || true
        sleep 1
    fi
fi

# Stop in reverse start order: slurmd, slurmctld, munged.
mapfile -t entries < <(tac "$STATE_DIR/pids")
for entry in "${entries[@]}"; do
    read -r name pid <<<"$entry"
    [ -n "${pid:-}" ] || continue
    if ! kill -0 "$pid" 2>/dev/null; then
        log "$name (PID $pid) already gone"
        continue
    fi
    # Guard against a recycled PID: only signal the process we started.
    comm=$(cat "/proc/$pid/comm" 2>/dev/null || true)
    case "$comm" in
    "$name" | setpriv) ;;
    *)
        log "PID $pid is '$comm', not $name; leaving it alone"
        continue
        ;;
    esac
    kill -TERM "$pid" 2>/dev/null || true
    for _ in $(seq 1 50); do
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.1
    done
    if kill -0 "$pid" 2>/dev/null; then
        log "$name (PID $pid) ignored SIGTERM; sending SIGKILL"
        kill -KILL "$pid" 2>/dev/null || true
    fi
    log "stopped $name (PID $pid)"
done
rm -f "$STATE_DIR/pids"

if [ -f "$STATE_DIR/slurm.conf.orig" ]; then
    cp -p "$STATE_DIR/slurm.conf.orig" "$SYS_CONF" && rm -f "$STATE_DIR/slurm.conf.orig"
    log "restored the original $SYS_CONF"
elif [ -f "$SYS_CONF" ] && grep -qF "$MARKER" "$SYS_CONF"; then
    rm -f "$SYS_CONF"
fi
exit 0

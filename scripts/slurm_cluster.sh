#!/usr/bin/env bash
# A real one-node Slurm cluster on this Debian/Ubuntu machine, for tests/test_slurm.py and bench/workflow_overhead.py.
#
#   scripts/slurm_cluster.sh up       # install slurm-wlm + munge if missing, write config, start daemons, wait idle
#   scripts/slurm_cluster.sh status   # which daemons run, whose they are, sinfo; exit 0 when the node takes jobs
#   scripts/slurm_cluster.sh down     # stop only the daemons `up` started
#
# Works in a container without systemd: munged, slurmctld and slurmd are started directly, with process tracking
# that needs no cgroups (proctrack/linuxproc, task/none) and no accounting database (accounting_storage/none).
# Snakemake's Slurm executor plugin unsets SLURM_CONF, so the config has to be at the default path
# /etc/slurm/slurm.conf. A config there that this script did not write is never overwritten.
# Without accounting, job states come from squeue only, so MinJobAge is long (finished jobs stay visible).
#
# State (PIDs of the daemons this script started, logs, spool) lives in $FORCENET_SLURM_STATE
# (default /var/tmp/forcenet-slurm). Idempotent: `up` twice starts nothing new; `down` leaves daemons that were
# already running before `up` (or that someone else started) alone.
set -euo pipefail

STATE_DIR=${FORCENET_SLURM_STATE:-/var/tmp/forcenet-slurm}
SLURM_CONF_PATH=/etc/slurm/slurm.conf
MUNGE_KEY=/etc/munge/munge.key
MARKER="# written by forcenet scripts/slurm_cluster.sh"
WAIT_S=${FORCENET_SLURM_WAIT_S:-90}
NODE=$(hostname -s)

log() { echo "slurm_cluster: $*" >&2; }
die() { echo "slurm_cluster: error: $*" >&2; exit 1; }

# --- helpers ---------------------------------------------------------------------------------------------------
pid_alive() {  # pid name: true if pid runs the program `name`
    local pid=$1 name=$2
    [[ -n $pid && -r /proc/$pid/comm ]] && [[ $(cat "/proc/$pid/comm" 2>/dev/null) == "$name" ]]
}

running_pid() {  # name: the PID of a running daemon called `name` (first one), or nothing
    pgrep -x "$1" 2>/dev/null | head -n1 || true
}

node_state() {  # the node's state as sinfo reports it (idle, mixed, alloc, down*, drain, ...), or nothing
    timeout 10 sinfo -h -N -n "$NODE" -o '%T' 2>/dev/null | head -n1 || true
}

node_usable() {  # whether the node takes jobs; the state may be given (else sinfo is asked)
    case "${1-$(node_state)}" in idle|mixed|allocated|alloc|completing) return 0 ;; *) return 1 ;; esac
}

need_root() {
    [[ $(id -u) -eq 0 ]] || die "$1 needs root (run as root, or ask an administrator for a Slurm cluster)"
}

# --- install ---------------------------------------------------------------------------------------------------
install_packages() {
    local missing=()
    for program in munged slurmctld slurmd sinfo sbatch squeue scontrol; do
        command -v "$program" >/dev/null 2>&1 || missing+=("$program")
    done
    [[ ${#missing[@]} -eq 0 ]] && return 0
    need_root "installing slurm-wlm and munge (missing: ${missing[*]})"
    command -v apt-get >/dev/null 2>&1 || die "missing ${missing[*]} and no apt-get: install Slurm (slurmctld, slurmd, client) and munge by hand"
    log "installing slurm-wlm and munge with apt-get (missing: ${missing[*]})"
    # Keep the packages' maintainer scripts from starting services (no systemd/init here; we start them below).
    local policy=/usr/sbin/policy-rc.d added_policy=0
    if [[ ! -e $policy ]]; then
        printf '#!/bin/sh\nexit 101\n' >"$policy" && chmod +x "$policy" && added_policy=1
    fi
    local rc=0
    {
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq >"$STATE_DIR/apt.log" 2>&1 &&
            apt-get install -y -qq --no-install-recommends slurm-wlm munge >>"$STATE_DIR/apt.log" 2>&1
    } || rc=$?
    [[ $added_policy -eq 1 ]] && rm -f "$policy"
    [[ $rc -eq 0 ]] || { tail -n 20 "$STATE_DIR/apt.log" >&2; die "apt-get install slurm-wlm munge failed (log: $STATE_DIR/apt.log)"; }
    for program in "${missing[@]}"; do
        command -v "$program" >/dev/null 2>&1 || die "$program still missing after installing slurm-wlm and munge"
    done
}

# --- config ----------------------------------------------------------------------------------------------------
write_config() {
    if [[ -e $SLURM_CONF_PATH ]] && ! grep -qF "$MARKER" "$SLURM_CONF_PATH"; then
        log "keeping existing $SLURM_CONF_PATH (not written by this script)"
        return 0
    fi
    local cpus mem_mb
    cpus=$(nproc)
    # RealMemory a little under MemTotal so slurmd's own measurement never falls below it (node would drain).
    mem_mb=$(awk '/^MemTotal:/ {printf "%d", $2 / 1024 * 0.95}' /proc/meminfo)
    mkdir -p "$(dirname "$SLURM_CONF_PATH")" "$STATE_DIR/ctld" "$STATE_DIR/spool"
    local tmp
    tmp=$(mktemp "$SLURM_CONF_PATH.XXXXXX")
    cat >"$tmp" <<EOF
$MARKER
# One-node cluster on $NODE: slurmctld + slurmd on localhost, no accounting database, no cgroups.
ClusterName=forcenet
SlurmctldHost=$NODE(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
# Trust the node line below rather than slurmd's hardware probe (a container may see other numbers).
SlurmdParameters=config_overrides
ReturnToService=2
# No accounting: squeue is the only source of job states, so finished jobs stay listed for an hour.
MinJobAge=3600
SchedulerParameters=defer_batch
SlurmctldPort=6817
SlurmdPort=6818
StateSaveLocation=$STATE_DIR/ctld
SlurmdSpoolDir=$STATE_DIR/spool
SlurmctldPidFile=$STATE_DIR/slurmctld.pid
SlurmdPidFile=$STATE_DIR/slurmd.pid
SlurmctldLogFile=$STATE_DIR/slurmctld.log
SlurmdLogFile=$STATE_DIR/slurmd.log
SlurmctldTimeout=60
SlurmdTimeout=120
InactiveLimit=0
KillWait=10
Waittime=0
NodeName=$NODE NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=main Nodes=$NODE Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
EOF
    mv "$tmp" "$SLURM_CONF_PATH"
    chmod 644 "$SLURM_CONF_PATH"
    log "wrote $SLURM_CONF_PATH (node $NODE: $cpus CPUs, $mem_mb MB)"
}

ensure_munge_key() {
    [[ -s $MUNGE_KEY ]] && return 0
    log "creating munge key $MUNGE_KEY"
    mkdir -p "$(dirname "$MUNGE_KEY")"
    if command -v mungekey >/dev/null 2>&1; then
        mungekey --create --keyfile="$MUNGE_KEY" --force
    else
        dd if=/dev/urandom of="$MUNGE_KEY" bs=1024 count=1 status=none
    fi
    if id munge >/dev/null 2>&1; then chown munge:munge "$MUNGE_KEY"; fi
    chmod 400 "$MUNGE_KEY"
}

# --- daemons ---------------------------------------------------------------------------------------------------
record() { echo "$2" >"$STATE_DIR/$1.started"; }  # name pid: this script started it

start_munged() {
    local pid
    pid=$(running_pid munged)
    if [[ -n $pid ]]; then log "munged already running (pid $pid), leaving it alone"; return 0; fi
    ensure_munge_key
    local user=root args=()
    if id munge >/dev/null 2>&1; then
        user=munge
        mkdir -p /run/munge /var/lib/munge /var/log/munge
        chown munge:munge /run/munge /var/lib/munge /var/log/munge "$MUNGE_KEY"
        chmod 755 /run/munge
    else
        args+=(--force)
    fi
    runuser -u "$user" -- munged "${args[@]}" || die "munged failed to start (see /var/log/munge/munged.log)"
    for _ in $(seq 50); do
        pid=$(cat /run/munge/munged.pid 2>/dev/null || running_pid munged)
        pid_alive "$pid" munged && break
        sleep 0.1
    done
    pid_alive "$pid" munged || die "munged did not stay up (see /var/log/munge/munged.log)"
    record munged "$pid"
    log "started munged (pid $pid)"
}

start_slurm_daemon() {  # name: slurmctld or slurmd (they daemonize and write the pid file named in slurm.conf)
    local name=$1 pid
    pid=$(running_pid "$name")
    if [[ -n $pid ]]; then log "$name already running (pid $pid), leaving it alone"; return 0; fi
    local args=()
    [[ $name == slurmd ]] && args+=(-N "$NODE")
    rm -f "$STATE_DIR/$name.pid"
    "$name" "${args[@]}" || die "$name failed to start (see $STATE_DIR/$name.log)"
    for _ in $(seq 100); do
        pid=$(cat "$STATE_DIR/$name.pid" 2>/dev/null || true)
        pid_alive "$pid" "$name" && break
        sleep 0.1
    done
    if ! pid_alive "$pid" "$name"; then
        tail -n 20 "$STATE_DIR/$name.log" >&2 2>/dev/null || true
        die "$name did not stay up (see $STATE_DIR/$name.log)"
    fi
    record "$name" "$pid"
    log "started $name (pid $pid)"
}

wait_idle() {
    local state="" resumed=0
    for _ in $(seq "$WAIT_S"); do
        state=$(node_state)
        if node_usable "$state"; then log "node $NODE is $state"; return 0; fi
        case "$state" in
            down*|drain*|drained*)
                # a node left down by an earlier run (ReturnToService covers most cases): resume it once
                if [[ $resumed -eq 0 ]]; then
                    scontrol update NodeName="$NODE" State=RESUME >/dev/null 2>&1 || true
                    resumed=1
                fi ;;
        esac
        sleep 1
    done
    die "node $NODE not idle after ${WAIT_S}s (state: '${state:-no answer from slurmctld}'; logs in $STATE_DIR)"
}

cmd_up() {
    mkdir -p "$STATE_DIR"
    if command -v sinfo >/dev/null 2>&1 && node_usable; then
        log "a Slurm cluster is already up (node $NODE: $(node_state)); nothing to do"
        return 0
    fi
    need_root "bringing up a Slurm cluster"
    install_packages
    write_config
    start_munged
    start_slurm_daemon slurmctld
    start_slurm_daemon slurmd
    wait_idle
}

cmd_down() {
    local stopped=0
    for name in slurmd slurmctld munged; do  # reverse order of start
        local file="$STATE_DIR/$name.started" pid
        [[ -f $file ]] || continue
        pid=$(cat "$file")
        if pid_alive "$pid" "$name"; then
            kill "$pid"
            for _ in $(seq 100); do pid_alive "$pid" "$name" || break; sleep 0.1; done
            if pid_alive "$pid" "$name"; then kill -9 "$pid" 2>/dev/null || true; fi
            log "stopped $name (pid $pid)"
            stopped=$((stopped + 1))
        else
            log "$name (pid $pid) had already exited"
        fi
        rm -f "$file"
    done
    [[ $stopped -gt 0 ]] || log "no daemon started by this script is running"
    return 0
}

cmd_status() {
    for name in munged slurmctld slurmd; do
        local pid owner="not started by this script"
        pid=$(running_pid "$name")
        if [[ -f $STATE_DIR/$name.started ]] && pid_alive "$(cat "$STATE_DIR/$name.started")" "$name"; then
            pid=$(cat "$STATE_DIR/$name.started"); owner="started by this script"
        fi
        if [[ -n $pid ]]; then echo "$name: running (pid $pid, $owner)"; else echo "$name: not running"; fi
    done
    if ! command -v sinfo >/dev/null 2>&1; then echo "sinfo: not installed"; return 1; fi
    timeout 10 sinfo 2>&1 || true
    node_usable
}

case "${1:-}" in
    up) cmd_up ;;
    down) cmd_down ;;
    status) cmd_status ;;
    *) echo "usage: $0 up|down|status" >&2; exit 2 ;;
esac

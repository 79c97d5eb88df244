#!/usr/bin/env bash
# The smoke workflow on a real SLURM: a one-node cluster of this machine, built from Debian's packages,
# driven by snakemake-executor-plugin-slurm through profiles/slurm, and its results checked equal to a
# local run's.
#
#   cluster/slurm-test.sh [--local DIR] [--workdir DIR] [--keep]
#
#   --local DIR    compare with this existing local smoke run (its work directory, the one holding
#                  results-smoke/) instead of running one
#   --workdir DIR  put the runs in DIR/slurm and DIR/local (default: a new directory under /tmp,
#                  removed at the end when everything passed)
#   --keep         keep the cluster's own directory (configuration, daemon logs, database) at the end
#
# Environment: PYTHON, the interpreter with sleighsim and snakemake-executor-plugin-slurm installed
# (default: python3 on PATH, i.e. the active virtualenv); SLURM_TEST_FIRST_CHECK, seconds before the
# plugin's first status check of a job (default 5; the plugin's 40 only adds idle time on one node).
#
# Steps: install what is missing of slurmctld, slurmd, slurm-client, munge, slurmdbd and mariadb-server
# (apt-get); write slurm.conf (the node line from `slurmd -C`) and slurmdbd.conf into a private
# directory; start munged, MariaDB, slurmdbd, slurmctld and slurmd there, each on its own socket or free
# port; wait for the node to be idle; run the smoke config with --profile profiles/slurm; run it locally
# (-c2) unless --local is given; compare the two with `python -m sleighsim.resultdiff`; print the SLURM
# run's wall time and every job's state from sacct. Exit status 0 only when every job COMPLETED and the
# results are identical.
#
# Nothing under /etc is written, and the daemons take their configuration from the private directory
# only (SLURM_CONF points every SLURM daemon and command at the private slurm.conf, which names a
# private plugstack.conf; munged and MariaDB get their own key, socket and data directory), so a SLURM,
# munge or MariaDB already set up on the machine is left alone. Everything started here is stopped on
# exit (trap); only the installed packages remain. Needs root: apt-get, and the daemons run as root.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
PYTHON=${PYTHON:-python3}
FIRST_CHECK=${SLURM_TEST_FIRST_CHECK:-5}
LOCAL=""
WORK=""
KEEP=0
while (($#)); do
    case $1 in
        --local) LOCAL=$(realpath "$2"); shift 2 ;;
        --workdir) WORK=$2; shift 2 ;;
        --keep) KEEP=1; shift ;;
        -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        *) echo "unknown argument: $1 (see --help)" >&2; exit 2 ;;
    esac
done

log() { printf '[slurm-test %s] %s\n' "$(date -u +%T)" "$*"; }
die() { log "ERROR: $*" >&2; exit 1; }

[[ $(id -u) -eq 0 ]] || die "needs root (apt-get, and the SLURM daemons run as root)"
[[ -z $LOCAL || -d $LOCAL/results-smoke ]] || die "--local $LOCAL holds no results-smoke/ (config/smoke.yaml writes there)"
"$PYTHON" -c "import sleighsim, snakemake_executor_plugin_slurm" 2>/dev/null \
    || die "$PYTHON lacks sleighsim or snakemake-executor-plugin-slurm (pip install -e '.[test]')"
script_start=$(date +%s)

# ---------------------------------------------------------------------------------------------------
# 1. Packages. slurmdbd and MariaDB are there for sacct: the plugin's default status command is sacct
# whenever the sacct binary exists (slurm-client always ships it), and without accounting every sacct
# call fails, so the plugin never learns that a job ended and the run hangs. (The squeue fallback,
# --slurm-status-command squeue, works only while MinJobAge >= 3x the first-check delay.) Testing the
# default path is the point, so accounting it is.
# ---------------------------------------------------------------------------------------------------
PACKAGES=(slurmctld slurmd slurm-client munge slurmdbd mariadb-server)
missing=()
for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    log "installing ${missing[*]}"
    t0=$(date +%s)
    # policy-rc.d / no systemd keeps the packages' own services from starting; nothing here uses them.
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
    log "installed in $(($(date +%s) - t0)) s"
fi
# The package scripts may start the stock services where an init system allows it: note what runs
# before we start anything, so we never touch it.
for d in munged mariadbd slurmdbd slurmctld slurmd; do
    if pgrep -x "$d" >/dev/null; then log "note: a $d is already running (pid $(pgrep -x "$d" | tr '\n' ' ')); left alone"; fi
done

# ---------------------------------------------------------------------------------------------------
# 2. The private directory and the configuration.
# ---------------------------------------------------------------------------------------------------
if [[ -n $WORK ]]; then
    [[ ! -e $WORK/slurm ]] || die "$WORK/slurm exists: the SLURM run needs a fresh work directory"
    [[ -n $LOCAL || ! -e $WORK/local ]] || die "$WORK/local exists: the local run needs a fresh work directory"
    mkdir -p "$WORK"
    WORK=$(realpath "$WORK")
    OWN_WORK=0
else
    WORK=$(mktemp -d /tmp/slurm-test-runs.XXXXXX)
    OWN_WORK=1
fi
SLURM_RUN=$WORK/slurm
LOCAL_RUN=${LOCAL:-$WORK/local}
# mktemp -d makes it 0700, which munged requires of its socket's directory.
D=$(mktemp -d /tmp/slurm-test.XXXXXX)
mkdir -p "$D"/{etc,log,state,spool,munge,db,bin}

PIDS=()      # daemons we started, in start order (stopped in reverse)
NAMES=()
passed=0
cleanup() {
    local rc=$?
    set +e
    trap - EXIT INT TERM
    if ((${#PIDS[@]})) && [[ -n ${SLURM_CONF:-} ]] && scontrol ping >/dev/null 2>&1; then
        # Jobs left by an interrupted run: cancel them before their slurmd goes away.
        local jobs
        jobs=$(squeue -h -o %i 2>/dev/null)
        if [[ -n $jobs ]]; then
            log "cancelling jobs still queued: $(echo "$jobs" | tr '\n' ' ')"
            # shellcheck disable=SC2086  # one job id per word
            scancel $jobs
            for _ in $(seq 30); do [[ -z $(squeue -h -o %i 2>/dev/null) ]] && break; sleep 1; done
        fi
    fi
    local i pid
    for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do
        pid=${PIDS[i]}
        kill -TERM "$pid" 2>/dev/null || continue
        for _ in $(seq 30); do kill -0 "$pid" 2>/dev/null || break; sleep 0.5; done
        if kill -0 "$pid" 2>/dev/null; then
            log "${NAMES[i]} (pid $pid) ignored SIGTERM for 15 s: SIGKILL"
            kill -KILL "$pid"
        fi
        wait "$pid" 2>/dev/null
    done
    ((${#PIDS[@]})) && log "stopped ${NAMES[*]}"
    if ((rc == 0 && passed && !KEEP)); then
        rm -rf "$D"
        ((OWN_WORK)) && rm -rf "$WORK"
    else
        log "kept for inspection: $D (cluster: configuration, logs/), $WORK (runs); remove them when done"
    fi
    exit "$rc"
}
trap cleanup EXIT
# A signal must end the script through cleanup (bash runs the EXIT trap on exit, not on every signal).
trap 'exit 130' INT
trap 'exit 143' TERM

start_daemon() {  # name, log file, command...: run in the foreground mode of the daemon, in the background here
    local name=$1 logf=$2
    shift 2
    "$@" >>"$logf" 2>&1 &
    PIDS+=($!)
    NAMES+=("$name")
}

wait_for() {  # seconds, what, log file, command...: poll the command until it succeeds
    local secs=$1 what=$2 logf=$3 i
    shift 3
    for ((i = 0; i < secs * 2; i++)); do
        if "$@" >/dev/null 2>&1; then return 0; fi
        # a daemon that died will not come up: say so at once
        kill -0 "${PIDS[-1]}" 2>/dev/null || break
        sleep 0.5
    done
    log "$what did not come up; the end of $logf:"
    tail -n 30 "$logf" >&2
    die "$what did not come up"
}

free_port() {  # a TCP port no one listens on now (the kernel picks it)
    "$PYTHON" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

HOST=$(hostname -s)
# The node line as slurmd sees this machine (CPUs, sockets, cores, threads, RealMemory), its first
# line; the second is the uptime.
NODE_LINE=$(slurmd -C | head -n 1)
[[ $NODE_LINE == NodeName=* ]] || die "unexpected output of slurmd -C: $NODE_LINE"
NODE=$(sed -E 's/^NodeName=([^ ]+).*/\1/' <<<"$NODE_LINE")
CTLD_PORT=$(free_port)
SLURMD_PORT=$(free_port)
DBD_PORT=$(free_port)
DB_PORT=$(free_port)
MUNGE_SOCKET=$D/munge/munge.socket
CLUSTER=sleighsimtest

cat >"$D/etc/slurm.conf" <<EOF
# Written by cluster/slurm-test.sh: one node, this machine, everything under $D.
ClusterName=$CLUSTER
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
# root runs the daemons (the script runs as root); jobs run as their submitter.
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# Our own munged, not the stock one at /run/munge.
AuthInfo=socket=$MUNGE_SOCKET
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
# No SPANK plugins: not those of a SLURM installed here before (/etc/slurm/plugstack.conf).
PlugStackConfig=$D/etc/plugstack.conf
SlurmctldLogFile=$D/log/slurmctld.log
SlurmdLogFile=$D/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroup setup needed (containers often lack a writable cgroup tree): processes are tracked
# through /proc, tasks are not bound to cores.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/linux
MpiDefault=none
# Jobs share the node, each with the CPUs and memory it asks for (the profile sets mem_mb).
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
SchedulerType=sched/backfill
ReturnToService=2
# Accounting through our slurmdbd (sacct answers the plugin's status queries); the rule and
# wildcards the plugin puts in the job comment are kept, so sacct can show them.
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=127.0.0.1
AccountingStoragePort=$DBD_PORT
AccountingStoreFlags=job_comment
# The munge socket for talking to slurmdbd (AuthInfo does not cover that connection; without this
# sacct and slurmctld would look for the stock /run/munge socket).
AccountingStoragePass=$MUNGE_SOCKET
JobCompType=jobcomp/none
$NODE_LINE NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF

DB_PASS=$(head -c 18 /dev/urandom | base64 | tr -dc 'A-Za-z0-9')
cat >"$D/etc/slurmdbd.conf" <<EOF
# Written by cluster/slurm-test.sh.
AuthType=auth/munge
AuthInfo=socket=$MUNGE_SOCKET
# slurmdbd runs only where DbdHost names this host; it listens on DbdAddr.
DbdHost=$HOST
DbdAddr=127.0.0.1
DbdPort=$DBD_PORT
SlurmUser=root
PidFile=$D/slurmdbd.pid
LogFile=$D/log/slurmdbd.log
DebugLevel=info
StorageType=accounting_storage/mysql
StorageHost=127.0.0.1
StoragePort=$DB_PORT
StorageUser=slurm
StoragePass=$DB_PASS
StorageLoc=slurm_acct_db
EOF
# slurmdbd refuses a configuration (it holds a password) readable by others.
chmod 600 "$D/etc/slurmdbd.conf"
: >"$D/etc/plugstack.conf"
# Every SLURM daemon and command started from here (sbatch, squeue, sacct) reads this file, and
# slurmdbd the slurmdbd.conf beside it.
export SLURM_CONF=$D/etc/slurm.conf
log "cluster directory $D; node: $NODE_LINE"

# Inside each job the jobstep plugin (snakemake-executor-plugin-slurm-jobstep) starts the rule through
# a nested srun, with every SLURM_* variable but a few job ids removed from srun's environment,
# SLURM_CONF included: srun would then look for the stock /etc/slurm/slurm.conf (absent here, or
# another cluster's) and fail. A real cluster's clients find their configuration there (or configless,
# through slurmd), so nothing is wrong with the profile; here an srun wrapper first on the run's PATH
# (jobs inherit it: the plugin submits with --export=ALL) gives srun alone SLURM_CONF back, instead of
# writing under /etc.
SRUN=$(command -v srun) || die "srun not found (package slurm-client)"
cat >"$D/bin/srun" <<EOF
#!/bin/sh
# Written by cluster/slurm-test.sh: srun with the test cluster's configuration.
SLURM_CONF=$SLURM_CONF exec $SRUN "\$@"
EOF
chmod +x "$D/bin/srun"

# ---------------------------------------------------------------------------------------------------
# 3. The daemons.
# ---------------------------------------------------------------------------------------------------
# munge: a fresh key, our socket; --force because /tmp is world-writable (sticky) above our 0700
# directory, which munged's path checks would otherwise refuse.
mungekey --create --keyfile="$D/munge/munge.key" >/dev/null 2>&1 \
    || dd if=/dev/urandom of="$D/munge/munge.key" bs=1024 count=1 status=none
chmod 600 "$D/munge/munge.key"
start_daemon munged "$D/log/munged.log" munged --foreground --force --socket="$MUNGE_SOCKET" \
    --key-file="$D/munge/munge.key" --log-file="$D/log/munged.log" --pid-file="$D/munge/munged.pid" \
    --seed-file="$D/munge/munged.seed"
wait_for 20 munged "$D/log/munged.log" bash -c "munge -n --socket='$MUNGE_SOCKET' | unmunge --socket='$MUNGE_SOCKET'"

# MariaDB: a data directory of its own, listening on 127.0.0.1 only.
mariadb-install-db --no-defaults --datadir="$D/db" --user=root --auth-root-authentication-method=socket \
    --skip-test-db >"$D/log/mariadb-install.log" 2>&1 || { tail -n 30 "$D/log/mariadb-install.log" >&2; die "mariadb-install-db failed"; }
start_daemon mariadbd "$D/log/mariadb.log" mariadbd --no-defaults --datadir="$D/db" --user=root \
    --socket="$D/mysql.sock" --port="$DB_PORT" --bind-address=127.0.0.1 --pid-file="$D/mariadb.pid" \
    --log-error="$D/log/mariadb.log" --innodb-buffer-pool-size=1024M --innodb-log-file-size=64M --innodb-lock-wait-timeout=900
wait_for 60 MariaDB "$D/log/mariadb.log" mariadb-admin --no-defaults --socket="$D/mysql.sock" ping
mariadb --no-defaults --socket="$D/mysql.sock" -u root <<EOF
CREATE USER 'slurm'@'127.0.0.1' IDENTIFIED BY '$DB_PASS';
GRANT ALL ON slurm_acct_db.* TO 'slurm'@'127.0.0.1';
EOF

start_daemon slurmdbd "$D/log/slurmdbd.log" slurmdbd -D
wait_for 60 slurmdbd "$D/log/slurmdbd.log" sacctmgr -n list cluster
# The cluster must exist in the database before slurmctld registers with it.
sacctmgr -i add cluster "$CLUSTER" >/dev/null

start_daemon slurmctld "$D/log/slurmctld.log" slurmctld -D -f "$SLURM_CONF"
wait_for 60 slurmctld "$D/log/slurmctld.log" bash -c "scontrol ping | grep -q UP"
start_daemon slurmd "$D/log/slurmd.log" slurmd -D -f "$SLURM_CONF"
wait_for 60 "node $NODE idle" "$D/log/slurmd.log" bash -c "[[ \$(sinfo -h -n '$NODE' -o %t) == idle ]]"
log "cluster up in $(($(date +%s) - script_start)) s:"
sinfo -N -o '%N %P %t %c %m'
# sacct's window: every job of this (fresh) cluster; its default would start at midnight.
SACCT=(sacct -a -X -S "$(date +%Y-%m-%dT%H:%M:%S -d "-1 min")")
print_jobs() {  # every job's rule and wildcards (the plugin's job comment), resources and state
    # slurmctld hands finished jobs to slurmdbd asynchronously: wait until none shows as queued.
    for _ in $(seq 30); do
        "${SACCT[@]}" -n -o State | grep -qE 'PENDING|RUNNING' || break
        sleep 1
    done
    echo
    echo "Jobs of the SLURM run (sacct):"
    "${SACCT[@]}" -o JobID,Comment%-60,Partition,AllocCPUS,ReqMem,State,ExitCode,Elapsed
    echo "job states: $("${SACCT[@]}" -n -P -o State | sort | uniq -c | awk '{printf "%s%s %s", sep, $1, $2; sep=", "}')"
}

# ---------------------------------------------------------------------------------------------------
# 4. The smoke run through the SLURM executor (the profile unchanged: its empty slurm_partition makes
# the plugin take the default partition, debug here, from sinfo).
# ---------------------------------------------------------------------------------------------------
cd "$ROOT"
log "SLURM run in $SLURM_RUN"
t0=$(date +%s.%N)
slurm_rc=0
PATH="$D/bin:$PATH" "$PYTHON" -m snakemake -s workflow/Snakefile -d "$SLURM_RUN" --configfile config/smoke.yaml \
    --profile "$ROOT/profiles/slurm" --slurm-init-seconds-before-status-checks "$FIRST_CHECK" \
    >"$WORK/slurm.log" 2>&1 || slurm_rc=$?
slurm_wall=$("$PYTHON" -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.0f}')" "$t0" "$(date +%s.%N)")
if ((slurm_rc)); then
    tail -n 40 "$WORK/slurm.log" >&2
    print_jobs
    die "the SLURM run failed (exit $slurm_rc); its log: $WORK/slurm.log, the jobs' logs under $SLURM_RUN/.snakemake/slurm_logs"
fi
log "SLURM run finished in $slurm_wall s (wall)"

# ---------------------------------------------------------------------------------------------------
# 5. The local run and the comparison.
# ---------------------------------------------------------------------------------------------------
if [[ -z $LOCAL ]]; then
    log "local run (-c2) in $LOCAL_RUN"
    t0=$(date +%s)
    "$PYTHON" -m snakemake -s workflow/Snakefile -d "$LOCAL_RUN" --configfile config/smoke.yaml -c2 \
        >"$WORK/local.log" 2>&1 || { tail -n 40 "$WORK/local.log" >&2; die "the local run failed; its log: $WORK/local.log"; }
    log "local run finished in $(($(date +%s) - t0)) s (wall)"
fi
diff_rc=0
"$PYTHON" -m sleighsim.resultdiff "$LOCAL_RUN/results-smoke" "$SLURM_RUN/results-smoke" >"$WORK/resultdiff.txt" 2>&1 || diff_rc=$?
if ((diff_rc)); then
    grep -v ': identical$' "$WORK/resultdiff.txt" >&2
else
    log "resultdiff: $(tail -n 1 "$WORK/resultdiff.txt") (identical)"
fi

# ---------------------------------------------------------------------------------------------------
# 6. The jobs' states, from the accounting database (print_jobs, above).
# ---------------------------------------------------------------------------------------------------
print_jobs
n_jobs=$("${SACCT[@]}" -n -P -o State | grep -c . || true)
n_bad=$("${SACCT[@]}" -n -P -o State | grep -vc '^COMPLETED$' || true)
echo "SLURM run wall time: $slurm_wall s; script time so far: $(($(date +%s) - script_start)) s"

((n_jobs > 0)) || die "sacct lists no job of the run: the accounting did not record it"
((n_bad == 0)) || die "$n_bad job(s) did not complete (a retry may have hidden it from Snakemake); logs under $SLURM_RUN/.snakemake/slurm_logs"
((diff_rc == 0)) || die "the SLURM results differ from the local ones (see above; $WORK/resultdiff.txt)"
passed=1
log "PASS: every job COMPLETED and the results equal the local run's"

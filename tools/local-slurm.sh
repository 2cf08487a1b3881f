#!/usr/bin/env bash
# A one-node SLURM cluster on this machine, for running the workflow through
# Snakemake's SLURM executor plugin (profiles/slurm) for real.
#
#   tools/local-slurm.sh [start]   install (apt-get, as root) and start it
#   tools/local-slurm.sh stop      stop every daemon it started
#   tools/local-slurm.sh status    what runs, sinfo
#
# What it sets up (Debian's packages; SLURM 22.05 on Debian 12):
#   munge        authentication between the SLURM daemons and commands
#   mariadb      the accounting database, for slurmdbd
#   slurmdbd     job accounting, as on a real cluster: sacct tells each
#                job's state, cores, memory, time limit and run time
#                (tests/test_cluster.py reads it); the plugin asks sacct
#                for job states unless told squeue (profiles/slurm does, as
#                sacct's "CANCELLED by <uid>" hangs it) and falls back to
#                sacct where MinJobAge is short
#   slurmctld    the controller, slurmd the one compute node: this machine,
#                with the cores and memory `slurmd -C` finds, in partition
#                "local" (the default partition)
# Idempotent: every step checks first and says what it changed; a second
# `start` changes nothing.  Processes are tracked by their pid files and
# stopped by them.  No cgroups (proctrack/linuxproc, task/none): this runs
# inside containers too; a job's memory is then not enforced, only
# scheduled.  The jobs inherit this script's niceness (slurmd starts them):
# `nice -n 10 tools/local-slurm.sh` keeps them behind other work.
set -euo pipefail

CLUSTER=local
PARTITION=local
HOST=$(hostname -s)
CONF=/etc/slurm
RUN=/run/slurm
SPOOL=/var/lib/slurm
LOGS=/var/log/slurm
PACKAGES=(slurm-wlm slurmdbd munge mariadb-server)
CHANGED=0

say() { echo "local-slurm: $*"; }
changed() { say "$*"; CHANGED=1; }
alive() { [[ -f $1 ]] && kill -0 "$(cat "$1")" 2>/dev/null; }
need_root() { [[ $EUID -eq 0 ]] || { say "must run as root to $1"; exit 1; }; }

# write_file PATH MODE OWNER: stdin to PATH if its content differs
write_file() {
    local path=$1 mode=$2 owner=$3 new
    new=$(cat)
    if [[ -f $path ]] && [[ "$(cat "$path")" == "$new" ]]; then
        return 0
    fi
    printf '%s\n' "$new" >"$path"
    chmod "$mode" "$path"
    chown "$owner" "$path"
    changed "wrote $path"
}

wait_for() {  # wait_for SECONDS DESCRIPTION COMMAND...
    local t=$1 what=$2
    shift 2
    for _ in $(seq "$t"); do
        "$@" >/dev/null 2>&1 && return 0
        sleep 1
    done
    say "$what did not come up in ${t}s"
    return 1
}

install_packages() {
    local missing=() p
    for p in "${PACKAGES[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    if [[ ${#missing[@]} -eq 0 ]]; then
        say "packages already installed: ${PACKAGES[*]}"
        return
    fi
    need_root "install ${missing[*]}"
    # no init system in a container: keep the packages' scripts from
    # starting the daemons (this script starts them, with its own configs)
    local policy=/usr/sbin/policy-rc.d own_policy=0
    if [[ ! -e $policy ]]; then
        printf '#!/bin/sh\nexit 101\n' >$policy && chmod +x $policy && own_policy=1
    fi
    apt-get update -q >/dev/null
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" >/tmp/local-slurm-apt.log 2>&1 \
        || { say "apt-get install failed, see /tmp/local-slurm-apt.log"; tail -5 /tmp/local-slurm-apt.log; exit 1; }
    [[ $own_policy -eq 1 ]] && rm -f $policy
    changed "installed ${missing[*]} ($(dpkg-query -W -f='${Version}' slurmctld) for slurm)"
}

start_munge() {
    if [[ ! -s /etc/munge/munge.key ]]; then
        mungekey --create --keyfile=/etc/munge/munge.key
        chown munge:munge /etc/munge/munge.key && chmod 400 /etc/munge/munge.key
        changed "created /etc/munge/munge.key"
    fi
    if alive /run/munge/munged.pid; then
        say "munged already running (pid $(cat /run/munge/munged.pid))"
        return
    fi
    install -d -o munge -g munge -m 755 /run/munge
    runuser -u munge -- /usr/sbin/munged
    wait_for 10 munged munge -n
    changed "started munged (pid $(cat /run/munge/munged.pid))"
}

start_mariadb() {
    # small and container-safe: no native AIO (gVisor and some kernels
    # refuse io_submit), a small buffer pool, local socket only
    write_file /etc/mysql/mariadb.conf.d/99-local-slurm.cnf 644 root:root <<'EOF'
# written by tools/local-slurm.sh (masonrydem): the accounting database of
# the local SLURM cluster
[mariadbd]
bind-address = 127.0.0.1
skip-networking = 1
innodb_use_native_aio = 0
innodb_buffer_pool_size = 64M
innodb_lock_wait_timeout = 900
EOF
    if mysqladmin ping >/dev/null 2>&1; then
        say "mariadb already running (pid $(cat /run/mysqld/mysqld.pid 2>/dev/null || echo ?))"
    else
        install -d -o mysql -g mysql -m 755 /run/mysqld
        setsid /usr/sbin/mariadbd --user=mysql --pid-file=/run/mysqld/mysqld.pid \
            >>/var/log/mysql-local-slurm.log 2>&1 </dev/null &
        wait_for 60 mariadb mysqladmin ping
        changed "started mariadb (pid $(cat /run/mysqld/mysqld.pid))"
    fi
    # the accounting database; slurmdbd (as user slurm) logs in through the
    # local socket by its user id: no password anywhere
    if ! mysql -N -e "SELECT 1 FROM mysql.user WHERE user='slurm'" | grep -q 1; then
        mysql -e "CREATE USER 'slurm'@'localhost' IDENTIFIED VIA unix_socket"
        changed "created database user slurm (unix_socket)"
    fi
    if ! mysql -N -e "SHOW DATABASES LIKE 'slurm_acct_db'" | grep -q slurm_acct_db; then
        mysql -e "CREATE DATABASE slurm_acct_db; GRANT ALL ON slurm_acct_db.* TO 'slurm'@'localhost'"
        changed "created database slurm_acct_db"
    fi
}

write_configs() {
    install -d -o slurm -g slurm -m 755 "$RUN" "$LOGS" "$SPOOL" "$SPOOL/slurmctld" "$SPOOL/slurmd"
    write_file $CONF/slurmdbd.conf 600 slurm:slurm <<EOF
# written by tools/local-slurm.sh (masonrydem)
AuthType=auth/munge
DbdHost=localhost
SlurmUser=slurm
PidFile=$RUN/slurmdbd.pid
LogFile=$LOGS/slurmdbd.log
StorageType=accounting_storage/mysql
StorageHost=localhost
StorageUser=slurm
StorageLoc=slurm_acct_db
EOF
    # the node as slurmd sees it (cores, sockets, memory)
    local node
    node=$(slurmd -C | head -1 | sed "s/^NodeName=[^ ]*/NodeName=$HOST NodeAddr=127.0.0.1/")
    write_file $CONF/slurm.conf 644 root:root <<EOF
# written by tools/local-slurm.sh (masonrydem): a one-node cluster
ClusterName=$CLUSTER
SlurmctldHost=$HOST(127.0.0.1)
SlurmUser=slurm
AuthType=auth/munge
StateSaveLocation=$SPOOL/slurmctld
SlurmdSpoolDir=$SPOOL/slurmd
SlurmctldPidFile=$RUN/slurmctld.pid
SlurmdPidFile=$RUN/slurmd.pid
SlurmctldLogFile=$LOGS/slurmctld.log
SlurmdLogFile=$LOGS/slurmd.log
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
# finished jobs stay visible to squeue for an hour: the plugin reads job
# states with squeue (profiles/slurm), and a job gone from squeue before
# Snakemake saw it end would be waited for forever
MinJobAge=3600
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=localhost
# sacct shows each job's comment: the plugin writes the rule or group there
AccountingStoreFlags=job_comment
JobAcctGatherType=jobacct_gather/linux
JobAcctGatherFrequency=30
$node State=UNKNOWN
PartitionName=$PARTITION Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
}

start_daemon() {  # start_daemon NAME PIDFILE COMMAND...
    local name=$1 pidfile=$2
    shift 2
    if alive "$pidfile"; then
        if [[ $CONFIG_CHANGED -eq 1 && $name != slurmdbd ]]; then
            scontrol reconfigure && changed "reconfigured $name (configuration changed)"
        else
            say "$name already running (pid $(cat "$pidfile"))"
        fi
        return
    fi
    "$@"
    wait_for 30 "$name" alive "$pidfile"
    changed "started $name (pid $(cat "$pidfile"))"
}

start() {
    install_packages
    need_root "start the daemons"
    start_munge
    start_mariadb
    local before=$CHANGED
    CHANGED=0
    write_configs
    CONFIG_CHANGED=$CHANGED
    CHANGED=$((before | CHANGED))
    start_daemon slurmdbd $RUN/slurmdbd.pid slurmdbd
    wait_for 30 slurmdbd sacctmgr -n list cluster
    if ! sacctmgr -n -P list cluster format=cluster | grep -qx $CLUSTER; then
        sacctmgr -i add cluster $CLUSTER >/dev/null
        changed "registered cluster $CLUSTER in the accounting database"
    fi
    start_daemon slurmctld $RUN/slurmctld.pid slurmctld
    CONFIG_CHANGED=0  # one reconfigure reaches slurmd too
    start_daemon slurmd $RUN/slurmd.pid slurmd
    wait_for 60 "node $HOST" bash -c "sinfo -h -n $HOST -o %T | grep -Eq '^(idle|mixed|allocated)'" || {
        sinfo -N -l
        say "node not idle: resuming it"
        scontrol update nodename="$HOST" state=resume
        wait_for 30 "node $HOST" bash -c "sinfo -h -n $HOST -o %T | grep -Eq '^(idle|mixed|allocated)'"
        changed "resumed node $HOST"
    }
    sinfo -o "%P %a %D %c %m %T %N"
    [[ $CHANGED -eq 1 ]] && say "cluster $CLUSTER up (changes above)" || say "cluster $CLUSTER already up: nothing changed"
}

stop_pid() {  # stop_pid NAME PIDFILE
    local name=$1 pidfile=$2 pid
    if ! alive "$pidfile"; then
        say "$name not running"
        return
    fi
    pid=$(cat "$pidfile")
    kill "$pid"
    for _ in $(seq 30); do kill -0 "$pid" 2>/dev/null || break; sleep 1; done
    if kill -0 "$pid" 2>/dev/null; then
        say "$name (pid $pid) did not stop in 30 s"
        return 1
    fi
    changed "stopped $name (pid $pid)"
}

stop() {
    need_root "stop the daemons"
    if alive $RUN/slurmctld.pid && [[ -n "$(squeue -h -o %i 2>/dev/null)" ]]; then
        say "jobs still queued or running (they end with slurmd): $(squeue -h -o %i | tr '\n' ' ')"
    fi
    stop_pid slurmd $RUN/slurmd.pid
    stop_pid slurmctld $RUN/slurmctld.pid
    stop_pid slurmdbd $RUN/slurmdbd.pid
    if mysqladmin ping >/dev/null 2>&1; then
        local pid
        pid=$(cat /run/mysqld/mysqld.pid 2>/dev/null || echo ?)
        mysqladmin shutdown
        changed "stopped mariadb (pid $pid)"
    else
        say "mariadb not running"
    fi
    stop_pid munged /run/munge/munged.pid
    [[ $CHANGED -eq 1 ]] && say "cluster stopped" || say "cluster was not running: nothing changed"
}

status() {
    local f
    for f in /run/munge/munged.pid /run/mysqld/mysqld.pid $RUN/slurmdbd.pid $RUN/slurmctld.pid $RUN/slurmd.pid; do
        if alive "$f"; then say "$(basename "$f" .pid): running (pid $(cat "$f"))"; else say "$(basename "$f" .pid): not running"; fi
    done
    sinfo -o "%P %a %D %c %m %T %N" 2>/dev/null || say "sinfo does not answer"
}

case ${1:-start} in
    start) start ;;
    stop) stop ;;
    status) status ;;
    *) echo "usage: $0 [start|stop|status]" >&2; exit 2 ;;
esac

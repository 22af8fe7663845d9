#!/usr/bin/env bash
# The farm workflow of docs/user-guide.md on a real Slurm: Debian's
# slurm-wlm (slurmctld + slurmd + munge) on localhost, configured here in a
# scratch folder. An array job of `render --tile` tasks with a dependent
# `merge` must give the whole render bit for bit; one task killed
# mid-render and requeued must change nothing; a merge of an incomplete set
# must be refused. Needs root (to start the daemons); otherwise, or when
# the daemons cannot start here, it says why and exits 0 (skipped).
#   bash tests/slurm/farm_test.sh [ISOTRACE]
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
isotrace=$(realpath "${1:-build/isotrace}")
skip() { echo "farm_test: SKIPPED: $*"; exit 0; }
[ "$(id -u)" -eq 0 ] || skip "needs root to start slurmctld, slurmd and munged"
[ -x "$isotrace" ] || { echo "farm_test: no isotrace at $isotrace" >&2; exit 2; }
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  # Installing Slurm enables its services: only where asked to (CI machines,
  # which .ci/run marks), never on a user's machine behind their back.
  [ "${ISOTRACE_INSTALL_SLURM:-0}" = 1 ] ||
    skip "slurm-wlm and munge are not installed (ISOTRACE_INSTALL_SLURM=1 lets this test install them)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null 2>&1 ||
    skip "cannot install slurm-wlm and munge"
fi

work=$(mktemp -d /tmp/isotrace-slurm.XXXXXX)
export SLURM_CONF=$work/slurm.conf
host=$(hostname -s)
cleanup() {
  scontrol shutdown >/dev/null 2>&1 || true
  sleep 1
  [ -f "$work/munged.pid" ] && kill "$(cat "$work/munged.pid")" 2>/dev/null || true
  pkill -f "slurmd -D -f $SLURM_CONF" 2>/dev/null || true
  pkill -f "slurmctld -D -f $SLURM_CONF" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# munge: a fresh key and socket of our own.
mkdir -p "$work/munge" "$work/state" "$work/spool" "$work/tiles" "$work/log"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 700 "$work/munge"; chmod 400 "$work/munge/munge.key"
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/socket" \
  --pid-file="$work/munged.pid" --log-file="$work/log/munged.log" --seed-file="$work/munge/seed" ||
  skip "munged does not start here (see $work/log/munged.log)"
cpus=$(nproc)
cat >"$SLURM_CONF" <<CONF
ClusterName=isotrace
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
ReturnToService=2
JobRequeue=1
MpiDefault=none
SlurmctldPort=16817
SlurmdPort=16818
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=farm Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
slurmctld -D -f "$SLURM_CONF" >"$work/log/slurmctld.out" 2>&1 &
slurmd -D -f "$SLURM_CONF" >"$work/log/slurmd.out" 2>&1 &
for _ in $(seq 1 60); do
  sinfo -h -o %T 2>/dev/null | grep -q idle && break
  sleep 0.5
done
sinfo -h -o %T 2>/dev/null | grep -q idle || skip "the Slurm daemons do not come up here (logs in $work/log)"

scene=$root/scenes/showcase.json
settings=(--width 96 --height 64 --spp 64 --seed 7 --threads 1 --no-preview --quiet)
tiles=4
# The reference: one whole render.
"$isotrace" render "$scene" "${settings[@]}" -o "$work/whole.exr"

# Each task renders its tile; task 1 is killed mid-render once (it sees no
# marker yet, drops one and sleeps until it is requeued) and then rerun.
cat >"$work/render.sbatch" <<JOB
#!/bin/bash
#SBATCH --array=0-$((tiles - 1)) --cpus-per-task=1 --requeue --output=$work/log/task-%a.out
if [ "\$SLURM_ARRAY_TASK_ID" = 1 ] && [ ! -f $work/killed-once ]; then
  touch $work/running-1
  "$isotrace" render "$scene" ${settings[*]} --spp 100000 --tile 1/$tiles -o $work/tiles/tile-1.exr
fi
exec "$isotrace" render "$scene" ${settings[*]} --tile \$SLURM_ARRAY_TASK_ID/$tiles -o $work/tiles/tile-\$SLURM_ARRAY_TASK_ID.exr
JOB
job=$(sbatch --parsable "$work/render.sbatch")
merge=$(sbatch --parsable --dependency=afterok:$job --output="$work/log/merge.out" \
  --wrap "$isotrace merge $work/tiles/tile-*.exr -o $work/frame.exr")
# Kill task 1 while it renders, then requeue it.
for _ in $(seq 1 120); do [ -f "$work/running-1" ] && break; sleep 0.5; done
[ -f "$work/running-1" ] || { echo "farm_test: task 1 never started" >&2; exit 1; }
sleep 1
touch "$work/killed-once"
scontrol requeue "${job}_1"
# Slurm holds a requeued job back for a while (its begin time moves two
# minutes ahead); let it start at once.
sleep 1
scontrol update jobid="${job}_1" StartTime=now >/dev/null 2>&1 || true
echo "farm_test: task ${job}_1 killed mid-render and requeued ($SECONDS s)"
for _ in $(seq 1 600); do
  state=$(sacct -n -X -j "$merge" -o State 2>/dev/null | head -1 | tr -d ' ' || true)
  [ -z "$state" ] && state=$(scontrol show job "$merge" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
  case "$state" in COMPLETED|FAILED|CANCELLED*|TIMEOUT) break ;; esac
  sleep 1
done
[ -f "$work/frame.exr" ] || { echo "farm_test: FAILED: no merged frame (merge job $state)" >&2; cat "$work"/log/*.out >&2; exit 1; }
restarts=$(scontrol show job "${job}_1" 2>/dev/null | sed -n 's/.*Restarts=\([0-9]*\).*/\1/p')
[ "${restarts:-0}" -ge 1 ] || { echo "farm_test: FAILED: task 1 was not requeued (restarts ${restarts:-none})" >&2; exit 1; }
if ls -a "$work/tiles" | grep -q partial; then
  echo "farm_test: FAILED: the killed task left a partial file: $(ls -a "$work/tiles")" >&2; exit 1
fi
"$isotrace" compare "$work/frame.exr" "$work/whole.exr" --metric max --fail 0 >/dev/null ||
  { echo "farm_test: FAILED: the merged frame differs from the whole render" >&2; exit 1; }
echo "farm_test: $tiles tiles rendered by Slurm array job $job, merged by job $merge: identical to the whole render ($SECONDS s)"

# A merge of an incomplete set is refused.
rm "$work/tiles/tile-2.exr"
if "$isotrace" merge "$work"/tiles/tile-*.exr -o "$work/incomplete.exr" 2>"$work/log/incomplete.err"; then
  echo "farm_test: FAILED: a merge of 3 of 4 tiles succeeded" >&2; exit 1
fi
[ ! -e "$work/incomplete.exr" ] || { echo "farm_test: FAILED: the refused merge left a file" >&2; exit 1; }
echo "farm_test: a merge of 3 of 4 tiles is refused: $(head -1 "$work/log/incomplete.err")"
echo "farm_test: PASSED"

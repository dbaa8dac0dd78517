#!/usr/bin/env bash
# The Slurm route of `mimo study`, end to end on a real one-node Slurm cluster on this machine:
# Debian's slurmctld, slurmd, slurm-client and munge, brought up on localhost with a private
# configuration (munge key, slurm.conf with this node's real CPU count and memory, state, logs:
# all in one temporary directory), then
#   1. examples/slurm/submit.sh runs a small plan over 3 shards plus the merge; results.parquet,
#      summary.parquet and every cell's tables must be byte-identical (cmp) to the same plan run
#      at once on this machine;
#   2. one shard's items are deleted, that one index is submitted again (sbatch --array=K with the
#      same shard count) with a new merge, and the tables must be identical again;
#   3. `mimo study --status` must report every shard finished.
# The daemons are started and stopped by their process ids and the temporary directory is
# removed on any exit, so the machine is left as it was (the packages stay installed).
#
# Needs root (apt-get, the daemons). Uses the mimo binary of this checkout's cargo target
# directory (CARGO_TARGET_DIR, else ./target), building it only if it is missing or stale.
#   bash scripts/slurm_test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
t_start=$(date +%s)
say() { echo "slurm_test: $*"; }
fail() {
  echo "slurm_test: FAILED: $*" >&2
  exit 1
}
if [ "$(id -u)" -ne 0 ]; then
  say "skipped: needs root (apt-get and the Slurm daemons)"
  exit 0
fi

# The mimo binary CI's cargo built (its test run builds it beside the tests); built here only if
# it is missing or older than a source file, since a build of the binary alone resolves other
# features than the test run's and would rebuild much of the dependency tree.
target_dir=${CARGO_TARGET_DIR:-$repo/target}
mimo=$target_dir/debug/mimo
if [ ! -x "$mimo" ] || [ -n "$(find crates Cargo.toml Cargo.lock -newer "$mimo" \( -name '*.rs' -o -name 'Cargo.*' \) -print -quit)" ]; then
  say "building $mimo"
  cargo build --bin mimo --locked --quiet
fi
[ -x "$mimo" ] || fail "no mimo binary at $mimo"

# Debian's packages, installed without starting their services (policy-rc.d says no; ours is
# removed again if there was none).
made_policy=
work=
pids=()
cleanup() {
  local rc=$?
  if [ -n "$work" ] && [ -f "$work/slurm.conf" ] && command -v scancel >/dev/null 2>&1; then
    SLURM_CONF=$work/slurm.conf timeout 10 scancel --user=root >/dev/null 2>&1 || true
    sleep 1
  fi
  # Stop in reverse order of start: slurmd, slurmctld, munged.
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill "${pids[i]}" 2>/dev/null || true
  done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.2; done
    kill -9 "$p" 2>/dev/null || true
  done
  if [ $rc -ne 0 ] && [ -n "$work" ]; then
    for f in "$work"/*.log "$work"/*.out "$work"/cluster/logs/*; do
      [ -f "$f" ] && { echo "--- $f"; tail -n 20 "$f"; } >&2
    done
  fi
  [ -n "$work" ] && rm -rf "$work"
  [ -n "$made_policy" ] && rm -f /usr/sbin/policy-rc.d
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT TERM

need=()
for c in slurmctld slurmd sbatch munged; do command -v $c >/dev/null 2>&1 || need+=("$c"); done
if [ ${#need[@]} -gt 0 ]; then
  say "installing slurmctld slurmd slurm-client munge (missing: ${need[*]})"
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    printf '#!/bin/sh\nexit 101\n' >/usr/sbin/policy-rc.d
    chmod +x /usr/sbin/policy-rc.d
    made_policy=1
  fi
  apt-get -o DPkg::Lock::Timeout=600 update -qq
  DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends \
    slurmctld slurmd slurm-client munge >/dev/null
  [ -n "$made_policy" ] && rm -f /usr/sbin/policy-rc.d && made_policy=
fi

work=$(mktemp -d /tmp/mimo-slurm-test.XXXXXX)
chmod 700 "$work"
mkdir -p "$work/state" "$work/spool" "$work/munge"
chmod 755 "$work/munge"

# munge: a private key and socket.
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged -F --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.sock" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/munged.log" --seed-file="$work/munge/munged.seed" \
  >"$work/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$work/munge/munge.sock" ] && break; sleep 0.2; done
[ -S "$work/munge/munge.sock" ] || fail "munged did not start"

# slurm.conf: this node as slurmd sees it (its real CPUs and memory), one partition.
node=$(slurmd -C | head -n 1)
name=$(sed -n 's/^NodeName=\([^ ]*\).*/\1/p' <<<"$node")
ports=$((20000 + RANDOM % 20000))
cat >"$work/slurm.conf" <<CONF
ClusterName=mimotest
SlurmctldHost=$name(127.0.0.1)
SlurmctldPort=$ports
SlurmdPort=$((ports + 1))
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
MinJobAge=3600
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=test Nodes=$name Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld -D -c -f "$SLURM_CONF" >"$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$work/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 60); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -n 1 || true)
  [ "$state" = idle ] && break
  sleep 1
done
[ "$state" = idle ] || fail "the node did not come up (sinfo says '$state')"
say "one-node cluster up: $node"

# The plan: scenario 1, two methods, three runs of 60 s; the runs' tables are kept (a study
# deletes them once scored by default) so that every cell's tables can be compared too.
cat >"$work/plan.toml" <<'PLAN'
title = "slurm route"
scenarios = [1]
runs = 3
duration_s = 60
keep_runs = true
[[methods]]
name = "mimo"
ta = "default"
[[methods]]
name = "conventional"
ta = "default"
config = { resource_manager = { mimo = false } }
PLAN

# The reference: the same plan at once on this machine.
"$mimo" study "$work/plan.toml" --out "$work/whole" --threads 2 --quiet

# Wait (bounded) until job $1 has left the queue; its final state must be COMPLETED.
wait_job() {
  local id=$1 st=
  for _ in $(seq 600); do
    st=$(scontrol show job "$id" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -n 1)
    case $st in PENDING | RUNNING | CONFIGURING | COMPLETING | "") sleep 1 ;; *) break ;; esac
  done
  [ "$st" = COMPLETED ] || fail "job $id ended $st"
}

# Every table of the reference, byte for byte, in the cluster's study.
same_tables() {
  local n=0 f
  cmp "$work/whole/results.parquet" "$work/cluster/results.parquet"
  cmp "$work/whole/summary.parquet" "$work/cluster/summary.parquet"
  while IFS= read -r f; do
    cmp "$work/whole/$f" "$work/cluster/$f"
    n=$((n + 1))
  done < <(cd "$work/whole" && find runs -name '*.parquet' | sort)
  [ "$n" -gt 0 ] || fail "no cell tables"
  local m
  m=$(cd "$work/cluster" && find runs -name '*.parquet' | wc -l)
  [ "$m" -eq "$n" ] || fail "$m cell tables in the cluster's study, $n in the reference"
  say "$1: results.parquet, summary.parquet and $n cell tables byte-identical to one machine"
}

# 0. More CPUs per task than the node has: refused before anything is written or queued.
if MIMO="$mimo" examples/slurm/submit.sh "$work/plan.toml" "$work/cluster" 3 -- --cpus-per-task=512 2>"$work/err"; then
  fail "submit.sh accepted 512 CPUs per task"
fi
grep -q "^error: --cpus-per-task=512: the largest node of partition (default) has" "$work/err" || fail "$(cat "$work/err")"
[ ! -e "$work/cluster" ] && [ -z "$(squeue -h)" ] || fail "something was written or queued"

# 1. The whole route: submit.sh, 3 shards and the merge.
out=$(MIMO="$mimo" examples/slurm/submit.sh "$work/plan.toml" "$work/cluster" 3 -- --time=00:20:00)
say "$out"
array=$(sed -n 's/^array job \([0-9]*\) .*/\1/p' <<<"$out")
merge=$(sed -n 's/.*merge job \([0-9]*\)$/\1/p' <<<"$out")
[ -n "$array" ] && [ -n "$merge" ] || fail "submit.sh did not print two job ids: $out"
wait_job "$merge"
for k in 0 1 2; do scontrol show job "${array}_$k" | grep -q JobState=COMPLETED || fail "task $k"; done
same_tables "3 shards + merge"
ls "$work/cluster/logs/shard-0-job-$array.out" "$work/cluster/logs/merge-job-$merge.out" >/dev/null
grep -q "^merged 6 runs of 2 cells (0 failed)" "$work/cluster/logs/merge-job-$merge.out" || fail "merge log"

# 2. Shard 1/3 lost its items (items 1 and 4: run 1 of each cell): run that index again.
rm -f "$work/cluster/results.parquet" "$work/cluster/summary.parquet"
for cell in "$work"/cluster/runs/method=*/scenario=1; do
  rm -f "$cell/.items/run-0001.json" "$cell"/*/run-0001.parquet
done
status=$("$mimo" study "$work/plan.toml" --out "$work/cluster" --status)
grep -q "shard 1/3: 0 of 2 items done" <<<"$status" || fail "status after the loss: $status"
again=$(sbatch --parsable --array=1 --output="$work/cluster/logs/shard-%a-job-%A.out" --export="ALL,MIMO=$mimo" \
  examples/slurm/study.sbatch "$work/plan.toml" "$work/cluster" 3)
again=${again%%;*}
remerge=$(sbatch --parsable --dependency="afterok:$again" --kill-on-invalid-dep=yes \
  --output="$work/cluster/logs/merge-job-%j.out" --export="ALL,MIMO=$mimo" \
  examples/slurm/merge.sbatch "$work/plan.toml" "$work/cluster")
wait_job "${remerge%%;*}"
grep -q "shard 1/3: ran 2 of its 2 runs" "$work/cluster/logs/shard-1-job-$again.out" || fail "shard 1 again"
same_tables "shard 1/3 again + merge"

# 3. The status of the finished study.
status=$("$mimo" study "$work/plan.toml" --out "$work/cluster" --status)
for k in 0 1 2; do
  grep -q "shard $k/3: 2 of 2 items done; finished" <<<"$status" || fail "status: $status"
done
grep -q "^merged" <<<"$status" || fail "status: $status"
say "passed in $(($(date +%s) - t_start)) s"

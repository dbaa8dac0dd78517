#!/usr/bin/env bash
# Submit a mimo study to Slurm: an array of SHARDS tasks, task K running shard K/SHARDS of the
# study into OUT (a directory every node shares), and a merge job that starts when every task has
# succeeded. Prints the two job ids. See examples/slurm/README.md.
#
#   examples/slurm/submit.sh PLAN OUT SHARDS [-- SBATCH OPTIONS...]
#
# SBATCH OPTIONS go to both jobs, e.g. -- --partition=short --account=radar --cpus-per-task=4
# --mem=4G --time=01:00:00 (the defaults are in study.sbatch and merge.sbatch). mimo is looked up
# on the PATH here, or given as MIMO=/path/to/mimo; the jobs run that same path, which every
# compute node must see. Logs go to OUT/logs/.
set -euo pipefail
usage="usage: submit.sh PLAN OUT SHARDS [-- SBATCH OPTIONS...]"
die() {
  echo "error: $*" >&2
  exit 2
}
[ $# -ge 3 ] || die "expected PLAN OUT SHARDS ($usage)"
plan=$1 out=$2 shards=$3
shift 3
if [ $# -gt 0 ]; then
  [ "$1" = "--" ] || die "unexpected argument '$1': sbatch options go after -- ($usage)"
  shift
fi
[[ $shards =~ ^[1-9][0-9]*$ ]] || die "SHARDS: expected a whole number of at least 1, got '$shards'"
[ -f "$plan" ] || die "$plan: no such plan file"
for o in "$@"; do
  case $o in
    --array* | -a* | --dependency* | -d* | --output* | -o* | --error* | -e*)
      die "sbatch option '$o': submit.sh sets it itself (see examples/slurm/README.md to run one shard again)" ;;
  esac
done
mimo=${MIMO:-$(command -v mimo || true)}
[ -n "$mimo" ] && [ -x "$mimo" ] ||
  die "mimo not found: put it on the PATH or set MIMO=/path/to/mimo (a path every compute node sees)"
command -v sbatch >/dev/null 2>&1 || die "sbatch not found: run this where Slurm's commands are (a login node)"
# A task asking for more CPUs than any node of its partition has would pend for ever, silently.
cpus=1 part= prev=
for o in "$@"; do
  case $prev in -c) cpus=$o ;; -p) part=$o ;; esac
  case $o in
    --cpus-per-task=*) cpus=${o#*=} ;;
    -c?*) cpus=${o#-c} ;;
    --partition=*) part=${o#*=} ;;
    -p?*) part=${o#-p} ;;
  esac
  prev=$o
done
most=$(sinfo -h -o %c ${part:+-p "$part"} 2>/dev/null | tr -dc '0-9\n' | sort -n | tail -n 1 || true)
if [[ $cpus =~ ^[0-9]+$ ]] && [ -n "$most" ] && [ "$cpus" -gt "$most" ]; then
  die "--cpus-per-task=$cpus: the largest node of partition ${part:-(default)} has $most CPUs; the tasks would pend for ever"
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
plan=$(realpath "$plan")
out=$(realpath -m "$out")
mimo=$(realpath "$mimo")
# Check the plan and create (or check) the study directory before anything is queued: a bad plan
# or an OUT that holds something else stops here, with mimo's error and its exit status.
"$mimo" study "$plan" --out "$out" --init --quiet
mkdir -p "$out/logs"
array=$(sbatch --parsable --array="0-$((shards - 1))" --output="$out/logs/shard-%a-job-%A.out" \
  --export="ALL,MIMO=$mimo" "$@" "$here/study.sbatch" "$plan" "$out" "$shards")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$out/logs/merge-job-%j.out" --export="ALL,MIMO=$mimo" "$@" "$here/merge.sbatch" "$plan" "$out")
merge=${merge%%;*}
echo "array job $array ($shards shards), merge job $merge"
echo "follow: squeue -j $array,$merge; mimo study $plan --out $out --status; logs in $out/logs/"

#!/usr/bin/env bash
# Run a mimo study on Kubernetes: the plan as a ConfigMap, study.yaml (the claim and the Indexed
# Job), a wait that ends as soon as the Job is Complete or Failed, then merge-job.yaml and the same
# wait. Uses the current kubectl context and namespace. See examples/kubernetes/README.md.
#
#   examples/kubernetes/run.sh PLAN [TIMEOUT_S]
set -euo pipefail
die() {
  echo "error: $*" >&2
  exit 2
}
[ $# -ge 1 ] && [ $# -le 2 ] || die "expected PLAN [TIMEOUT_S] (usage: run.sh PLAN [TIMEOUT_S])"
plan=$1 timeout_s=${2:-86400}
[ -f "$plan" ] || die "$plan: no such plan file"
[[ $timeout_s =~ ^[1-9][0-9]*$ ]] || die "TIMEOUT_S: expected whole seconds, got '$timeout_s'"
command -v kubectl >/dev/null 2>&1 || die "kubectl not found"
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

# Wait until job $1 is Complete (0) or Failed (1), at most $timeout_s seconds (1).
wait_job() {
  local job=$1 t0 conds
  t0=$(date +%s)
  while :; do
    conds=$(kubectl get job "$job" -o jsonpath='{range .status.conditions[?(@.status=="True")]}{.type} {end}')
    case " $conds " in
      *" Complete "*) return 0 ;;
      *" Failed "*)
        echo "error: job $job failed ($conds); see kubectl describe job $job, kubectl logs -l job-name=$job" >&2
        return 1 ;;
    esac
    if [ $(($(date +%s) - t0)) -ge "$timeout_s" ]; then
      echo "error: job $job not finished after $timeout_s s" >&2
      return 1
    fi
    sleep 10
  done
}

kubectl create configmap mimo-plan --from-file=plan.toml="$plan" --dry-run=client -o yaml | kubectl apply -f -
# A Job's spec cannot change: a study run again (after a failure) starts a new Job; the runs
# already on the volume are kept and only the unfinished ones run.
kubectl delete job mimo-study --ignore-not-found
kubectl apply -f "$here/study.yaml"
wait_job mimo-study
kubectl delete job mimo-merge --ignore-not-found
kubectl apply -f "$here/merge-job.yaml"
wait_job mimo-merge
kubectl logs job/mimo-merge

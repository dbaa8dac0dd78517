#!/usr/bin/env python3
"""Check examples/kubernetes without a cluster: every YAML document parses (PyYAML), and the
parts agree with each other and with mimo — the Indexed Job's completions equal the N of its
--shard argument, the index comes from the Job's completion index, the study fails fast
(per-index retries, no failed index tolerated, bad input not retried), the claim is
ReadWriteMany and is the one both Jobs mount, the merge Job merges the same plan and directory
with the same image, run.sh applies both and waits on their names, and the image is Debian slim
with the binary copied in. Prints one line per check; exits 1 on the first failure.

    python3 scripts/check_kubernetes.py
"""

import pathlib
import re
import sys

import yaml

ROOT = pathlib.Path(__file__).resolve().parent.parent / "examples" / "kubernetes"


def check(ok, what):
    if not ok:
        print(f"check_kubernetes: FAILED: {what}", file=sys.stderr)
        sys.exit(1)
    print(f"check_kubernetes: ok: {what}")


def docs(name):
    with open(ROOT / name, encoding="utf-8") as f:
        return [d for d in yaml.safe_load_all(f) if d is not None]


def by_kind(ds, kind):
    return [d for d in ds if d.get("kind") == kind]


def container(job):
    cs = job["spec"]["template"]["spec"]["containers"]
    check(len(cs) == 1, f"job {job['metadata']['name']}: one container")
    return cs[0]


def option(args, flag):
    check(flag in args, f"{flag} in {args}")
    return args[args.index(flag) + 1]


def volumes(job):
    return {v["name"]: v for v in job["spec"]["template"]["spec"]["volumes"]}


def main():
    study = docs("study.yaml")
    merge = docs("merge-job.yaml")
    check(len(study) == 2 and len(merge) == 1, "study.yaml: a claim and a Job; merge-job.yaml: a Job")
    (pvc,) = by_kind(study, "PersistentVolumeClaim")
    (job,) = by_kind(study, "Job")
    (mjob,) = by_kind(merge, "Job")
    check(pvc["spec"]["accessModes"] == ["ReadWriteMany"], "the claim is ReadWriteMany (every pod mounts it)")

    spec = job["spec"]
    check(spec["completionMode"] == "Indexed", "the study Job is Indexed")
    c = container(job)
    env = {e["name"]: e for e in c["env"]}
    n = int(env["SHARDS"]["value"])
    check(spec["completions"] == n, f"completions ({spec['completions']}) equal SHARDS ({n})")
    check(1 <= spec["parallelism"] <= n, "parallelism between 1 and N")
    field = env["SHARD"]["valueFrom"]["fieldRef"]["fieldPath"]
    check(field == "metadata.annotations['batch.kubernetes.io/job-completion-index']", "K is the completion index")
    args = c["args"]
    check(args[0] == "study" and c.get("command") is None, "the image's entrypoint runs `mimo study`")
    check(option(args, "--shard") == "$(SHARD)/$(SHARDS)", "--shard K/N from the two variables")
    threads = int(option(args, "--threads"))
    check(str(threads) == str(c["resources"]["requests"]["cpu"]), "--threads equals the CPUs requested")
    check(spec["template"]["spec"]["restartPolicy"] == "Never", "pods are not restarted in place")
    check(spec["backoffLimitPerIndex"] >= 0 and spec["maxFailedIndexes"] == 0, "an index out of retries fails the Job")
    rules = spec["podFailurePolicy"]["rules"]
    check(
        any(r["action"] == "FailIndex" and 2 in r["onExitCodes"]["values"] for r in rules),
        "exit status 2 (bad input) is not retried",
    )

    mc = container(mjob)
    margs = mc["args"]
    check("--merge" in margs and margs[1] == args[1], "the merge Job merges the same plan")
    check(option(margs, "--out") == option(args, "--out"), "... into the same directory")
    check(mc["image"] == c["image"], "... with the same image")
    check(mjob["spec"]["completions"] == 1, "one merge")
    for j in (job, mjob):
        v = volumes(j)
        check(v["studies"]["persistentVolumeClaim"]["claimName"] == pvc["metadata"]["name"], "the Jobs mount the claim")
        mounts = {m["name"]: m["mountPath"] for m in container(j)["volumeMounts"]}
        check(option(args, "--out").startswith(mounts["studies"] + "/"), "--out is on the shared volume")
        check(args[1].startswith(mounts["plan"] + "/"), "the plan is the mounted ConfigMap")

    run = (ROOT / "run.sh").read_text(encoding="utf-8")
    cm = volumes(job)["plan"]["configMap"]["name"]
    check(f"create configmap {cm} " in run, f"run.sh creates the ConfigMap {cm}")
    for name in (job["metadata"]["name"], mjob["metadata"]["name"]):
        check(f"wait_job {name}" in run, f"run.sh waits on {name}")
    for f in ("study.yaml", "merge-job.yaml"):
        check(f'"$here/{f}"' in run, f"run.sh applies {f}")

    docker = (ROOT / "Dockerfile").read_text(encoding="utf-8")
    check(re.search(r"^FROM debian:bookworm-slim$", docker, re.M) is not None, "the image is Debian 12 slim")
    check(re.search(r"^COPY mimo /usr/local/bin/mimo$", docker, re.M) is not None, "with the binary copied in")
    check(re.search(r'^ENTRYPOINT \["mimo"\]$', docker, re.M) is not None, "and mimo as its entrypoint")

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    check("1.29" in readme and "no Kubernetes cluster" in readme, "the README states the version and what was tried")
    print("check_kubernetes: every check passed")


if __name__ == "__main__":
    main()

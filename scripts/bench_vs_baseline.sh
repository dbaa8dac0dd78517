#!/usr/bin/env bash
# Scenario 7, 10 × 1000 s, simulate + score (with charts) of two release binaries, alternating
# round by round on the same machine (issue 38's ratio goal: the baseline is the release build of
# 5122fef: `git worktree add ../base 5122fef && (cd ../base && cargo build --release)`).
#
#   BASE=../base/target/release/mimo NEW=target/release/mimo bash scripts/bench_vs_baseline.sh [ROUNDS]
#
# Prints, per round and binary, the wall and user seconds of each command and the load average.
set -euo pipefail
: "${BASE:?set BASE to the baseline binary}" "${NEW:?set NEW to the binary measured}"
rounds=${1:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for r in $(seq 1 "$rounds"); do
  for b in "$BASE" "$NEW"; do
    d="$work/run"
    rm -rf "$d"
    s=$({ /usr/bin/time -f "%e %U" "$b" simulate --scenario 7 --runs 10 --out "$d" --quiet; } 2>&1 | tail -1)
    c=$({ /usr/bin/time -f "%e %U" "$b" score "$d" --quiet; } 2>&1 | tail -1)
    echo "round $r $b simulate(wall user) $s score(wall user) $c load $(cut -d' ' -f1 /proc/loadavg)"
  done
done

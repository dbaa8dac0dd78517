#!/usr/bin/env bash
# End-to-end benchmark of the pipeline on a standard scenario: wall time and peak memory of
# `mimo simulate`, `mimo track` and `mimo score` (release build). Per-stage figures of the radar
# model and the closed loop come from `cargo bench -p mimo-radar` and `cargo bench -p mimo-sim`.
#
#   scripts/bench.sh [SCENARIO] [RUNS]      (default: 7 10)
set -euo pipefail
cd "$(dirname "$0")/.."
scenario="${1:-7}"
runs="${2:-10}"
out="runs/bench-s${scenario}"
cargo build --release -q -p mimo-cli
mimo=target/release/mimo
peak() { # run a command, print its wall time and peak RSS
  local log
  log=$(mktemp)
  local t0=$(date +%s.%N)
  if command -v /usr/bin/time >/dev/null 2>&1; then
    /usr/bin/time -v "$@" 2>"$log" >/dev/null
    local rss=$(awk -F: '/Maximum resident set size/ {gsub(/ /,"",$2); print $2}' "$log")
  else
    "$@" >/dev/null
    local rss="?"
  fi
  local t1=$(date +%s.%N)
  printf "%-60s wall %7.1f s   peak RSS %s MiB\n" "$*" "$(echo "$t1 - $t0" | bc)" "$([ "$rss" = "?" ] && echo "?" || echo $((rss / 1024)))"
  rm -f "$log"
}
peak $mimo simulate --scenario "$scenario" --runs "$runs" --out "$out" --force --quiet
peak $mimo track "$out" --from measurements --out "$out-track" --force --quiet
peak $mimo track "$out" --tracker imm --out "$out-imm" --force --quiet
peak $mimo score "$out" --quiet
peak $mimo score "$out-imm" --quiet
$mimo score "$out"

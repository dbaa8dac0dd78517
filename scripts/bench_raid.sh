#!/usr/bin/env bash
# Cost per target of the whole pipeline under a raid (docs/model.md §8.4): for each raid size N,
# one run of standard scenario SCENARIO with N raid aircraft added (`mimo simulate --raid N`,
# default test article, one thread), then `mimo score`; prints a table of N, the CPU seconds
# (user + system) of simulate and of score, the CPU per target per simulated second (targets =
# the scenario's own + N) and the peak RSS of each stage.
#
#   scripts/bench_raid.sh [N...]          (default: 32 128 512)
#
# Environment: MIMO=path/to/mimo (default target/debug/mimo: the dev profile optimises the mimo
# crates), SCENARIO (default 7), DURATION_S (default 300), SEED (default the simulator's),
# OUT=dir for the scratch runs (default a temporary directory, removed at the end).
set -euo pipefail
cd "$(dirname "$0")/.."
mimo="${MIMO:-target/debug/mimo}"
scenario="${SCENARIO:-7}"
duration="${DURATION_S:-300}"
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(32 128 512)
seed_args=()
[ -n "${SEED:-}" ] && seed_args=(--seed "$SEED")
out="${OUT:-$(mktemp -d)}"
[ -z "${OUT:-}" ] && trap 'rm -rf "$out"' EXIT
mkdir -p "$out"
export RAYON_NUM_THREADS=1
measure() { # LOG CMD...: run CMD under /usr/bin/time -v; print "cpu_s rss_mb"
  local log="$1"
  shift
  /usr/bin/time -v "$@" 2>"$log" >/dev/null || { cat "$log" >&2; exit 1; }
  awk -F': ' '/User time/ {u=$2} /System time/ {s=$2} /Maximum resident set size/ {r=$2}
    END {printf "%.2f %d\n", u + s, r / 1024}' "$log"
}
printf "%6s %8s %10s %10s %22s %12s %12s\n" N targets "sim CPU s" "score CPU s" "CPU us/(target*sim s)" "sim RSS MB" "score RSS MB"
for n in "${sizes[@]}"; do
  run="$out/raid-$n"
  read -r sim_cpu sim_rss < <(measure "$out/sim-$n.log" "$mimo" simulate --scenario "$scenario" --raid "$n" \
    --duration "$duration" --threads 1 "${seed_args[@]}" --out "$run" --force --quiet)
  read -r score_cpu score_rss < <(measure "$out/score-$n.log" "$mimo" score "$run")
  targets=$(jq '.scenario.resolved.targets | length' "$run/manifest.json")
  per=$(echo "($sim_cpu + $score_cpu) * 1000000 / ($targets * $duration)" | bc -l)
  printf "%6d %8d %10.2f %10.2f %22.1f %12d %12d\n" "$n" "$targets" "$sim_cpu" "$score_cpu" "$per" "$sim_rss" "$score_rss"
  [ -z "${OUT:-}" ] && rm -rf "$run"
done

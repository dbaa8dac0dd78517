#!/usr/bin/env bash
# End-to-end benchmark of the pipeline on a standard scenario: for each stage (`mimo simulate`,
# `mimo track --from measurements`, `mimo score`) its wall time, peak RSS, dwells/s and
# measurements/s, printed and written to reports/bench.json. Per-stage figures of the radar model
# and the closed loop come from `cargo bench -p mimo-radar` and `cargo bench -p mimo-sim`.
#
#   scripts/bench.sh [SCENARIO] [RUNS] [DURATION_S]      (default: 7 10 and the scenario's duration)
#
# MIMO=path/to/mimo uses that binary (e.g. MIMO=target/debug/mimo for the dev build, which is
# what the shared machine can build in minutes); without it a release build is made and used.
# OUT=dir sets where the recordings go (default runs/bench-sSCENARIO).
set -euo pipefail
cd "$(dirname "$0")/.."
scenario="${1:-7}"
runs="${2:-10}"
duration="${3:-}"
out="${OUT:-runs/bench-s${scenario}}"
if [ -z "${MIMO:-}" ]; then
  cargo build --release -q -p mimo-cli
  MIMO=target/release/mimo
fi
mimo="$MIMO"
profile="$(case "$mimo" in *release*) echo release ;; *debug*) echo dev ;; *) echo unknown ;; esac)"
dur_args=()
[ -n "$duration" ] && dur_args=(--duration "$duration")
rows() { # total rows of a table in a run directory's manifest
  jq "[.tables.\"$2\"[]?.rows] | add // 0" "$1/manifest.json"
}
stages=()
stage() { # NAME DWELLS MEASUREMENTS CMD...: run CMD, print and record wall time and peak RSS
  local name="$1" dwells="$2" meas="$3"
  shift 3
  local log t0 t1 wall rss
  log=$(mktemp)
  t0=$(date +%s.%N)
  /usr/bin/time -v "$@" 2>"$log" >/dev/null
  t1=$(date +%s.%N)
  wall=$(echo "$t1 - $t0" | bc)
  rss=$(awk -F: '/Maximum resident set size/ {gsub(/ /,"",$2); print int($2 / 1024)}' "$log")
  rm -f "$log"
  local dps mps
  dps=$(echo "$dwells / $wall" | bc)
  mps=$(echo "$meas / $wall" | bc)
  printf "%-10s wall %8.1f s   peak RSS %6d MiB   %9d dwells/s   %8d measurements/s\n" \
    "$name" "$wall" "$rss" "$dps" "$mps"
  stages+=("$(jq -n --arg stage "$name" --arg cmd "$*" --argjson wall "$wall" --argjson rss "$rss" \
    --argjson dwells "$dwells" --argjson meas "$meas" \
    '{stage: $stage, command: $cmd, wall_s: $wall, peak_rss_mib: $rss, dwells: $dwells,
      measurements: $meas, dwells_per_s: ($dwells / $wall), measurements_per_s: ($meas / $wall)}')")
}

# Simulate first (its counts come from the manifest it writes).
log=$(mktemp)
t0=$(date +%s.%N)
/usr/bin/time -v "$mimo" simulate --scenario "$scenario" --runs "$runs" "${dur_args[@]}" --out "$out" --force --quiet \
  2>"$log" >/dev/null
t1=$(date +%s.%N)
dwells=$(rows "$out" dwells)
meas=$(rows "$out" measurements)
sim_wall=$(echo "$t1 - $t0" | bc)
sim_rss=$(awk -F: '/Maximum resident set size/ {gsub(/ /,"",$2); print int($2 / 1024)}' "$log")
rm -f "$log"
printf "%-10s wall %8.1f s   peak RSS %6d MiB   %9d dwells/s   %8d measurements/s\n" \
  simulate "$sim_wall" "$sim_rss" "$(echo "$dwells / $sim_wall" | bc)" "$(echo "$meas / $sim_wall" | bc)"
stages+=("$(jq -n --arg cmd "$mimo simulate --scenario $scenario --runs $runs ${dur_args[*]} --out $out --force --quiet" \
  --argjson wall "$sim_wall" --argjson rss "$sim_rss" --argjson dwells "$dwells" --argjson meas "$meas" \
  '{stage: "simulate", command: $cmd, wall_s: $wall, peak_rss_mib: $rss, dwells: $dwells,
    measurements: $meas, dwells_per_s: ($dwells / $wall), measurements_per_s: ($meas / $wall)}')")

stage track "$dwells" "$meas" "$mimo" track "$out" --from measurements --out "$out-track" --force --quiet
stage score "$dwells" "$meas" "$mimo" score "$out" --no-charts --quiet

size_mb() { du -sm "$1" | cut -f1; }
mkdir -p reports
jq -n --arg scenario "$scenario" --argjson runs "$runs" --arg profile "$profile" --arg binary "$mimo" \
  --arg date "$(date -u +%Y-%m-%dT%H:%M:%SZ)" --arg commit "$(git rev-parse --short HEAD 2>/dev/null || echo unknown)" \
  --argjson nproc "$(nproc)" --arg load "$(cut -d' ' -f1-3 /proc/loadavg)" \
  --argjson rec_mb "$(size_mb "$out")" --argjson dwells_mb "$(size_mb "$out/dwells")" \
  --argjson stages "$(printf '%s\n' "${stages[@]}" | jq -s .)" \
  '{scenario: $scenario, runs: $runs, build_profile: $profile, binary: $binary, date: $date, commit: $commit,
    cores: $nproc, load_average: $load, recording_mb: $rec_mb, dwells_table_mb: $dwells_mb, stages: $stages}' \
  >reports/bench.json
echo "recording $(size_mb "$out") MB (dwells table $(size_mb "$out/dwells") MB); wrote reports/bench.json"

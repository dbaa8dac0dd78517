#!/usr/bin/env bash
# The README's screenshot of the run viewer: scenario 7, run 0, at t = 250 s, with a bistatic
# (MIMO) measurement selected (its 1σ/3σ ellipsoid and sensor lines drawn). Uses the 1000-s run
# of scripts/plot_open_time.sh (runs/plot-s7, made here when missing), headless Chromium driven by
# scripts/plot_screenshot.mjs (node).
#
#   scripts/plot_screenshot.sh            writes reports/plot-s7-t250.png
set -euo pipefail
cd "$(dirname "$0")/.."
mimo=target/debug/mimo
chromium="${MIMO_CHROMIUM:-/usr/bin/chromium}"
run=runs/plot-s7
[ -x "$mimo" ] || cargo build --workspace --bins -q
if [ ! -f "$run/manifest.json" ] || [ ! -f "$run/score/summary.json" ]; then
  "$mimo" simulate --scenario 7 --runs 1 --duration 1000 --out "$run" --force --quiet
  "$mimo" score "$run" --no-charts --quiet
fi
"$mimo" plot "$run" --out "$run/view-t250.html" --force --quiet
node scripts/plot_screenshot.mjs "$chromium" "file://$(realpath "$run/view-t250.html")#t=250&select=mimo" \
  "$PWD/reports/plot-s7-t250.png" 1400 1000

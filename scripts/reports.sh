#!/usr/bin/env bash
# Regenerate reports/: reference results of the standard scenarios (summary + charts) with the
# default test article.
#
#   scripts/reports.sh [RUNS] [SCENARIOS...]      (default: 2 runs of scenarios 1-7)
#   MIMO=target/debug/mimo scripts/reports.sh
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-2}"
shift || true
scenarios=("$@")
[ ${#scenarios[@]} -gt 0 ] || scenarios=(1 2 3 4 5 6 7)
# MIMO=path/to/mimo uses an existing binary (e.g. target/debug/mimo: the dev build optimises the
# simulation and scoring crates too).
if [[ -z "${MIMO:-}" ]]; then
  cargo build --release -q --workspace --bins
  MIMO=target/release/mimo
fi
mimo="$MIMO"
mkdir -p reports
# The map is this script's own output: drawn afresh (a map from before maps carried mimo's mark
# would be refused even with --force).
rm -f reports/geometry.png
$mimo scenarios --map reports/geometry.png >/dev/null
cp reports/geometry.png scenarios/geometry.png
for s in "${scenarios[@]}"; do
  out="runs/ref-s${s}"
  $mimo simulate --scenario "$s" --runs "$runs" --out "$out" --force --quiet
  $mimo score "$out" --quiet
  rm -rf "reports/s${s}"
  mkdir -p "reports/s${s}"
  cp "$out/score/summary.json" "reports/s${s}/"
  cp "$out"/score/charts/*.png "reports/s${s}/"
done
{
  echo "# Reference results"
  echo
  echo "Made by \`scripts/reports.sh $runs ${scenarios[*]}\` (default test article, seed 20261122, $runs runs of 1000 s)."
  echo
  echo "| scenario | completeness | challenge met | redundant | spurious | breaks/run | switches/run | position RMSE (m) | energy/run (J) | TA energy/run (J) | dwell time/run (s) |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
  for s in "${scenarios[@]}"; do
    python3 - "reports/s${s}/summary.json" "$s" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); t = d["track"]; u = d["usage"]
f = lambda x, k=4: "n/a" if x is None else f"{x:.{k}f}"
print(f"| {sys.argv[2]} | {f(t['completeness'])} | {d['challenge']['met']} | {f(t['redundant_ratio'])} | {f(t['spurious_ratio'])} | {t['breaks']:.1f} | {t['switches']:.1f} | {f(t['position_rmse_m'],1)} | {u['total_energy_j']:.0f} | {u['ta_energy_j']:.0f} | {u['total_dwell_time_s']:.1f} |")
PY
  done
} > reports/README.md
echo "reports/ regenerated"

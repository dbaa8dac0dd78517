#!/usr/bin/env bash
# Regenerate the shipped studies' results under reports/studies/: run each plan of studies/ with
# a release build, then copy its summary table, charts and report (the run directories stay in
# runs/studies/, which is not committed). Prints each study's wall time.
#
#   bash scripts/studies.sh              # both studies
#   bash scripts/studies.sh stability    # one of them
#   MIMO=target/debug/mimo bash scripts/studies.sh
set -euo pipefail
cd "$(dirname "$0")/.."
# MIMO=path/to/mimo uses an existing binary (the dev build optimises the simulation crates too).
if [[ -z "${MIMO:-}" ]]; then
  cargo build --release --locked --workspace --bins
  MIMO=target/release/mimo
fi
for name in "${@:-challenge stability}"; do
  for study in $name; do
    out=runs/studies/$study
    start=$(date +%s)
    "$MIMO" study "studies/$study.toml" --out "$out" --force --quiet
    echo "$study: $(( $(date +%s) - start )) s wall on $(nproc) cores"
    dest=reports/studies/$study
    rm -rf "$dest"
    mkdir -p "$dest"
    cp -r "$out/charts" "$out/report.md" "$out/summary.parquet" "$out/results.parquet" "$out/challenge.parquet" \
      "$out/challenge_ratios.parquet" "$out/plan.toml" "$dest/"
  done
done

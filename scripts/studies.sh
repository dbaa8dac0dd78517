#!/usr/bin/env bash
# Regenerate the shipped studies' results under reports/studies/: run each plan of studies/ with
# a release build, then copy its study tables, charts and report and write MADE_BY.md (the
# commit, the command, the time). The run directories stay in runs/studies/, which is not
# committed; by default a study keeps only its runs' records there (docs/studies.md).
#
#   bash scripts/studies.sh              # the challenge, stability, registration and budget7 studies
#   bash scripts/studies.sh stability    # one of them
#   MIMO=target/debug/mimo bash scripts/studies.sh
set -euo pipefail
cd "$(dirname "$0")/.."
# MIMO=path/to/mimo uses an existing binary (the dev build optimises the simulation crates too).
if [[ -z "${MIMO:-}" ]]; then
  cargo build --release --locked --workspace --bins
  MIMO=target/release/mimo
fi
commit=$(git rev-parse --short HEAD)
if [[ -n "$(git status --porcelain -- crates Cargo.toml Cargo.lock studies)" ]]; then
  commit="$commit with uncommitted changes to crates/ or studies/"
fi
for name in "${@:-challenge stability registration budget7}"; do
  for study in $name; do
    out=runs/studies/$study
    mkdir -p runs/studies
    load_before=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo "?")
    start=$(date +%s)
    timing=""
    if [[ -x /usr/bin/time ]]; then
      /usr/bin/time -f "%U s user, %S s system, peak %M KB" -o "$out.time" \
        "$MIMO" study "studies/$study.toml" --out "$out" --force --quiet
      timing=" ($(cat "$out.time"))"
    else
      "$MIMO" study "studies/$study.toml" --out "$out" --force --quiet
    fi
    wall=$(( $(date +%s) - start ))
    echo "$study: $wall s wall on $(nproc) cores$timing"
    dest=reports/studies/$study
    # The page's screenshot (report-html.png) is made apart and kept.
    shot=""
    if [[ -f "$dest/report-html.png" ]]; then shot=$(mktemp) && cp "$dest/report-html.png" "$shot"; fi
    rm -rf "$dest"
    mkdir -p "$dest"
    if [[ -n "$shot" ]]; then mv "$shot" "$dest/report-html.png"; fi
    cp -r "$out/charts" "$out/report.md" "$out/report.html" "$out/summary.parquet" "$out/results.parquet" "$out/costs.parquet" \
      "$out/challenge.parquet" "$out/challenge_ratios.parquet" "$out/failure_points.parquet" "$out/plan.toml" "$dest/"
    # frontier.parquet: studies merged since the efficient frontier (docs/studies.md, "The challenge").
    if [[ -f "$out/frontier.parquet" ]]; then cp "$out/frontier.parquet" "$dest/"; fi
    runs=$(find "$out/runs" -path '*/.items/run-*.json' | wc -l)
    cat >"$dest/MADE_BY.md" <<MADE
# How these results were made

* Plan: \`studies/$study.toml\` (copied here as \`plan.toml\`), $runs runs.
* Binary: \`$MIMO\` of commit \`$commit\`.
* Command: \`bash scripts/studies.sh $study\`, which ran
  \`mimo study studies/$study.toml --out $out --force --quiet\` and copied the study tables,
  charts and report here.
* Time: $wall s wall on $(nproc) cores$timing, started $(date -u -d "@$start" '+%Y-%m-%d %H:%M UTC');
  load average $load_before before it started.
* \`crates/mimo-study/tests/shipped_studies.rs\` re-runs the cheapest item of the plan and checks
  its metrics against \`results.parquet\`, and checks \`plan.toml\` against \`studies/$study.toml\`.
MADE
  done
done

#!/usr/bin/env bash
# Open time of a study's page (report.html, docs/studies.md "The page") in headless Debian
# Chromium with the network off, driven over the DevTools protocol by scripts/plot_open_time.mjs
# (the run viewer's driver: it waits for the page's #selftest verdict). Prints the page's size,
# then per open its marks (performance.now(), ms since navigation; crates/mimo-study/assets/report.js):
# plotly.js parsed, data parsed, first render (the frontier drawn and painted), all drawn
# (failure curves and the report's tables too) and the self-test's verdict.
#
#   scripts/study_page_open_time.sh [N] [PAGE]   (default 5 opens of reports/studies/challenge/report.html)
set -euo pipefail
cd "$(dirname "$0")/.."
n="${1:-5}"
page="${2:-reports/studies/challenge/report.html}"
chromium="${MIMO_CHROMIUM:-/usr/bin/chromium}"
printf 'page %s: %s bytes\n' "$page" "$(stat -c %s "$page")"
url="file://$(realpath "$page")#selftest"
for i in $(seq 1 "$n"); do
  node scripts/plot_open_time.mjs "$chromium" "$url" 60000 | python3 -c '
import json, os, sys
r = json.loads(sys.stdin.read())
k, v = r.get("marks") or {}, r.get("verdict") or {}
k = {a: round(x) for a, x in k.items()}
print("open %s: plotly %s  data %s  first render %s  all drawn %s ms | self-test ok %s, errors %s | load %.1f" % (
    sys.argv[1], k.get("plotly_loaded_ms"), k.get("data_parsed_ms"), k.get("first_render_ms"), k.get("all_drawn_ms"),
    v.get("ok", "n/a"), len(v.get("errors", [])), os.getloadavg()[0]))
' "$i"
done

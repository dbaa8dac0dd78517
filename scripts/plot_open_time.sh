#!/usr/bin/env bash
# Open time of the run viewer (`mimo plot`, docs/design.md) in headless Debian Chromium with
# the network off, driven over the DevTools protocol by scripts/plot_open_time.mjs (node): a 1000-s scenario-7 run is simulated and scored (once, kept in runs/plot-s7),
# its page written, then opened N times from a file URL on the real clock. The page's own marks
# (performance.now(), ms since navigation; see crates/mimo-plot/assets/view.js) are printed:
# plotly.js parsed, data parsed, scene drawn, metrics panel drawn, first render (the scene's first
# WebGL frame painted; pages made before the scene was drawn first: both panels drawn), all drawn (both
# panels painted), and the mean and worst time of a 1-s slider step from the self-test.
#
#   scripts/plot_open_time.sh [N]           (default 3; uses target/debug/mimo)
#   PAGE=old.html scripts/plot_open_time.sh  measure an existing page instead
#
# Software WebGL (SwiftShader, no GPU), so figures are an upper bound for a desktop browser.
# The load average is printed: on a shared machine it moves the figures a lot.
set -euo pipefail
cd "$(dirname "$0")/.."
n="${1:-3}"
mimo=target/debug/mimo
chromium="${MIMO_CHROMIUM:-/usr/bin/chromium}"
run=runs/plot-s7
page="${PAGE:-}"
if [ -z "$page" ]; then
  [ -x "$mimo" ] || cargo build --workspace --bins -q
  if [ ! -f "$run/manifest.json" ] || [ ! -f "$run/score/summary.json" ]; then
    "$mimo" simulate --scenario 7 --runs 1 --duration 1000 --out "$run" --force --quiet
    "$mimo" score "$run" --no-charts --quiet
  fi
  page=$run/view.html
  "$mimo" plot "$run" --out "$page" --force --quiet
fi
printf 'page %s: %s bytes\n' "$page" "$(stat -c %s "$page")"
url="file://$(realpath "$page")#selftest"
for i in $(seq 1 "$n"); do
  node scripts/plot_open_time.mjs "$chromium" "$url" 90000 | python3 -c '
import json, os, sys
r = json.loads(sys.stdin.read())
k, v = r.get("marks") or {}, r.get("verdict") or {}
if "first_render_ms" not in k:
    print("open %s: no first render within 90 s" % sys.argv[1]); sys.exit(0)
k = {a: round(x) for a, x in k.items()}
rnd = lambda x: round(x) if x else "n/a"
print("open %s: first render %5d ms | plotly %5d  data %5d  scene %5d  metrics %5d  all drawn %5d | slider step mean %s worst %s ms | self-test ok %s | load %.1f" % (
    sys.argv[1], k["first_render_ms"], k["plotly_loaded_ms"], k["data_parsed_ms"], k.get("scene_ms", -1), k.get("metrics_ms", -1),
    k.get("all_drawn_ms", k["first_render_ms"]), rnd(v.get("step_render_ms")), rnd(v.get("step_worst_ms")),
    v.get("ok", "n/a"), os.getloadavg()[0]))
' "$i"
done

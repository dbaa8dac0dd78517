#!/usr/bin/env bash
# Cost per target of the whole pipeline under a raid (docs/model.md §8.4): for each raid size N,
# one run of standard scenario SCENARIO with N raid aircraft added (`mimo simulate --raid N`,
# default test article, one thread), then `mimo score`; prints a table of N, the CPU seconds
# (user + system) of simulate and of score, the CPU per target per simulated second (targets =
# the scenario's own + N) and the peak RSS of each stage.
#
#   scripts/bench_raid.sh [N...]          (default: 32 128 512)
#
# With ROUNDS=R (default 1) the sizes are measured R times, alternating (N1 N2 … N1 N2 …), and a
# last table gives each column's median over the rounds and, for every N after the first, the
# ratio of its median CPU per target to the first N's, for simulate and score each (issue 38's
# goal: 512 within 1.5× of 32): one run's CPU time moves by ±20 % on a loaded machine.
#
# With COUNT=instructions each stage is counted instead of timed: the instructions it executes
# (valgrind's callgrind, `Collected`), which do not depend on the machine's load, so one round
# decides the ratio; the CPU columns then hold billions of instructions and the RSS columns 0.
# Counting runs about 50 times slower than the binary (512 aircraft: about 20 minutes). It sees
# no cache misses, which grow with the number of targets: the timed figure stays the goal's.
#
# Environment: MIMO=path/to/mimo (default target/debug/mimo: the dev profile optimises the mimo
# crates), SCENARIO (default 7), DURATION_S (default 300), SEED (default the simulator's),
# OUT=dir for the scratch runs (default a temporary directory, removed at the end).
set -euo pipefail
cd "$(dirname "$0")/.."
mimo="${MIMO:-target/debug/mimo}"
scenario="${SCENARIO:-7}"
duration="${DURATION_S:-300}"
rounds="${ROUNDS:-1}"
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(32 128 512)
seed_args=()
[ -n "${SEED:-}" ] && seed_args=(--seed "$SEED")
out="${OUT:-$(mktemp -d)}"
[ -z "${OUT:-}" ] && trap 'rm -rf "$out"' EXIT
mkdir -p "$out"
export RAYON_NUM_THREADS=1
count="${COUNT:-cpu}"
case "$count" in
  cpu) unit="CPU s" per_unit="CPU us" ;;
  instructions)
    unit="G instr" per_unit="k instr"
    command -v valgrind >/dev/null || { echo "error: COUNT=instructions needs valgrind" >&2; exit 1; }
    ;;
  *) echo "error: COUNT must be cpu or instructions, not '$count'" >&2; exit 2 ;;
esac
measure() { # LOG CMD...: run CMD under /usr/bin/time -v (or callgrind); print "cpu_s rss_mb"
  local log="$1"
  shift
  if [ "$count" = instructions ]; then
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>"$log" >/dev/null || { cat "$log" >&2; exit 1; }
    grep -o 'Collected : [0-9]*' "$log" | awk '{printf "%.4f 0\n", $3 / 1e9}'
    return
  fi
  /usr/bin/time -v "$@" 2>"$log" >/dev/null || { cat "$log" >&2; exit 1; }
  awk -F': ' '/User time/ {u=$2} /System time/ {s=$2} /Maximum resident set size/ {r=$2}
    END {printf "%.2f %d\n", u + s, r / 1024}' "$log"
}
printf "%5s %6s %8s %10s %12s %22s %12s %12s\n" round N targets "sim $unit" "score $unit" "$per_unit/(target*sim s)" "sim RSS MB" "score RSS MB"
rows="$out/rows.txt"
: >"$rows"
for r in $(seq 1 "$rounds"); do
  for n in "${sizes[@]}"; do
    run="$out/raid-$n"
    read -r sim_cpu sim_rss < <(measure "$out/sim-$n.log" "$mimo" simulate --scenario "$scenario" --raid "$n" \
      --duration "$duration" --threads 1 "${seed_args[@]}" --out "$run" --force --quiet)
    read -r score_cpu score_rss < <(measure "$out/score-$n.log" "$mimo" score "$run")
    targets=$(jq '.scenario.resolved.targets | length' "$run/manifest.json")
    per=$(echo "($sim_cpu + $score_cpu) * 1000000 / ($targets * $duration)" | bc -l)
    printf "%5d %6d %8d %10.2f %12.2f %22.1f %12d %12d\n" "$r" "$n" "$targets" "$sim_cpu" "$score_cpu" "$per" "$sim_rss" "$score_rss"
    echo "$n $targets $sim_cpu $score_cpu $per" >>"$rows"
    [ -z "${OUT:-}" ] && rm -rf "$run"
  done
done
if [ "$rounds" -gt 1 ]; then
  echo
  echo "medians over $rounds rounds (load average $(cut -d' ' -f1-3 /proc/loadavg) at the end):"
  awk -v order="${sizes[*]}" -v unit="$unit" -v per_unit="$per_unit" '
    function median(list,   a, k, n, t, i, j) {
      n = split(list, a, " ")
      for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
      return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
    }
    { tg[$1] = $2; sim[$1] = sim[$1] " " $3; sc[$1] = sc[$1] " " $4; per[$1] = per[$1] " " $5 }
    END {
      printf "%6s %10s %12s %22s %18s %18s %18s\n", "N", "sim " unit, "score " unit, per_unit "/(target*sim s)", "sim per target", "score per target", "total per target"
      k = split(order, ns, " ")
      for (i = 1; i <= k; i++) {
        n = ns[i]; s = median(sim[n]); c = median(sc[n]); p = median(per[n])
        if (i == 1) { s0 = s / tg[n]; c0 = c / tg[n]; p0 = p }
        printf "%6d %10.2f %12.2f %22.1f %17.2fx %17.2fx %17.2fx\n", n, s, c, p, (s / tg[n]) / s0, (c / tg[n]) / c0, p / p0
      }
    }' "$rows"
fi

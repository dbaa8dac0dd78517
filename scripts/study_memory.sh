#!/usr/bin/env bash
# A study stays flat: peak memory (/usr/bin/time -f %M) of a whole study and of its merge alone,
# and the merge's wall time, for studies of N short items each (scenario 1, 30 s, one method,
# N runs, one thread). Peak memory should not grow with N, and the merge's time should grow
# linearly. Prints one line per N and per phase.
#
#   bash scripts/study_memory.sh [N ...]        (default: 100 1000 10000; 10 000 items take a
#                                                while: about 0.1 s each on one free core)
# MIMO=path/to/mimo overrides the binary (default: the dev build of this checkout).
set -euo pipefail
cd "$(dirname "$0")/.."
mimo=${MIMO:-${CARGO_TARGET_DIR:-target}/debug/mimo}
[ -x "$mimo" ] || cargo build --bin mimo --locked --quiet
[ -x /usr/bin/time ] || { echo "error: /usr/bin/time not found (Debian: apt-get install time)" >&2; exit 2; }
work=$(mktemp -d /tmp/mimo-study-memory.XXXXXX)
trap 'rm -rf "$work"' EXIT
[ $# -gt 0 ] || set -- 100 1000 10000
for n in "$@"; do
  printf 'title = "flat %s"\nscenarios = [1]\nruns = %s\nduration_s = 30\n[[methods]]\nname = "default"\nta = "default"\n' \
    "$n" "$n" >"$work/plan$n.toml"
  /usr/bin/time -f "study of $n items: peak %M KB, %e s wall" \
    "$mimo" study "$work/plan$n.toml" --out "$work/s$n" --threads 1 --quiet
  /usr/bin/time -f "merge of $n items: peak %M KB, %e s wall" \
    "$mimo" study "$work/plan$n.toml" --out "$work/s$n" --merge --quiet
  rm -rf "$work/s$n"
done

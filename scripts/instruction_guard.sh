#!/usr/bin/env bash
# The regression guard on cost that does not depend on load (docs/decisions/0300-instruction-guard.md):
# counts the instructions (valgrind's callgrind) of `mimo simulate` and `mimo score` on one fixed
# small case — standard scenario 7, one run of 300 s, default seed, one thread — and compares them
# with the committed baseline reports/instructions.json. It fails (exit 1) when either grew by more
# than 10 %, and says so when either fell by more than that (the baseline is then worth updating).
#
#   scripts/instruction_guard.sh            measure and compare (what .ci/run runs)
#   scripts/instruction_guard.sh --update   measure and write the new baseline
#
# A change that makes simulate or score heavier on purpose updates the baseline in the same commit
# and says why in its message. The counts belong to the dev profile built without incremental
# compilation (`CARGO_INCREMENTAL=0 cargo build --bin mimo`, what .ci/run builds), the rustc and the
# valgrind of the baseline: an incremental build splits the code differently and counts more
# (simulate about 8 %, score 1.5 %), and a different rustc or valgrind may move them by a few per
# cent (the script prints both versions).
#
# Environment: MIMO=path/to/mimo (default target/debug/mimo), BASELINE (default
# reports/instructions.json), LIMIT_PCT (default 10), OUT=dir for the scratch run (default a
# temporary directory, removed at the end).
set -euo pipefail
cd "$(dirname "$0")/.."
mimo="${MIMO:-target/debug/mimo}"
baseline="${BASELINE:-reports/instructions.json}"
limit="${LIMIT_PCT:-10}"
update=0
[ "${1:-}" = "--update" ] && update=1
command -v valgrind >/dev/null || { echo "error: valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
[ -x "$mimo" ] || { echo "error: $mimo not found: build it first (cargo build --bin mimo)" >&2; exit 1; }
out="${OUT:-$(mktemp -d)}"
[ -z "${OUT:-}" ] && trap 'rm -rf "$out"' EXIT
mkdir -p "$out"
export RAYON_NUM_THREADS=1
case_args=(--scenario 7 --runs 1 --duration 300 --threads 1)

count() { # NAME CMD...: the instructions CMD executes (callgrind's "Collected")
  local name="$1"
  shift
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" >"$out/$name.out" 2>"$out/$name.log" ||
    { cat "$out/$name.log" >&2; echo "error: $name failed under valgrind" >&2; exit 1; }
  grep -o 'Collected : [0-9]*' "$out/$name.log" | awk '{print $3}'
}

sim=$(count simulate "$mimo" simulate "${case_args[@]}" --out "$out/run" --force --quiet)
score=$(count score "$mimo" score "$out/run" --threads 1 --no-charts)
rustc_v=$(rustc --version 2>/dev/null || echo unknown)
valgrind_v=$(valgrind --version)

if [ "$update" = 1 ]; then
  python3 - "$baseline" "$sim" "$score" "$rustc_v" "$valgrind_v" <<'EOF'
import json, sys
path, sim, score, rustc, valgrind = sys.argv[1:]
doc = {
    "about": "Instructions (valgrind --tool=callgrind, 'Collected') of one fixed case, compared by "
             "scripts/instruction_guard.sh; update with --update in the commit that explains why.",
    "profile": "dev, not incremental (CARGO_INCREMENTAL=0 cargo build --bin mimo, as .ci/run builds: dependencies opt-level 2, the mimo crates 3, debug assertions on)",
    "rustc": rustc,
    "valgrind": valgrind,
    "simulate_command": "mimo simulate --scenario 7 --runs 1 --duration 300 --threads 1 --out RUN --quiet",
    "score_command": "mimo score RUN --threads 1 --no-charts",
    "simulate_instructions": int(sim),
    "score_instructions": int(score),
}
with open(path, "w") as f:
    json.dump(doc, f, indent=2)
    f.write("\n")
EOF
  echo "baseline written to $baseline: simulate $sim, score $score instructions ($rustc_v; $valgrind_v)"
  exit 0
fi

[ -f "$baseline" ] || { echo "error: no baseline $baseline (run scripts/instruction_guard.sh --update)" >&2; exit 1; }
python3 - "$baseline" "$sim" "$score" "$limit" "$rustc_v" "$valgrind_v" <<'EOF'
import json, sys
path, sim, score, limit, rustc, valgrind = sys.argv[1:]
base = json.load(open(path))
limit = float(limit)
failed = False
for name, got in (("simulate", int(sim)), ("score", int(score))):
    want = base[f"{name}_instructions"]
    change = 100.0 * (got - want) / want
    verdict = "ok"
    if change > limit:
        verdict = f"FAIL: more than {limit:g} % heavier"
        failed = True
    elif change < -limit:
        verdict = f"lighter by more than {limit:g} %: worth a new baseline"
    print(f"{name:8s} {got:>15,d} instructions, baseline {want:>15,d} ({change:+.1f} %): {verdict}")
for key, now in (("rustc", rustc), ("valgrind", valgrind)):
    if base.get(key) != now:
        print(f"note: the baseline was counted with {base.get(key)}, this count with {now}")
if failed:
    print(f"\nIf the extra cost is intended, run `scripts/instruction_guard.sh --update` and commit "
          f"{path} in the same commit that explains the change (docs/decisions/0300-instruction-guard.md).")
    sys.exit(1)
EOF

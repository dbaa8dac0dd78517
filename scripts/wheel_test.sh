#!/usr/bin/env bash
# The wheel (pyproject.toml at the repository root): build it with maturin (from PyPI, into a
# throw-away virtual environment), install it in a fresh virtual environment with nothing else
# (numpy comes from PyPI as its one dependency), then — with no compiler on the PATH — run a
# closed loop with the installed package's Python test article and score it.
#
#   bash scripts/wheel_test.sh            # dev profile: reuses the cargo target dir of the tests
#   PROFILE=release bash scripts/wheel_test.sh
#
# Prints the time of each step. Called by .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."
profile=${PROFILE:-dev}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
t0=$(date +%s%N)
step() {
  local ms=$(( ($(date +%s%N) - t0) / 1000000 ))
  printf 'wheel_test: %-60s %4d.%01d s\n' "$1" $((ms / 1000)) $(((ms % 1000) / 100))
  t0=$(date +%s%N)
}

python3 -m venv "$tmp/build"
"$tmp/build/bin/python" -m pip install --quiet "maturin>=1.9,<2.0"
step "maturin from PyPI"
"$tmp/build/bin/maturin" build --profile "$profile" --locked --out "$tmp/wheels" >"$tmp/build.log" 2>&1 \
  || { cat "$tmp/build.log"; exit 1; }
wheel=$(ls "$tmp"/wheels/mimo-*.whl)
step "maturin build --profile $profile ($(basename "$wheel"))"

# One wheel: the binary as a script and the package, nothing else.
python3 - "$wheel" <<'PY'
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
bins = [n for n in names if n.endswith(".data/scripts/mimo")]
assert len(bins) == 1, f"no mimo binary in the wheel: {names}"
assert "mimo_ta/__init__.py" in names and "mimo_ta/stonesoup/model.py" in names, names
assert not any(n.startswith(("tests/", "examples/")) for n in names), names
PY

python3 -m venv "$tmp/env"
"$tmp/env/bin/python" -m pip install --quiet "$wheel"
step "fresh venv + pip install the wheel (and numpy)"

# From here: only the environment and the system's /usr/bin:/bin, no cargo, no rustc.
run() { env -i HOME="$tmp" PATH="$tmp/env/bin:/usr/bin:/bin" "$@"; }
run sh -c '! command -v cargo >/dev/null && ! command -v rustc >/dev/null' || { echo "a compiler is on the PATH"; exit 1; }
[[ "$(run sh -c 'command -v mimo')" == "$tmp/env/bin/mimo" ]] || { echo "mimo is not the environment's"; exit 1; }
[[ "$(run python -m mimo_ta which)" == "$tmp/env/bin/mimo" ]] || { echo "mimo_ta.binary found another mimo"; exit 1; }
# Stripped: no symbol table in the ELF file.
run python - "$tmp/env/bin/mimo" <<'PY'
import struct, sys
d = open(sys.argv[1], "rb").read()
assert d[:4] == b"\x7fELF" and d[4] == 2, "not a 64-bit ELF"
shoff, = struct.unpack_from("<Q", d, 0x28)
shentsize, shnum, shstrndx = struct.unpack_from("<HHH", d, 0x3A)
sections = [struct.unpack_from("<IIQQQQ", d, shoff + i * shentsize) for i in range(shnum)]
strtab = sections[shstrndx]
names = [d[strtab[4] + s[0]:].split(b"\0", 1)[0] for s in sections]
assert b".symtab" not in names, "the mimo binary is not stripped"
PY

cd "$tmp"
run mimo simulate --scenario 1 --duration 120 --ta-cmd "python -m mimo_ta simple" --quiet --out "$tmp/run"
run mimo score "$tmp/run" --no-charts --quiet
step "mimo simulate (scenario 1, 120 s, python -m mimo_ta simple) + score"
run python - "$tmp/run/score/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
def find(v, key):
    if isinstance(v, dict):
        if isinstance(v.get(key), (int, float)):
            return v[key]
        return next((x for x in (find(w, key) for w in v.values()) if x is not None), None)
    if isinstance(v, list):
        return next((x for x in (find(w, key) for w in v) if x is not None), None)
    return None
c = find(s, "completeness")
print(f"wheel_test: completeness {c:.4f} (scenario 1, 120 s, the installed simple test article)")
assert c is not None and c >= 0.9, c
PY
echo "wheel_test: ok"

#!/usr/bin/env bash
# Where moving frames have no speed, gvs replay, gvs eval, the eval plot and
# gvs snapshot say why, from the method words and the truth and exposure:
# at 60 km/h (sine) a 3 ms exposure draws a 500 px streak, too long; 100 us
# one of 17 px, too short; at 800 us (133 px) every speed is measured and
# nothing is said.
# usage: cli_speed_gaps.sh GVS_BINARY GVS_PLOT_PY
set -euo pipefail
gvs=$1
plot_py=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

run() {  # run NAME SIM_ARGS...: sim, replay, eval --plot; outputs in $work/NAME.*
  local name=$1; shift
  "$gvs" sim --scenario sine --seconds 0.5 --seed 2 "$@" --out "$work/$name" > /dev/null
  "$gvs" replay "$work/$name" --out "$work/$name.csv" > "$work/$name.replay"
  PLOT_DESCRIPTION="$work/$name.plot.json" GVS_PLOT_SCRIPT="$work/describe_plot.py" \
    "$gvs" eval "$work/$name" "$work/$name.csv" --plot "$work/$name.png" > "$work/$name.eval"
}
# The plot script as gvs eval calls it, with --describe recording the figure.
cat > "$work/describe_plot.py" <<PY
import os, subprocess, sys
out = subprocess.run(["/usr/bin/python3", "$plot_py", *sys.argv[1:], "--describe"],
                     check=True, capture_output=True, text=True).stdout
open(os.environ["PLOT_DESCRIPTION"], "w").write(out)
PY

# 1. Fixed 3 ms: too long, and what measures it.
run long --exposure fixed --exposure-us 3000
cat "$work/long.eval"
for f in long.replay long.eval; do
  grep -q '^no speed on 30 of 30 moving frames:' "$work/$f" || fail "$f does not say how many frames lack a speed"
  grep -q '= 60 km/h x 3000 us / 0.1 mm/px, is 500 px, longer than this 512x384 frame measures' "$work/$f" \
    || fail "$f does not give the streak's length from the truth and exposure"
  grep -q -- '--exposure double-pulse' "$work/$f" || fail "$f does not name the mode that measures it"
  grep -Eq '\((([0-9]+ )?(streak|blur)-[a-z]+(, )?)+; frames 0-29\)' "$work/$f" || fail "$f does not name the methods"
done
/usr/bin/python3 - "$work/long.plot.json" <<'PY' || fail "the plot does not say why"
import json, sys
d = json.load(open(sys.argv[1]))
text = " ".join(d["speed_note"].split())  # as one line: the plot wraps it
assert "no speed on 30 of 30 moving frames" in text and "500 px, longer than" in text, text
speed = [p for p in d["panels"] if p["title"].startswith("speed error")][0]
assert "no data" in speed["title"], speed
PY
"$gvs" snapshot --dataset "$work/long" --frame 20 --out "$work/snap.png" > "$work/snap.txt"
grep -Eq '^no speed: (streak|blur)-[a-z]+: the streak, .* is 500 px, longer than' "$work/snap.txt" \
  || fail "gvs snapshot does not say why: $(cat "$work/snap.txt")"

# 2. 100 us: too short, and what measures it.
run short --exposure fixed --exposure-us 100
grep -q 'is 17 px, shorter than the 30 px' "$work/short.eval" || fail "too short not said: $(cat "$work/short.eval")"
grep -q -- '--exposure adaptive' "$work/short.eval" || fail "too short: no mode named"

# 3. 800 us: every speed measured, nothing to explain.
run fits --exposure fixed --exposure-us 800
grep -q '^all .* 30/30 |' "$work/fits.eval" || fail "800 us should measure every speed: $(cat "$work/fits.eval")"
! grep -q 'no speed' "$work/fits.eval" "$work/fits.replay" || fail "a reason printed though every frame has a speed"
/usr/bin/python3 -c "import json,sys; assert json.load(open(sys.argv[1]))['speed_note'] == \"\"" "$work/fits.plot.json" \
  || fail "the plot carries a note though every frame has a speed"
echo "OK speed gaps"

#!/usr/bin/env bash
# gvs eval --plot on a small simulated run where the estimator measures a
# yaw rate (crawl: pairs at walking pace, turning): the figure has direction,
# speed and yaw-rate panels with truth and estimate, the yaw-rate panel holds
# the estimates' yaw rates, its histogram their errors, and no legend covers
# a panel. The figure is read back from gvs_plot.py --describe.
# usage: eval_plot.sh GVS_BINARY GVS_PLOT_PY
set -euo pipefail
gvs=$1
plot_py=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cat > "$work/describe_plot.py" <<PY
import os, subprocess, sys
out = subprocess.run(["/usr/bin/python3", "$plot_py", *sys.argv[1:], "--describe"],
                     check=True, capture_output=True, text=True).stdout
open(os.environ["PLOT_DESCRIPTION"], "w").write(out)
PY
"$gvs" sim --scenario crawl --seconds 1 --seed 4 --out "$work/run" > /dev/null
"$gvs" replay "$work/run" --out "$work/est.csv" > /dev/null
with_yaw=$(tail -n +2 "$work/est.csv" | awk -F, '$7 != "" {n++} END {print n + 0}')
[[ $with_yaw -gt 0 ]] || fail "the crawl run has no yaw-rate estimates to plot"
PLOT_DESCRIPTION="$work/plot.json" GVS_PLOT_SCRIPT="$work/describe_plot.py" \
  "$gvs" eval "$work/run" "$work/est.csv" --plot "$work/plot.png" --title "crawl" > /dev/null
[[ $(head -c 8 "$work/plot.png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "plot is not a PNG"
# --plot FILE writes FILE as given, also without a .png suffix, and says so.
out=$("$gvs" eval "$work/run" "$work/est.csv" --plot "$work/plot-no-suffix")
[[ -f "$work/plot-no-suffix" && ! -e "$work/plot-no-suffix.png" ]] || fail "--plot FILE did not write FILE: $(ls "$work")"
grep -q "plot written to $work/plot-no-suffix\$" <<<"$out" || fail "the message names another file: $out"

/usr/bin/python3 - "$work/plot.json" "$with_yaw" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
with_yaw = int(sys.argv[2])
panels = d["panels"]
def panel(ylabel):
    found = [p for p in panels if p["ylabel"] == ylabel]
    assert found, f"FAIL: no panel '{ylabel}' in {[p['ylabel'] for p in panels]}"
    return found[0]
for ylabel in ("direction (deg)", "speed (km/h)", "yaw rate (deg/s)"):
    lines = {ln["label"]: ln["points"] for ln in panel(ylabel)["lines"]}
    assert lines.get("truth", 0) > 0 and "estimate" in lines, f"FAIL: {ylabel}: {lines}"
    assert {"truth", "estimate"} <= set(panel(ylabel)["legend"]), f"FAIL: {ylabel} legend"
yaw = {ln["label"]: ln["points"] for ln in panel("yaw rate (deg/s)")["lines"]}
assert yaw["estimate"] == with_yaw, f"FAIL: yaw panel shows {yaw['estimate']} estimates, the CSV has {with_yaw}"
hist = [p for p in panels if p["title"].startswith("yaw rate error: n=")]
assert hist and f"n={with_yaw}," in hist[0]["title"], f"FAIL: yaw-rate error histogram: {[p['title'] for p in panels]}"
covering = [p["ylabel"] for p in panels if p["legend_covers_a_panel"]]
assert not covering, f"FAIL: legends cover panels: {covering}"
print("OK eval plot: %d panels, yaw rate on %d frames" % (len(panels), with_yaw))
PY

#!/usr/bin/env bash
# End to end through the gvs tool: sim -> replay -> eval (+ plot), on a
# simulated run and on a dataset written by hand like a third-party tool
# would (other size and mm_per_px, colour PNG, index gaps, pulses, changing
# exposure), and the named errors for broken datasets.
# usage: cli_end_to_end.sh GVS_BINARY SCENARIO METHOD
set -euo pipefail
gvs=$1
scenario=$2
method=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# 1. A short simulated run.
"$gvs" sim --scenario "$scenario" --out "$work/run" --seconds 0.4 --seed 3 --fps 30
frames=$(($(wc -l < "$work/run/frames.csv") - 1))
truth=$(($(wc -l < "$work/run/truth.csv") - 1))
[[ $frames -ge 10 ]] || fail "sim wrote $frames frames"
[[ $frames -eq $truth ]] || fail "frames.csv has $frames rows, truth.csv $truth"
head -1 "$work/run/frames.csv" | grep -qx 'index,file,t_ns,exposure_us,pulses' || fail "frames.csv header"
head -1 "$work/run/truth.csv" | grep -qx 'index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps' || fail "truth.csv header"
grep -q '"format": "gvs-dataset/1"' "$work/run/camera.json" || fail "camera.json format"

# 2. Replay writes one row per frame, with the spec's header.
"$gvs" replay "$work/run" --out "$work/est.csv" --method "$method"
rows=$(($(wc -l < "$work/est.csv") - 1))
[[ $rows -eq $frames ]] || fail "replay wrote $rows rows for $frames frames"
head -1 "$work/est.csv" | grep -qx 'index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,quality,method' \
  || fail "estimates header"

# 2b. --config takes the estimator from a gvsd configuration; a bad one is named.
printf '[estimator]\nmethod = "%s"\n' "$method" > "$work/gvsd.toml"
"$gvs" replay "$work/run" --out "$work/est2.csv" --config "$work/gvsd.toml" | grep -q "with '$method'" \
  || fail "replay --config did not take the method"
cmp -s "$work/est.csv" "$work/est2.csv" || fail "replay --config gave other estimates than --method"
printf '[estimator]\nmethd = "gvs"\n' > "$work/bad.toml"
out=$("$gvs" replay "$work/run" --out "$work/x.csv" --config "$work/bad.toml" 2>&1) && fail "bad config accepted"
grep -q "bad.toml:2: unknown key 'methd'" <<<"$out" || fail "bad config not named: $out"

# 3. Eval prints the table; --plot draws a PNG; --json parses.
"$gvs" eval "$work/run" "$work/est.csv" --plot "$work/plot.png" --json "$work/acc.json" | tee "$work/table.txt"
grep -q '^0-5 ' "$work/table.txt" && grep -q '^140-250 ' "$work/table.txt" || fail "eval table lacks the bands"
[[ $(head -c 8 "$work/plot.png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "plot is not a PNG"
/usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert len(j['bands'])==5" "$work/acc.json" \
  || fail "eval --json"

# 4. A dataset another tool wrote: 200x150 px at 0.25 mm/px, colour PNG,
#    an index gap, a pulsed frame, exposure changing per frame, extra keys.
mkdir -p "$work/other/frames"
cat > "$work/other/camera.json" <<JSON
{"format": "gvs-dataset/1", "width": 200, "height": 150, "mm_per_px": 0.25, "mount_yaw_deg": -3.5,
 "vendor": "someone else"}
JSON
/usr/bin/python3 - "$work/other" <<'PY'
import sys, zlib, struct, random
folder = sys.argv[1]
def png(path, w, h, colour, seed):
    random.seed(seed)
    raw = b""
    for _ in range(h):
        row = bytes(random.randrange(256) for _ in range(w * (3 if colour else 1)))
        raw += b"\x00" + row
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 2 if colour else 0, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
for i in range(4):
    png(f"{folder}/frames/f{i}.png", 200, 150, i == 1, i)
PY
cat > "$work/other/frames.csv" <<CSV
index,file,t_ns,exposure_us,pulses
10,frames/f0.png,5000000000,3000,
11,frames/f1.png,5016666667,1200.5,
14,frames/f2.png,5066666667,500,0:20|400:20
15,frames/f3.png,5083333333,250,
CSV
"$gvs" replay "$work/other" --out "$work/other.csv" --method "$method"
[[ $(($(wc -l < "$work/other.csv") - 1)) -eq 4 ]] || fail "replay of the other dataset: wrong row count"
cut -d, -f1 "$work/other.csv" | tail -n +2 | tr '\n' ' ' | grep -qx '10 11 14 15 ' || fail "indices not kept"

# 5. Broken datasets: a clear error naming file and line or key, exit 1, no crash.
expect_error() {  # expect_error DATASET PATTERN
  local out rc=0
  out=$("$gvs" replay "$1" --out "$work/x.csv" --method "$method" 2>&1) || rc=$?
  [[ $rc -eq 1 ]] || fail "expected exit 1 for $1, got $rc: $out"
  grep -q -- "$2" <<<"$out" || fail "error for $1 lacks '$2': $out"
}
cp -r "$work/other" "$work/bad1"
sed -i 's/"mm_per_px": 0.25, //' "$work/bad1/camera.json"
expect_error "$work/bad1" "camera.json: missing required key 'mm_per_px'"
cp -r "$work/other" "$work/bad2"
sed -i 's/^11,frames\/f1.png,5016666667/11,frames\/f1.png,4000000000/' "$work/bad2/frames.csv"
expect_error "$work/bad2" "frames.csv:3: t_ns 4000000000 goes backwards"
cp -r "$work/other" "$work/bad3"
head -c 100 "$work/other/frames/f2.png" > "$work/bad3/frames/f2.png"
expect_error "$work/bad3" "frames/f2.png: unreadable or truncated image"
cp -r "$work/other" "$work/bad4"
sed -i 's/^15,frames\/f3.png,5083333333,250,/15,frames\/f3.png,5083333333,-2,/' "$work/bad4/frames.csv"
expect_error "$work/bad4" "frames.csv:5: exposure_us '-2' must be a number > 0"
echo "PASS: gvs sim/replay/eval end to end ($scenario, $method)"

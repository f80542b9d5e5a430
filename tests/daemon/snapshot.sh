#!/usr/bin/env bash
# gvs snapshot on a simulated frame driving forward (sine: direction within
# +-8 deg): the image is the frame and its spectrum side by side above a text
# band, and the green ground-motion arrow points down the image (a ground
# point moves by +row when the car moves forward, dataset-format.md), not up.
set -euo pipefail
gvs=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
"$gvs" sim --scenario sine --seconds 0.2 --width 256 --height 192 --mm-per-px 0.2 --out "$work/run" >/dev/null
"$gvs" snapshot --dataset "$work/run" --out "$work/snap.png" | tee "$work/out.txt"
grep -q "direction [+-][0-9]" "$work/out.txt" || { echo "FAIL: no direction in the snapshot's text"; exit 1; }
# An unreadable frame before the one asked for costs history, not the snapshot;
# the frame asked for itself must be readable.
cp -r "$work/run" "$work/broken"
echo garbage > "$work/broken/frames/000008.png"
"$gvs" snapshot --dataset "$work/broken" --frame 10 --out "$work/snap10.png" > /dev/null ||
  { echo "FAIL: an unreadable frame 8 stopped the snapshot of frame 10"; exit 1; }
if "$gvs" snapshot --dataset "$work/broken" --frame 8 --out "$work/snap8.png" 2> "$work/err8.txt"; then
  echo "FAIL: a snapshot of the unreadable frame 8 succeeded"; exit 1
fi
grep -q "000008.png" "$work/err8.txt" || { echo "FAIL: the error does not name the frame: $(cat "$work/err8.txt")"; exit 1; }
/usr/bin/python3 - "$work/snap.png" <<'PY'
import sys
import matplotlib.image as mpimg
img = mpimg.imread(sys.argv[1])  # rows x cols x 3|4, floats 0..1
h, w = img.shape[0], img.shape[1]
# Frame and spectrum side by side above a 64 px text band, 20 px more a line of why there is no speed.
assert w == 2 * 256 and h >= 192 + 64 and (h - 192 - 64) % 20 == 0, f"FAIL: snapshot is {w}x{h}, expected 512x(256+20k)"
def green(r, c):
    p = img[r, c]
    return p[1] > 0.8 and p[0] < 0.4 and p[2] < 0.4
cx, cy, arm = 128, 96, int(0.4 * 192)
below = sum(green(cy + d, c) for d in range(20, arm - 10) for c in range(cx - 15, cx + 16))
above = sum(green(cy - d, c) for d in range(20, arm - 10) for c in range(cx - 15, cx + 16))
print(f"green arrow pixels below the centre {below}, above {above}")
assert below > 40 and above == 0, "FAIL: the ground-motion arrow does not point down the image"
print("OK snapshot")
PY

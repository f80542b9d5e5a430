#!/usr/bin/env bash
# gvs calibrate yaw on a simulated straight run (accel: direction 0) with the
# camera turned +3 deg but camera.json claiming 0; the fitted yaw must be
# 3 +- 0.2 deg and land in the configuration file, comments kept.
set -euo pipefail
gvs=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
"$gvs" sim --scenario accel --seconds 2.5 --seed 4 --mount-yaw-deg 3 --out "$work/run" >/dev/null
sed -i 's/"mount_yaw_deg": *[-0-9.e]*/"mount_yaw_deg": 0.0/' "$work/run/camera.json"
grep -q '"mount_yaw_deg": 0.0' "$work/run/camera.json" || { echo "FAIL: could not reset camera.json"; exit 1; }
printf '# test car\n[camera]\nmm_per_px = 0.1  # keep me\n' > "$work/gvsd.toml"
"$gvs" calibrate yaw "$work/run" --config "$work/gvsd.toml" | tee "$work/out.txt"
yaw=$(sed -n 's/^mount_yaw_deg = \([-0-9.e]*\)$/\1/p' "$work/gvsd.toml")
[[ -n "$yaw" ]] || { echo "FAIL: no mount_yaw_deg written:"; cat "$work/gvsd.toml"; exit 1; }
grep -q '^mm_per_px = 0.1  # keep me' "$work/gvsd.toml" || { echo "FAIL: the rest of the file changed"; cat "$work/gvsd.toml"; exit 1; }
awk -v y="$yaw" 'BEGIN { exit !(y > 2.8 && y < 3.2) }' || { echo "FAIL: mount_yaw_deg $yaw, expected 3 +- 0.2"; exit 1; }
echo "OK mount_yaw_deg $yaw"

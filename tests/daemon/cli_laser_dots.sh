#!/usr/bin/env bash
# gvs sim --lasers records the beams in camera.json; gvs replay finds the
# dots, keeps the estimates CSV's columns as the dataset format fixes them
# and writes the measured height to --ride; gvs eval --ride reports it; the
# scale correction takes the speed's slope against the height from the
# scale's -1.67 %/mm to about 0.
# usage: cli_laser_dots.sh GVS_BINARY
set -euo pipefail
gvs=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# 60 km/h for 1.5 s at 20 fps, double pulse, heave of up to +-5 mm.
"$gvs" sim --scenario sine --seconds 1.5 --fps 20 --exposure double-pulse --body heave --lasers --out "$work/run" > /dev/null
grep -q '"lasers"' "$work/run/camera.json" || fail "camera.json lacks the lasers"
[[ $(grep -c '"tilt_deg"' "$work/run/camera.json") == 4 ]] || fail "camera.json does not hold four beams"
grep -q -- '--lasers' "$work/run/camera.json" || fail "camera.json's description does not say --lasers"

"$gvs" replay "$work/run" --out "$work/est.csv" --ride "$work/ride.csv" > /dev/null
head -1 "$work/est.csv" | grep -qx 'index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,quality,method' \
  || fail "the estimates CSV's header changed: $(head -1 "$work/est.csv")"
head -1 "$work/ride.csv" | grep -qx 'index,t_ns,height_mm,pitch_deg,roll_deg,dots_found,scale_source' \
  || fail "ride CSV header: $(head -1 "$work/ride.csv")"
rows=$(($(wc -l < "$work/ride.csv") - 1))
dots=$(grep -c ',laser_dots$' "$work/ride.csv" || true)
[[ $rows == 30 ]] || fail "ride CSV has $rows rows, not 30"
(( dots >= 24 )) || fail "only $dots of 30 frames scaled by the dots"

"$gvs" eval "$work/run" "$work/est.csv" --ride "$work/ride.csv" > "$work/eval"
cat "$work/eval"
grep -q '^Ride height from the laser dots' "$work/eval" || fail "gvs eval --ride has no ride table"
rms=$(sed -n 's/^  height mm *[-0-9.]* *\([0-9.]*\) .*/\1/p' "$work/eval")
awk -v r="$rms" 'BEGIN { exit !(r > 0 && r < 0.1) }' || fail "height RMS '$rms' mm is not below 0.1"
slope=$(sed -n 's/^slope: \(-\?[0-9.]*\) % of speed per mm.*/\1/p' "$work/eval")
awk -v s="$slope" 'BEGIN { exit !(s > -0.5 && s < 0.5) }' || fail "corrected slope $slope %/mm is not about 0"

# Uncorrected (dots masked, nominal scale): the scale's slope, and no laser_dots source.
"$gvs" replay "$work/run" --out "$work/nc.csv" --ride "$work/nc.ride.csv" --no-scale-correction > /dev/null
if grep -q ',laser_dots$' "$work/nc.ride.csv"; then fail "--no-scale-correction still scaled by the dots"; fi
"$gvs" eval "$work/run" "$work/nc.csv" > "$work/nc.eval"
slope=$(sed -n 's/^slope: \(-\?[0-9.]*\) % of speed per mm.*/\1/p' "$work/nc.eval")
awk -v s="$slope" 'BEGIN { exit !(s < -1.4 && s > -1.95) }' || fail "uncorrected slope $slope %/mm is not the scale's -1.67"
echo "OK laser dots"

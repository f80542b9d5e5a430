#!/usr/bin/env bash
# gvs sim --body: the truth gains height_mm, pitch_deg, roll_deg (and
# camera.json the nominal height), gvs replay reads the dataset, and gvs
# eval prints the speed error against the height, which follows the scale
# H0/H - 1; a run without body motion keeps the seven truth columns and no
# such table; a bad body is refused naming the known ones.
# usage: cli_body_motion.sh GVS_BINARY
set -euo pipefail
gvs=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# 60 km/h for 1 s at 20 fps, double pulse: heave of up to +-5 mm.
"$gvs" sim --scenario sine --seconds 1 --fps 20 --exposure double-pulse --body heave --out "$work/heave" > "$work/sim.out"
grep -q "with body motion heave" "$work/sim.out" || fail "gvs sim does not say it moved the body"
head -1 "$work/heave/truth.csv" | grep -qx 'index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,height_mm,pitch_deg,roll_deg' \
  || fail "truth.csv header: $(head -1 "$work/heave/truth.csv")"
grep -q '"height_mm": 60.0' "$work/heave/camera.json" || fail "camera.json lacks the nominal height"
awk -F, 'NR > 1 && ($8 < 54.99 || $8 > 65.01 || $9 != 0 || $10 != 0) { bad = 1 } END { exit bad }' "$work/heave/truth.csv" \
  || fail "heave outside 60 +- 5 mm or tilted"
"$gvs" replay "$work/heave" --out "$work/heave.csv" > /dev/null
"$gvs" eval "$work/heave" "$work/heave.csv" > "$work/heave.eval"
cat "$work/heave.eval"
grep -q '^speed against height (nominal 60.0 mm' "$work/heave.eval" || fail "gvs eval has no speed-against-height table"
slope=$(sed -n 's/^slope: \(-\?[0-9.]*\) % of speed per mm.*/\1/p' "$work/heave.eval")
awk -v s="$slope" 'BEGIN { exit !(s < -1.4 && s > -1.95) }' || fail "slope $slope %/mm is not the scale's -1.67"

# Without body motion: seven columns, no table.
"$gvs" sim --scenario sine --seconds 0.2 --fps 20 --exposure double-pulse --out "$work/flat" > /dev/null
head -1 "$work/flat/truth.csv" | grep -qx 'index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps' \
  || fail "a flat run's truth has other columns"
"$gvs" replay "$work/flat" --out "$work/flat.csv" > /dev/null
"$gvs" eval "$work/flat" "$work/flat.csv" > "$work/flat.eval"
if grep -q 'speed against height' "$work/flat.eval"; then fail "a flat run has a height table"; fi

# A body that does not exist: exit 2, naming the known ones.
set +e
"$gvs" sim --scenario sine --body bumpy --out "$work/bad" > "$work/bad.out" 2>&1
rc=$?
set -e
[[ $rc == 2 ]] || fail "--body bumpy exited $rc, not 2"
grep -q 'flat' "$work/bad.out" && grep -q 'ride' "$work/bad.out" || fail "--body bumpy does not name the known bodies"
echo "OK body motion"

#!/usr/bin/env bash
# gvs sim --ground photo:FILE[:MM_PER_PIXEL] end to end: a run on a shared
# real-asphalt photo is a dataset that records its ground and replays; a
# missing photo or a bad scale stops gvs sim naming the file.
# usage: sim_photo_ground.sh GVS_BINARY SHARED_DIR
set -euo pipefail
gvs=$1
photo=$2/testdata/real-asphalt/ph_asphalt_04_1024.png
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
[[ -f $photo ]] || fail "real-asphalt photo missing: $photo (configure with -DGVS_SHARED_DIR=the shared/ folder)"

"$gvs" sim --scenario const --ground "photo:$photo:0.2" --out "$work/run" --seconds 0.3 --seed 4 --fps 30
frames=$(($(wc -l < "$work/run/frames.csv") - 1))
truth=$(($(wc -l < "$work/run/truth.csv") - 1))
[[ $frames -eq 9 ]] || fail "sim wrote $frames frames, expected 9"
[[ $truth -eq $frames ]] || fail "frames.csv has $frames rows, truth.csv $truth"
grep -qF "\"ground\": \"photo:$photo:0.2\"" "$work/run/camera.json" || fail "camera.json lacks the ground: $(cat "$work/run/camera.json")"
grep -qF -- "--ground photo:$photo:0.2" "$work/run/camera.json" || fail "camera.json description lacks the ground"
[[ $(head -c 8 "$work/run/frames/000000.png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "frame is not a PNG"

# The default ground is recorded too; the same seed on the photo renders the same frames.
"$gvs" sim --scenario const --out "$work/proc" --seconds 0.1 --seed 4 --fps 30 >/dev/null
grep -qF '"ground": "procedural"' "$work/proc/camera.json" || fail "procedural ground not recorded"
"$gvs" sim --scenario const --ground "photo:$photo" --out "$work/again" --seconds 0.3 --seed 4 --fps 30 >/dev/null
cmp -s "$work/run/frames/000005.png" "$work/again/frames/000005.png" || fail "same seed, same photo: other frame 5"

# The run replays and evaluates like any dataset.
"$gvs" replay "$work/run" --out "$work/est.csv" --method gvs >/dev/null
[[ $(($(wc -l < "$work/est.csv") - 1)) -eq $frames ]] || fail "replay row count"
"$gvs" eval "$work/run" "$work/est.csv" >/dev/null || fail "eval"

expect_error() {  # expect_error GROUND PATTERN
  local out rc=0
  out=$("$gvs" sim --scenario const --ground "$1" --out "$work/x" --seconds 0.1 2>&1) || rc=$?
  [[ $rc -eq 1 ]] || fail "expected exit 1 for --ground $1, got $rc: $out"
  grep -qF -- "$2" <<<"$out" || fail "error for --ground $1 lacks '$2': $out"
}
expect_error "photo:$work/no_such.png" "$work/no_such.png"
expect_error "photo:$photo:0" "$photo"
expect_error "photo:$photo:huge" "$photo"
expect_error "gravel" "procedural or photo:FILE[:MM_PER_PIXEL]"
printf '\nOK sim photo ground\n'

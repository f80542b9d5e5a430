#!/usr/bin/env bash
# README.md's "A short tour" as a new user runs it: its first sh block, as
# written, with build/release/bin/ pointing at this build's binaries and
# /tmp/ at a scratch folder. The eval must show a speed on nearly every
# frame, within 1 % RMS of the truth, and the plot must be written.
# usage: readme_tour.sh README.md BIN_DIR
set -euo pipefail
readme=$1
bin=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# The first ```sh block after the tour's heading.
awk '/^## A short tour/ {tour=1} tour && /^```sh$/ {block=1; next} block && /^```$/ {exit} block {print}' \
  "$readme" > "$work/tour.sh"
[[ -s $work/tour.sh ]] || fail "no sh block under '## A short tour' in $readme"
grep -q 'gvs eval ' "$work/tour.sh" || fail "the tour's block runs no gvs eval: $(cat "$work/tour.sh")"
sed -i -e "s|build/release/bin/|$bin/|g" -e "s|/tmp/|$work/|g" "$work/tour.sh"
echo "--- the tour, as run:"; cat "$work/tour.sh"
bash -euo pipefail "$work/tour.sh" | tee "$work/out.txt"

# The eval table's "all" row: label frames dir-coverage speed-coverage | dir
# mean std rms max | speed mean rms off>5 | yaw rms.
all=$(grep '^all ' "$work/out.txt") || fail "no 'all' row in the eval's output"
read -r _ frames _ speed_cov <<<"${all%%|*}"
read -r _ speed_rms off <<<"$(cut -d'|' -f3 <<<"$all")"
with_speed=${speed_cov%/*}
echo "frames $frames, with a speed $with_speed, speed RMS $speed_rms %, off by > 5 %: $off"
[[ $frames -ge 100 ]] || fail "the tour evaluated $frames frames"
[[ $speed_rms != - ]] || fail "the tour shows no speed: $all"
awk -v n="$with_speed" -v f="$frames" 'BEGIN {exit !(n >= 0.95 * f)}' || fail "speed on only $with_speed of $frames frames"
awk -v r="$speed_rms" 'BEGIN {exit !(r < 1.0)}' || fail "speed RMS $speed_rms % is not within 1 %"
[[ $off -eq 0 ]] || fail "$off speeds off by more than 5 %"
png=$(sed -n 's/^plot written to //p' "$work/out.txt")
[[ -n $png && $(head -c 8 "$png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "the tour's plot is not a PNG"
echo "OK readme tour"

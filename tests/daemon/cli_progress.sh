#!/usr/bin/env bash
# gvs sim and gvs replay report progress (frames done of the total, rate,
# time left) on a terminal, run here under script(1)'s pseudo-terminal, and
# write nothing of it when standard error is a file.
# usage: cli_progress.sh GVS_BINARY
set -euo pipefail
gvs=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v script >/dev/null || fail "script(1) (util-linux) is needed to give gvs a terminal"

# 1. Not a terminal: results on stdout, nothing on stderr.
"$gvs" sim --scenario stop --seconds 0.5 --fps 30 --out "$work/quiet" >"$work/sim.out" 2>"$work/sim.err"
grep -q "^wrote" "$work/sim.out" || fail "sim result missing: $(cat "$work/sim.out")"
[[ ! -s "$work/sim.err" ]] || fail "sim wrote to a non-terminal stderr: $(cat "$work/sim.err")"
"$gvs" replay "$work/quiet" --out "$work/quiet.csv" >"$work/replay.out" 2>"$work/replay.err"
[[ ! -s "$work/replay.err" ]] || fail "replay wrote to a non-terminal stderr: $(cat "$work/replay.err")"

# 2. On a terminal: a progress line against the run's real frame count,
#    cleared before the result line.
script -qec "'$gvs' sim --scenario stop --seconds 0.5 --fps 30 --out '$work/tty'" /dev/null > "$work/sim.tty"
frames=$(($(wc -l < "$work/tty/frames.csv") - 1))
tr '\r' '\n' < "$work/sim.tty" > "$work/sim.lines"
grep -Eq "gvs sim: [0-9]+/$frames frames \([0-9]+ %\), [0-9.]+ frames/s, [0-9?]+ ?s? left" "$work/sim.lines" \
  || fail "no sim progress against $frames frames: $(cat "$work/sim.lines")"
grep -q $'^\033\\[Kwrote' "$work/sim.lines" || fail "progress line not cleared before the result: $(cat "$work/sim.lines")"
script -qec "'$gvs' replay '$work/tty' --out '$work/tty.csv'" /dev/null | tr '\r' '\n' > "$work/replay.lines"
grep -Eq "gvs replay: [0-9]+/$frames frames \([0-9]+ %\), [0-9.]+ frames/s" "$work/replay.lines" \
  || fail "no replay progress against $frames frames: $(cat "$work/replay.lines")"
echo "OK progress"

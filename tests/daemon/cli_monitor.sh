#!/usr/bin/env bash
# gvs monitor reading gvsd's candump output from a pipe: it refreshes while
# frames flow, flags the silence after gvsd stops (no "valid yes", rate 0),
# ends at end of input even with --follow, writes no screen escapes into a
# file, and refuses input that is not candump -L, saying how to record one.
# usage: cli_monitor.sh GVS_BINARY GVSD_BINARY
set -euo pipefail
gvs=$1
gvsd=$2
work=$(mktemp -d)
mon=
cleanup() { exec 3>&- 2>/dev/null || true; [[ -n "$mon" ]] && kill "$mon" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
# wait_for PATTERN: until the monitor's output matches (bounded: 60 s).
wait_for() {
  for _ in $(seq 600); do grep -q "$1" "$work/mon.txt" && return 0; sleep 0.1; done
  fail "monitor never showed '$1': $(tail -20 "$work/mon.txt")"
}

# 1. gvsd -> FIFO -> monitor; the write end stays open after gvsd stops.
mkfifo "$work/pipe"
"$gvs" monitor - --follow --refresh-ms 100 < "$work/pipe" > "$work/mon.txt" 2>&1 &
mon=$!
exec 3>"$work/pipe"
"$gvsd" --run-for 1 --can candump:- >&3 2>"$work/gvsd.log" || fail "gvsd: $(cat "$work/gvsd.log")"
wait_for "^NO DATA for [0-9]* ms"
# The view shown during the silence: no "valid yes", GVS_Velocity rate 0.
silent_view=$(awk '/^source:/ { block = "" } { block = block $0 "\n" } /^NO DATA/ { found = 1 }
                   found && /^bus error frames/ { printf "%s", block; exit }' "$work/mon.txt")
[[ -n "$silent_view" ]] || fail "no complete view with NO DATA"
grep -q "valid yes" <<<"$silent_view" && fail "silent view still claims valid: $silent_view"
grep -q "^speed .* valid old" <<<"$silent_view" || fail "silent view does not mark the speed old: $silent_view"
awk '$1 == "GVS_Velocity" { exit !($2 >= 40 && $3 == 0.0) }' <<<"$silent_view" \
  || fail "silent view: GVS_Velocity frames/rate wrong: $silent_view"
# Before the silence, while gvsd ran, a view claimed valid data at ~50 Hz.
before=$(sed '/^NO DATA/,$d' "$work/mon.txt")
grep -q "valid yes" <<<"$before" || fail "no view with valid data while frames flowed: $before"
awk '$1 == "GVS_Velocity" && $3 > 40 { ok = 1 } END { exit !ok }' <<<"$before" \
  || fail "no view showed the live rate while frames flowed: $before"

# 2. End of input ends the monitor, --follow or not; its summary is last.
exec 3>&-
rc=0; wait "$mon" || rc=$?
mon=
[[ $rc -eq 0 ]] || fail "monitor exited $rc at end of input"
grep -q "^source: standard input (summary)" "$work/mon.txt" || fail "no summary at end of input"
! grep -q $'\033' "$work/mon.txt" || fail "screen escapes written into a file"

# 3. Input that is not candump -L: refused, saying how to record a log.
printf 'index,t_ns,vx_mps\n0,1,2\n' > "$work/not-candump.csv"
rc=0; out=$("$gvs" monitor - < "$work/not-candump.csv" 2>&1) || rc=$?
[[ $rc -eq 1 ]] || fail "non-candump input: exit $rc: $out"
grep -q "line 1 is not a candump -L line.*candump -L can0 > run.log" <<<"$out" || fail "refusal: $out"
rc=0; out=$("$gvs" monitor "$work/not-candump.csv" 2>&1) || rc=$?
[[ $rc -eq 1 ]] && grep -q "not-candump.csv: line 1 is not a candump -L line" <<<"$out" || fail "file refusal: $out"
echo "OK monitor"

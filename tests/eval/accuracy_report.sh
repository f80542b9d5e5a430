#!/usr/bin/env bash
# scripts/accuracy-report on tiny runs (0.3 s, 1-2 seeds): --help describes
# every option, the default method is the product's (gvs), the temporary
# folder is gone after a run, an error, SIGTERM and Ctrl-C (SIGINT), and
# progress shows on a terminal (script(1)) and not in a pipe.
# usage: accuracy_report.sh SCRIPT GVS_BINARY
set -euo pipefail
report=$1
gvs=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
export TMPDIR=$work/tmp  # where the report's temporary folder goes
mkdir "$TMPDIR"
no_temporaries() {  # no_temporaries WHEN
  [[ -z $(ls -A "$TMPDIR") ]] || fail "temporary files left $1: $(find "$TMPDIR" | head)"
}
quick=(--gvs "$gvs" --scenarios sine --seconds 0.3)

# 1. --help: every option in the usage line has a description.
"$report" --help > "$work/help.txt"
/usr/bin/python3 - "$work/help.txt" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
usage, _, rest = text.partition("\noptions:\n")
opts = sorted(set(re.findall(r"\[(--[a-z-]+)", usage)))
assert len(opts) >= 10, f"FAIL: usage lists only {opts}"
for o in opts:
    m = re.search(r"^  (?:-h, )?%s(?: [A-Z_]+)?(?:\n {20,}| {2,})(\S.*)" % re.escape(o), rest, re.M)
    assert m and len(m.group(1)) > 10, f"FAIL: --help does not describe {o}"
assert "default: gvs" in rest, "FAIL: --help does not say the default method"
print("help describes %d options" % len(opts))
PY

# 2. The default method is gvs; the temporary folder is removed; quiet in a pipe.
"$report" "${quick[@]}" --seeds 1 > "$work/out.md" 2> "$work/err.txt"
grep -q '^#### `sine`, method `gvs`$' "$work/out.md" || fail "default method is not gvs: $(cat "$work/out.md")"
[[ $(grep -c '^#### ' "$work/out.md") -eq 1 ]] || fail "more than the one default method: $(grep '^####' "$work/out.md")"
grep -q '^| all | 18 |' "$work/out.md" || fail "not one 0.3 s run of 18 frames: $(cat "$work/out.md")"
grep -Eq '^Valid on the bus \(quality >= 0.3\), direction on / speed on: .*all [0-9.]+ % / [0-9.]+ %$' "$work/out.md" \
  || fail "no valid-on-the-bus line: $(cat "$work/out.md")"
[[ ! -s $work/err.txt ]] || fail "wrote to a non-terminal stderr: $(cat "$work/err.txt")"
no_temporaries "after a run"

# 3. An error in a run (gvs sim refuses --fps 0): says which command, exit 1, nothing left.
rc=0; "$report" "${quick[@]}" --seeds 2 --sim-args "--fps 0" > /dev/null 2> "$work/err.txt" || rc=$?
[[ $rc -ne 0 ]] || fail "a failing gvs sim did not fail the report"
grep -q "failed: .*gvs sim --scenario sine" "$work/err.txt" || fail "the error does not name the command: $(cat "$work/err.txt")"
no_temporaries "after an error"

# 4. Stopped while a run renders (10 s scenario): SIGTERM, then SIGINT as
#    Ctrl-C sends it (job control on, so a background job does not ignore it).
set -m
for sig in TERM INT; do
  "$report" --gvs "$gvs" --scenarios sine --seeds 3 > /dev/null 2> "$work/err.txt" &
  pid=$!
  for _ in $(seq 300); do  # until the first run is rendering frames
    [[ -n $(find "$TMPDIR" -name '*.png' -print -quit 2>/dev/null) ]] && break
    sleep 0.1
  done
  [[ -n $(find "$TMPDIR" -name '*.png' -print -quit) ]] || fail "no run started within 30 s"
  kill -"$sig" "$pid"
  rc=0; wait "$pid" || rc=$?
  [[ $rc -ne 0 ]] || fail "SIG$sig: the report exited 0"
  grep -q "interrupted, temporary runs removed" "$work/err.txt" || fail "SIG$sig: $(cat "$work/err.txt")"
  no_temporaries "after SIG$sig"
done
set +m

# 5. On a terminal: runs done of the total and the time left, cleared at the end.
if command -v script > /dev/null; then
  script -qec "'$report' --gvs '$gvs' --scenarios sine --seconds 0.3 --seeds 2" /dev/null | tr '\r' '\n' > "$work/tty.txt"
  grep -Eq 'accuracy-report: 1/2 runs, [0-9]+:[0-9]{2} elapsed, [0-9]+:[0-9]{2} left' "$work/tty.txt" \
    || fail "no progress on a terminal: $(cat "$work/tty.txt")"
  grep -q '^#### `sine`, method `gvs`' "$work/tty.txt" || fail "no table on a terminal"
  no_temporaries "after a run on a terminal"
fi
echo "OK accuracy-report"

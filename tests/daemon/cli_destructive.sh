#!/usr/bin/env bash
# The gvs tool does not destroy or half-write data by default: sim refuses
# an existing dataset without --force and leaves nothing behind when
# interrupted; calibrate refuses a missing --config without --create-config.
# usage: cli_destructive.sh GVS_BINARY
set -euo pipefail
gvs=$1
work=$(mktemp -d)
sim_pid=
cleanup() { [[ -n "$sim_pid" ]] && kill "$sim_pid" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
rows() { echo $(($(wc -l < "$1") - 1)); }

# 1. sim over an existing dataset: refused, the old one untouched.
"$gvs" sim --scenario const --seconds 0.2 --fps 30 --out "$work/run" >/dev/null
old=$(rows "$work/run/frames.csv")
old_sum=$(cat "$work/run/frames.csv" "$work/run/truth.csv" | md5sum)
set +e
out=$("$gvs" sim --scenario sine --seconds 0.4 --fps 30 --out "$work/run" 2>&1); rc=$?
set -e
[[ $rc -ne 0 ]] || fail "sim over an existing dataset succeeded"
grep -q "exists and is not empty.*--force" <<<"$out" || fail "refusal does not say what to do: $out"
[[ $(cat "$work/run/frames.csv" "$work/run/truth.csv" | md5sum) == "$old_sum" ]] || fail "refused run changed the dataset"

# 2. --force replaces it whole: the new run's frames only, no stale PNG.
"$gvs" sim --scenario sine --seconds 0.4 --fps 30 --out "$work/run/" --force >/dev/null
new=$(rows "$work/run/frames.csv")
[[ $new -gt $old ]] || fail "--force did not write the longer run ($old -> $new frames)"
[[ $(ls "$work/run/frames" | wc -l) -eq $new ]] || fail "frames/ holds $(ls "$work/run/frames" | wc -l) files for $new rows"
[[ $(rows "$work/run/truth.csv") -eq $new ]] || fail "truth.csv does not match frames.csv"
grep -q 'scenario sine' "$work/run/camera.json" || fail "camera.json is not the new run's"
[[ -z $(find "$work" -maxdepth 1 -name '.*partial*') ]] || fail "staging folder left behind"

# 3. SIGINT during sim: --out never appears, the staging folder is removed.
"$gvs" sim --scenario sine --seconds 60 --fps 30 --out "$work/long" >/dev/null 2>"$work/long.err" &
sim_pid=$!
for _ in $(seq 600); do   # wait (up to 60 s) until frames are being written
  compgen -G "$work/.long.partial-*/frames/*.png" >/dev/null && break
  sleep 0.1
done
compgen -G "$work/.long.partial-*/frames/*.png" >/dev/null || fail "sim wrote no frame into a staging folder"
kill -INT "$sim_pid"
set +e; wait "$sim_pid"; rc=$?; set -e
sim_pid=
[[ $rc -eq 130 ]] || fail "interrupted sim exited with $rc, expected 130"
[[ ! -e "$work/long" ]] || fail "interrupted sim left $work/long"
[[ -z $(find "$work" -maxdepth 1 -name '.long.partial-*') ]] || fail "interrupted sim left its staging folder"
grep -q "interrupted" "$work/long.err" || fail "interruption not reported: $(cat "$work/long.err")"

# 4. calibrate --config with a wrong path: refused, no file created.
/usr/bin/python3 - "$work/board.png" <<'PY'
import sys, zlib, struct
sq, cols, rows, margin = 20, 10, 7, 40      # 9x6 inner corners
w, h = cols * sq + 2 * margin, rows * sq + 2 * margin
raw = b""
for y in range(h):
    row = bytearray(255 for _ in range(w))
    for x in range(w):
        cx, cy = x - margin, y - margin
        if 0 <= cx < cols * sq and 0 <= cy < rows * sq and (cx // sq + cy // sq) % 2 == 0:
            row[x] = 0
    raw += b"\x00" + bytes(row)
def chunk(t, d):
    return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
ihdr = struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)
open(sys.argv[1], "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
PY
set +e
out=$("$gvs" calibrate scale "$work/board.png" --square-mm 5 --config "$work/typo.toml" 2>&1); rc=$?
set -e
[[ $rc -ne 0 ]] || fail "calibrate with a missing --config succeeded: $out"
grep -q "typo.toml: no such configuration file.*--create-config" <<<"$out" || fail "refusal does not say what to do: $out"
[[ ! -e "$work/typo.toml" ]] || fail "calibrate created $work/typo.toml"

# 5. ... and with --create-config it starts the file, as asked.
"$gvs" calibrate scale "$work/board.png" --square-mm 5 --config "$work/new.toml" --create-config >/dev/null
grep -q '^mm_per_px = 0.25' "$work/new.toml" || fail "new config: $(cat "$work/new.toml")"
echo "OK destructive defaults"

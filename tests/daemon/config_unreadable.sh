#!/bin/bash
# gvsd names why it cannot read its configuration: permission denied (a
# file the daemon's user may not read), no such file, or a folder.
#   config_unreadable.sh GVSD
set -euo pipefail
gvsd=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
printf '[source]\nuri = "sim:sine"\n' > "$work/gvsd.toml"
chmod 755 "$work"

# A file its reader may not open. Root reads anything: then gvsd runs as
# nobody (setpriv, util-linux), as the service runs as its own user.
chmod 000 "$work/gvsd.toml"
if [[ $(id -u) -eq 0 ]]; then
  run_as=(setpriv --reuid=65534 --regid=65534 --clear-groups)
else
  run_as=()
fi
out=$("${run_as[@]}" "$gvsd" --config "$work/gvsd.toml" --check-config 2>&1) && fail "unreadable file accepted: $out"
grep -q "gvsd.toml: cannot read the configuration file (permission denied" <<<"$out" || fail "no 'permission denied': $out"

mkdir "$work/folder.toml"
out=$("$gvsd" --config "$work/folder.toml" --check-config 2>&1) && fail "folder accepted: $out"
grep -q "folder.toml" <<<"$out" || fail "folder not named: $out"
echo "OK: $out"

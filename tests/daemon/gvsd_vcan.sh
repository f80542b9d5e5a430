#!/usr/bin/env bash
# gvsd on a real SocketCAN bus: a vcan0 inside Debian's kernel under qemu
# (tests/bench/qemu-vcan.sh). gvsd replays a small simulated sine run (the
# truth estimator keeps the emulated guest's work light) and sends on vcan0;
# `gvs monitor vcan0`, on a second raw socket, decodes the traffic and its
# summary is checked by the ctest PASS_REGULAR_EXPRESSION: 200 velocity
# frames for --run-for 4, no CRC errors, no counter jumps, the right values.
# usage: gvsd_vcan.sh GVS GVSD QEMU_VCAN_SH CACHE WORKDIR
set -euo pipefail
gvs=$1 gvsd=$2 harness=$3 cache=$4 work=$5
mkdir -p "$work"
rm -rf "$work/sine"
"$gvs" sim --scenario sine --seconds 6 --width 128 --height 96 --out "$work/sine" > /dev/null
printf '[estimator]\nmethod = "truth"\n' > "$work/gvsd-truth.toml"
exec "$harness" --cache "$cache" --timeout 600 -- /bin/sh "$(dirname "$0")/gvsd_vcan_guest.sh" \
  "$gvs" "$gvsd" "$work/sine" "$work/gvsd-truth.toml"

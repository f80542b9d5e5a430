#!/usr/bin/env bash
# gvsd on a real SocketCAN bus: a vcan0 inside Debian's kernel under qemu
# (tests/bench/qemu-vcan.sh). gvsd replays a small simulated sine run (the
# truth estimator keeps the emulated guest's work light) and sends on vcan0;
# `gvs monitor vcan0`, on a second raw socket, decodes the traffic and its
# summary is checked by the ctest PASS_REGULAR_EXPRESSION: 200 velocity
# frames for --run-for 4, no CRC errors, no counter jumps, the right values.
# An external distance sensor (cangen: ID 0x520, Motorola 16 bits at 0.01 mm,
# 62.00 mm, every 2 ms) gives the height: the speed is scaled by 62/60 and
# GVS_RideHeight carries 62.00 mm, valid, scale source external.
# usage: gvsd_vcan.sh GVS GVSD QEMU_VCAN_SH CACHE WORKDIR
set -euo pipefail
gvs=$1 gvsd=$2 harness=$3 cache=$4 work=$5
mkdir -p "$work"
rm -rf "$work/sine"
"$gvs" sim --scenario sine --seconds 6 --width 128 --height 96 --out "$work/sine" > /dev/null
printf '[estimator]\nmethod = "truth"\n[height]\nsource = "can"\ninterface = "vcan0"\ncan_id = 0x520\nstart_bit = 7\nlength = 16\nbyte_order = "motorola"\nscale = 0.01\nnominal_mm = 60.0\nmax_gap_ms = 50.0\n' > "$work/gvsd-truth.toml"
exec "$harness" --cache "$cache" --timeout 600 -- /bin/sh "$(dirname "$0")/gvsd_vcan_guest.sh" \
  "$gvs" "$gvsd" "$work/sine" "$work/gvsd-truth.toml"

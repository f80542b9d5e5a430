#!/usr/bin/env bash
# gvsd's light and trigger on a simulated GPIO chip: gpio-sim inside Debian's
# kernel under qemu (tests/bench/qemu-vcan.sh --gpio-sim 4). gvsd replays a
# small simulated run with [light] driver = "gpio" (trigger on line 0, LED
# ring on line 1) for 4 s; the guest script samples the LED line's level
# from gpio-sim's sysfs while gvsd runs and checks what gvsd reports.
# usage: gvsd_gpio_sim.sh GVS GVSD QEMU_VCAN_SH CACHE WORKDIR
set -euo pipefail
gvs=$1 gvsd=$2 harness=$3 cache=$4 work=$5
mkdir -p "$work"
rm -rf "$work/sine"
"$gvs" sim --scenario sine --seconds 6 --width 128 --height 96 --out "$work/sine" > /dev/null
exec "$harness" --cache "$cache" --timeout 600 --gpio-sim 4 -- /bin/sh "$(dirname "$0")/gvsd_gpio_sim_guest.sh" \
  "$gvsd" "$work/sine"

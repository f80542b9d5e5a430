#!/usr/bin/env bash
# gvsd.service under a real systemd (PID 1) in a qemu guest with Debian's
# kernel (it has vcan; this machine's kernel has no CAN): the package built
# here with cpack is installed in the guest; gvsd sends on vcan0 under the
# unit's whole sandbox; service_restart_check.sh (mode emulated) kills and
# hangs it. The guest's CPU is emulated: times are reported, the car's
# timing is asserted by service_nspawn.sh on the real CPU.
# usage: service_in_qemu.sh BUILD_DIR QEMU_VCAN_SH BENCH_CACHE FREEZE_TOOL
set -euo pipefail
build_dir=$(cd "$1" && pwd) qemu=$2 cache=$3 freeze=$4
here=$(cd "$(dirname "$0")" && pwd)
work=$build_dir/service_in_qemu
rm -rf "$work"; mkdir -p "$work"
(cd "$build_dir" && cpack -G DEB -B "$work" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; echo "FAIL: cpack -G DEB"; exit 1; }
deb=$(ls "$work"/gvs_*.deb | head -1)
"$qemu" --cache "$cache" --timeout 1500 --systemd -- sh "$here/service_restart_check.sh" emulated "$deb" "$freeze" |
  tee "$work/guest.log"
grep -q '^guest: all checks passed' "$work/guest.log" || { echo "FAIL: the guest's checks failed (above)"; exit 1; }
echo "OK"

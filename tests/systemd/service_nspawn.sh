#!/usr/bin/env bash
# gvsd.service under a real systemd on this machine's own kernel and CPU:
# systemd-nspawn boots systemd as PID 1 in a container whose root is this
# machine's root under an overlay (writes go to a scratch folder); the
# package built here with cpack is installed there and service_restart_check.sh
# (mode native) kills and hangs gvsd and times the recovery.
# usage: service_nspawn.sh BUILD_DIR FREEZE_TOOL
set -euo pipefail
build_dir=$(cd "$1" && pwd) freeze=$2
here=$(cd "$(dirname "$0")" && pwd)
work=$build_dir/service_nspawn
fail() { echo "FAIL: $*"; exit 1; }
[[ $(id -u) -eq 0 ]] || fail "needs root (systemd-nspawn and an overlay mount)"
if ! command -v systemd-nspawn >/dev/null; then
  apt-get install -y -qq systemd-container >/dev/null 2>&1 || fail "systemd-nspawn missing: apt-get install systemd-container"
fi
mountpoint -q "$work/root" 2>/dev/null && umount "$work/root"
rm -rf "$work"; mkdir -p "$work"/{upper,overlay-work,root,out,deb}
(cd "$build_dir" && cpack -G DEB -B "$work/deb" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack -G DEB"; }
deb=$(ls "$work"/deb/gvs_*.deb | head -1)

mount -t overlay overlay -o "lowerdir=/,upperdir=$work/upper,workdir=$work/overlay-work" "$work/root" ||
  fail "cannot mount an overlay of / on $work/root"
trap 'umount "$work/root" 2>/dev/null || umount -l "$work/root"' EXIT
# The command as the only job of the boot: gvs-bench.target = basic.target + it.
units=$work/root/etc/systemd/system
printf '%s\n' '[Unit]' 'Requires=basic.target gvs-bench.service' 'After=basic.target gvs-bench.service' \
  'AllowIsolate=yes' > "$units/gvs-bench.target"
printf '%s\n' '[Unit]' 'After=basic.target' '[Service]' 'Type=oneshot' \
  "ExecStart=/bin/sh -c 'GVS_BENCH_OUT=/gvs-out sh $here/service_restart_check.sh native $deb $freeze > /gvs-out/output.log 2>&1; echo \$? > /gvs-out/rc; systemctl poweroff'" \
  > "$units/gvs-bench.service"
# CAP_IPC_LOCK is not in nspawn's default set; the unit grants it to gvsd.
timeout 600 systemd-nspawn -D "$work/root" --register=no --keep-unit --quiet -b --capability=CAP_IPC_LOCK \
  --bind="$work/out:/gvs-out" --bind-ro="$here" --bind-ro="$build_dir" \
  -- systemd.unit=gvs-bench.target </dev/null >"$work/console.log" 2>&1 || true
[[ -f "$work/out/output.log" ]] || { tail -n 30 "$work/console.log"; fail "the container did not run the check (console above)"; }
cat "$work/out/output.log"
[[ "$(cat "$work/out/rc" 2>/dev/null)" == 0 ]] || fail "the check failed in the container"
echo "OK"

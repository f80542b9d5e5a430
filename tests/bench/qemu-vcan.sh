#!/bin/bash
# qemu-vcan.sh — run a command on a virtual CAN bus (vcan0) inside a Debian
# kernel booted under qemu, for machines whose own kernel has no CAN support.
#
#   tests/bench/qemu-vcan.sh [--cache DIR] [--timeout SEC] [--gpio-sim LINES] [--systemd] [--prepare-only] -- COMMAND [ARG...]
#
# The guest runs Debian 12's kernel (linux-image-amd64 → linux-image-6.1.0-*-amd64,
# fetched with apt-get download into the cache) with a busybox initramfs that
# loads the CAN and 9p modules, creates and raises vcan0, mounts the host's
# root read-only over 9p and runs COMMAND chrooted into it (same paths, same
# libraries, the host's current directory). /tmp in the guest is the host's
# /tmp under a tmpfs overlay (a checkout or cache under /tmp stays visible;
# the guest's writes stay in the guest); $GVS_BENCH_OUT (a per-run folder
# under the cache) is writable and shared with the host. COMMAND's output appears on this script's stdout;
# the script exits with COMMAND's exit code.
#
# --systemd boots systemd as PID 1 instead: the host root (read-only 9p)
# under a tmpfs overlay, so the guest can install packages and start units,
# and COMMAND runs as the unit gvs-bench.service of the target
# gvs-bench.target (basic.target, nothing of the host's multi-user.target);
# its output is printed when the guest has powered off.
# --gpio-sim LINES also loads gpio-sim.ko, the kernel's GPIO simulator, built
# out of tree for the same kernel ABI by tests/bench/build-gpio-sim.sh
# (linux-source-6.1 + linux-headers-<abi>, cached in the cache folder), mounts
# configfs and creates one simulated chip with LINES lines (label gvs-sim).
# COMMAND then sees GVS_GPIO_SIM_CHIP (/dev/gpiochipN) and GVS_GPIO_SIM_SYSFS
# (/sys/devices/platform/gpio-sim.0/gpiochipN, with sim_gpioK/value = the
# line's level as driven by its consumer).
#
# Exit codes: COMMAND's own; 125 if the guest did not boot or did not report
# (message and console tail on stderr); 126 if qemu/kernel/busybox cannot be
# installed (no network, not root); 124 on timeout (console tail on stderr).
# A guest kernel that shows no sign of its init within 240 s is killed and
# booted once more (an emulator hang, not the command's).
#
# Needs (installed with apt-get when missing and running as root):
# qemu-system-x86, busybox-static, xz-utils; the kernel package is
# downloaded (not installed) with apt-get download. --gpio-sim also needs
# linux-source-6.1, linux-headers-<abi> and gcc-12 (build-gpio-sim.sh).
set -euo pipefail

CACHE="${GVS_BENCH_CACHE:-${PWD}/bench-cache}"
TIMEOUT=300
PREPARE_ONLY=0
SYSTEMD=0
MEMORY_MB=1024
GPIO_SIM_LINES=0

die() { echo "qemu-vcan: $*" >&2; exit "${2:-126}"; }

while [[ $# -gt 0 ]]; do
  case "$1" in
    --cache) CACHE="$2"; shift 2 ;;
    --timeout) TIMEOUT="$2"; shift 2 ;;
    --prepare-only) PREPARE_ONLY=1; shift ;;
    --systemd) SYSTEMD=1; shift ;;
    --gpio-sim) GPIO_SIM_LINES="$2"; shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n '2,33p' "$0"; exit 0 ;;
    *) break ;;
  esac
done
if [[ $PREPARE_ONLY -eq 0 && $# -eq 0 ]]; then
  die "no command given; usage: $0 [--cache DIR] [--timeout SEC] -- COMMAND [ARG...]" 2
fi
mkdir -p "$CACHE"
CACHE="$(cd "$CACHE" && pwd)"

# --- host tools --------------------------------------------------------------
need_pkgs=()
command -v qemu-system-x86_64 >/dev/null || need_pkgs+=(qemu-system-x86)
{ [[ -x /bin/busybox ]] && /bin/busybox --list 2>/dev/null | grep -x insmod >/dev/null; } || need_pkgs+=(busybox-static)
command -v xz >/dev/null || need_pkgs+=(xz-utils)
if [[ ${#need_pkgs[@]} -gt 0 ]]; then
  [[ $(id -u) -eq 0 ]] || die "missing ${need_pkgs[*]} and not root: install them with apt-get install ${need_pkgs[*]}"
  echo "qemu-vcan: installing ${need_pkgs[*]} with apt-get" >&2
  (apt-get install -y -qq "${need_pkgs[@]}" >/dev/null 2>&1 ||
    { apt-get update -qq >/dev/null 2>&1 && apt-get install -y -qq "${need_pkgs[@]}" >/dev/null 2>&1; }) ||
    die "apt-get install ${need_pkgs[*]} failed (no network or no Debian mirror?); install them and retry"
fi
file /bin/busybox 2>/dev/null | grep -q 'statically linked' || [[ ! -x /usr/bin/file ]] ||
  die "/bin/busybox is not statically linked: install busybox-static (apt-get install busybox-static)"

# --- kernel and modules --------------------------------------------------------
KDIR="$CACHE/kernel"
if [[ ! -f "$KDIR/.ready" ]]; then
  rm -rf "$KDIR"; mkdir -p "$KDIR/deb"
  pkg="$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/ {print $2; exit}')"
  if [[ -z "$pkg" ]]; then
    apt-get update -qq >/dev/null 2>&1 || true
    pkg="$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/ {print $2; exit}')"
  fi
  [[ -n "$pkg" ]] || die "cannot resolve linux-image-amd64 with apt-cache (run apt-get update; network needed)"
  echo "qemu-vcan: downloading $pkg" >&2
  (cd "$KDIR/deb" && apt-get download "$pkg" >/dev/null 2>&1) ||
    { apt-get update -qq >/dev/null 2>&1 || true; (cd "$KDIR/deb" && apt-get download "$pkg" >/dev/null 2>&1); } ||
    die "apt-get download $pkg failed (no network?)"
  dpkg -x "$KDIR"/deb/*.deb "$KDIR/root" || die "dpkg -x of $pkg failed"
  dpkg-deb -f "$KDIR"/deb/*.deb Version > "$KDIR/image-version"
  rm -rf "$KDIR/deb"
  touch "$KDIR/.ready"
fi
VMLINUZ="$(ls "$KDIR"/root/boot/vmlinuz-* | head -1)"
KVER="${VMLINUZ##*/vmlinuz-}"
MODDIR="$KDIR/root/lib/modules/$KVER"

# --- gpio-sim (optional) ----------------------------------------------------------
INITRD_TAG=""
if [[ "$GPIO_SIM_LINES" != 0 ]]; then
  [[ "$GPIO_SIM_LINES" =~ ^[1-9][0-9]?$ ]] || die "--gpio-sim wants a line count 1..99, got '$GPIO_SIM_LINES'" 2
  image_version="$(cat "$KDIR/image-version" 2>/dev/null ||
    apt-cache show "linux-image-$KVER" 2>/dev/null | awk '/^Version:/ {print $2; exit}')"
  "$(dirname "$0")/build-gpio-sim.sh" "$KVER" "$CACHE/gpio-sim-$KVER" "$image_version" >&2 ||
    die "cannot build gpio-sim.ko for $KVER (see above)" $?
  INITRD_TAG="-gpio-sim"
fi

# --- initramfs -----------------------------------------------------------------
WANT_MODULES=(configfs can-dev vcan can can-raw virtio_ring virtio virtio_pci_modern_dev
  virtio_pci_legacy_dev virtio_pci netfs fscache 9pnet 9pnet_virtio 9p overlay)
INITRD="$CACHE/initramfs-$KVER$INITRD_TAG.cpio.gz"
if [[ ! -f "$INITRD" || "$0" -nt "$INITRD" || ( -n "$INITRD_TAG" && "$CACHE/gpio-sim-$KVER/gpio-sim.ko" -nt "$INITRD" ) ]]; then
  IR="$CACHE/initramfs-root"
  rm -rf "$IR"; mkdir -p "$IR"/{bin,dev,proc,sys,host,modules,tmp}
  cp /bin/busybox "$IR/bin/busybox"
  # Resolve each module's file and its dependencies (the "depends=" entry of
  # its .modinfo; the package ships no modules.dep and depmod may be absent);
  # load dependencies first; names not found are built into the kernel.
  declare -A seen=() path_of=()
  while IFS= read -r f; do
    n="${f##*/}"; n="${n%%.ko*}"; path_of[${n//-/_}]="$f"
  done < <(find "$MODDIR/kernel" -name '*.ko' -o -name '*.ko.xz' -o -name '*.ko.zst')
  order=()
  modinfo_depends() {
    case "$1" in
      *.ko.xz) xz -dc "$1" ;; *.ko.zst) zstd -qdc "$1" ;; *) cat "$1" ;;
    esac | grep -a -o 'depends=[A-Za-z0-9_,-]*' | head -1 | sed 's/^depends=//; s/,/ /g'
  }
  add_module() {
    local key="${1//-/_}" path dep
    path="${path_of[$key]:-}"
    [[ -n "$path" ]] || return 0
    [[ -z "${seen[$key]:-}" ]] || return 0
    seen[$key]=1
    for dep in $(modinfo_depends "$path"); do add_module "$dep"; done
    order+=("${path#"$MODDIR/"}")
  }
  for m in "${WANT_MODULES[@]}"; do add_module "$m"; done
  : > "$IR/modules/order"
  for path in "${order[@]}"; do
    base="$(basename "$path")"
    case "$base" in
      *.ko.xz) xz -dc "$MODDIR/$path" > "$IR/modules/${base%.xz}"; base="${base%.xz}" ;;
      *.ko.zst) zstd -qdc "$MODDIR/$path" > "$IR/modules/${base%.zst}"; base="${base%.zst}" ;;
      *) cp "$MODDIR/$path" "$IR/modules/$base" ;;
    esac
    echo "$base" >> "$IR/modules/order"
  done
  [[ -z "$INITRD_TAG" ]] || cp "$CACHE/gpio-sim-$KVER/gpio-sim.ko" "$IR/modules/gpio-sim.ko"
  cat > "$IR/init" <<'INIT'
#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc; mount -t sysfs sys /sys; mount -t devtmpfs dev /dev
echo "gvs-bench: init started"
for m in $(cat /modules/order); do insmod /modules/$m 2>/dev/null || echo "gvs-bench: insmod $m failed"; done
set -- $(cat /proc/cmdline)
RUN=""; SYSTEMD=""; GPIO_SIM=0
for a; do case "$a" in gvs.run=*) RUN="${a#gvs.run=}";; gvs.systemd=1) SYSTEMD=1;; gvs.gpiosim=*) GPIO_SIM="${a#gvs.gpiosim=}";; esac; done
fail() { echo "gvs-bench: $*"; poweroff -f; }
if [ "$GPIO_SIM" != 0 ]; then
  insmod /modules/gpio-sim.ko || fail "insmod gpio-sim.ko failed"
  mkdir -p /sys/kernel/config
  mount -t configfs none /sys/kernel/config || fail "cannot mount configfs"
  G=/sys/kernel/config/gpio-sim/gvs
  mkdir $G $G/bank0 || fail "cannot create a gpio-sim chip in configfs"
  echo "$GPIO_SIM" > $G/bank0/num_lines; echo gvs-sim > $G/bank0/label
  echo 1 > $G/live || fail "cannot bring the gpio-sim chip live"
  export GVS_GPIO_SIM_CHIP="/dev/$(cat $G/bank0/chip_name)"
  export GVS_GPIO_SIM_SYSFS="/sys/devices/platform/$(cat $G/dev_name)/$(cat $G/bank0/chip_name)"
  echo "gvs-bench: gpio-sim $GVS_GPIO_SIM_CHIP with $GPIO_SIM lines"
fi
ip link add dev vcan0 type vcan || fail "cannot create vcan0"
ip link set vcan0 up || fail "cannot raise vcan0"
mount -t 9p -o trans=virtio,version=9p2000.L,ro hostroot /host || fail "cannot mount the host root over 9p"
if [ -n "$SYSTEMD" ]; then
  # systemd as PID 1 on the host root with a writable tmpfs overlay.
  mkdir -p /overlay /newroot
  mount -t tmpfs -o size=768m,mode=0755 upper /overlay
  mkdir -p /overlay/upper /overlay/work
  mount -t overlay overlay -o lowerdir=/host,upperdir=/overlay/upper,workdir=/overlay/work /newroot ||
    fail "cannot mount the overlay root"
  mount -t 9p -o trans=virtio,version=9p2000.L gvsrun "/newroot$RUN" || fail "cannot mount the run folder"
  # /tmp stays the overlay's view of the host's /tmp (the run folder or the
  # whole checkout may be under it); tmp.conf masked so systemd-tmpfiles
  # does not empty it at boot.
  mkdir -p /newroot/etc/tmpfiles.d
  : > /newroot/etc/tmpfiles.d/tmp.conf
  U=/newroot/etc/systemd/system
  mkdir -p "$U"
  printf '%s\n' '[Unit]' 'Description=gvs bench target' 'Requires=basic.target gvs-bench.service' \
    'After=basic.target gvs-bench.service' 'AllowIsolate=yes' > "$U/gvs-bench.target"
  printf '%s\n' '[Unit]' 'Description=gvs bench command' 'After=basic.target' '[Service]' 'Type=oneshot' \
    "ExecStart=/bin/sh -c '/bin/sh $RUN/cmd.sh > $RUN/output.log 2>&1; echo \$? > $RUN/rc; sync; systemctl poweroff -ff'" \
    > "$U/gvs-bench.service"
  umount /proc /sys 2>/dev/null; umount /dev 2>/dev/null
  exec switch_root /newroot /lib/systemd/systemd systemd.unit=gvs-bench.target
fi
# /tmp before the run folder, which may be under it: the host's /tmp (the
# checkout may be there) under a tmpfs overlay, so the guest can write.
mkdir -p /tmpover
mount -t tmpfs -o mode=0755 tmpover /tmpover
mkdir -p /tmpover/upper /tmpover/work; chmod 1777 /tmpover/upper
mount -t overlay overlay -o lowerdir=/host/tmp,upperdir=/tmpover/upper,workdir=/tmpover/work /host/tmp ||
  fail "cannot mount the /tmp overlay"
mount -t 9p -o trans=virtio,version=9p2000.L gvsrun "/host$RUN" || fail "cannot mount the run folder"
mount -t proc proc /host/proc; mount -t sysfs sys /host/sys; mount -t devtmpfs dev /host/dev
echo "gvs-bench: guest up, vcan0 ready"
chroot /host /bin/sh "$RUN/cmd.sh" < /dev/console > /dev/console 2>&1
echo $? > "/host$RUN/rc"
sync
poweroff -f
INIT
  chmod +x "$IR/init"
  (cd "$IR" && find . | busybox cpio -o -H newc 2>/dev/null | gzip -1) > "$INITRD.tmp"
  mv "$INITRD.tmp" "$INITRD"
  rm -rf "$IR"
fi
[[ $PREPARE_ONLY -eq 1 ]] && { echo "qemu-vcan: kernel $KVER and initramfs ready in $CACHE"; exit 0; }

# --- run -------------------------------------------------------------------------
RUN="$(mktemp -d "$CACHE/run.XXXXXX")"
mkdir -p "$RUN/out"
{
  echo "export PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin"
  echo "export HOME=/tmp GVS_BENCH_OUT=$(printf '%q' "$RUN/out") GVS_IN_QEMU_VCAN=1"
  echo "cd $(printf '%q' "$PWD") || exit 125"
  printf '%q ' "$@"; echo
} > "$RUN/cmd.sh"

EXTRA_APPEND=""
[[ $SYSTEMD -eq 1 ]] && EXTRA_APPEND=" gvs.systemd=1 systemd.show_status=0 systemd.log_level=warning"

# One boot of the guest. A kernel under software emulation that has not run
# the initramfs's init within BOOT_TIMEOUT seconds is hung in the emulator,
# not in the command: it is killed and booted once more. A command that
# hangs is never retried.
boot_guest() {
  rm -f "$RUN/rc" "$RUN/qemu.pid" "$RUN/qemu_rc"
  { timeout --foreground "$TIMEOUT" qemu-system-x86_64 -m "$MEMORY_MB" -smp 2 -nographic -no-reboot \
      -pidfile "$RUN/qemu.pid" -kernel "$VMLINUZ" -initrd "$INITRD" \
      -append "console=ttyS0 quiet loglevel=3 panic=-1 gvs.run=$RUN gvs.gpiosim=$GPIO_SIM_LINES$EXTRA_APPEND" \
      -virtfs "local,path=/,mount_tag=hostroot,security_model=none,readonly=on,multidevs=remap" \
      -virtfs "local,path=$RUN,mount_tag=gvsrun,security_model=none,multidevs=remap" \
      -nic none < /dev/null 2>&1; echo $? > "$RUN/qemu_rc"; } | tee "$RUN/console.log" |
    awk '{ sub(/\r$/, "") } /gvs-bench: guest up/ { on = 1; next } on && !/^\[ *[0-9]+\.[0-9]+\] reboot: / { print; fflush() }' &
  local pipeline=$! waited=0
  while kill -0 "$pipeline" 2>/dev/null && ! grep -q "gvs-bench: init started" "$RUN/console.log" 2>/dev/null; do
    if [[ $waited -ge $BOOT_TIMEOUT ]]; then
      echo "qemu-vcan: the guest kernel did not reach its init within ${BOOT_TIMEOUT}s. Console tail:" >&2
      tail -n 20 "$RUN/console.log" >&2
      [[ -f "$RUN/qemu.pid" ]] && kill "$(cat "$RUN/qemu.pid")" 2>/dev/null
      wait "$pipeline"
      return 2
    fi
    sleep 1
    waited=$((waited + 1))
  done
  wait "$pipeline"
  qemu_rc="$(cat "$RUN/qemu_rc" 2>/dev/null || echo 125)"
  return 0
}

BOOT_TIMEOUT=240
qemu_rc=0
set +e
boot_guest
if [[ $? -eq 2 ]]; then
  echo "qemu-vcan: booting the guest once more" >&2
  boot_guest || { echo "qemu-vcan: the guest did not boot twice; console log: $RUN/console.log" >&2; exit 125; }
fi
set -e
if [[ $qemu_rc -eq 124 ]]; then
  echo "qemu-vcan: timed out after ${TIMEOUT}s; console log: $RUN/console.log. Console tail:" >&2
  tail -n 30 "$RUN/console.log" >&2
  exit 124
fi
if [[ ! -f "$RUN/rc" ]]; then
  echo "qemu-vcan: the guest did not run the command (qemu exit $qemu_rc). Console tail:" >&2
  tail -n 30 "$RUN/console.log" >&2
  exit 125
fi
rc="$(cat "$RUN/rc")"
[[ $SYSTEMD -eq 1 && -f "$RUN/output.log" ]] && cat "$RUN/output.log"
rm -rf "$RUN"
exit "$rc"

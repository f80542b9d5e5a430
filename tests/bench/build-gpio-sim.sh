#!/bin/bash
# build-gpio-sim.sh — builds gpio-sim.ko (the kernel's GPIO simulator) out of
# tree for a Debian 12 kernel that ships without it (CONFIG_GPIO_SIM unset).
#
#   tests/bench/build-gpio-sim.sh KVER OUTDIR [IMAGE_VERSION]
#
# KVER is the kernel ABI (e.g. 6.1.0-56-amd64), IMAGE_VERSION the Debian
# version of linux-image-KVER (e.g. 6.1.192-2; compared with linux-source-6.1's
# and a difference reported). Sources: linux-source-6.1's
# drivers/gpio/gpio-sim.c, drivers/gpio/gpiolib.h and kernel/irq/irq_sim.c
# (the irq simulator gpio-sim needs; CONFIG_IRQ_SIM is unset too). The kernel
# does not export irq_to_desc() to modules, so irq_sim.c's
# handle_simple_irq(irq_to_desc(irqnum)) becomes generic_handle_irq(irqnum).
# Both go into one module, built with Kbuild against linux-headers-KVER
# (gcc-12, as the image). The module is unsigned: it loads, tainting the
# kernel, because Debian does not enforce signatures without Secure Boot.
#
# Writes OUTDIR/gpio-sim.ko and OUTDIR/build.log; prints one line saying
# which sources and headers it used. Exit 0 when built (or already built for
# the same inputs), 126 when a package is missing and cannot be installed,
# 1 when the build fails (log tail on stderr).
set -euo pipefail

die() { echo "build-gpio-sim: $*" >&2; exit "${2:-126}"; }
[[ $# -ge 2 ]] || die "usage: $0 KVER OUTDIR [IMAGE_VERSION]" 2
KVER=$1 OUT=$2 IMAGE_VERSION=${3:-}
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
need=()
installed linux-source-6.1 || need+=(linux-source-6.1)
[[ -f "/usr/src/linux-headers-$KVER/Makefile" ]] || need+=("linux-headers-$KVER")
command -v make >/dev/null && command -v gcc-12 >/dev/null || need+=(build-essential gcc-12)
if [[ ${#need[@]} -gt 0 ]]; then
  [[ $(id -u) -eq 0 ]] || die "missing ${need[*]} and not root: install them with apt-get install ${need[*]}"
  echo "build-gpio-sim: installing ${need[*]} with apt-get" >&2
  export DEBIAN_FRONTEND=noninteractive
  (apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null 2>&1 ||
    { apt-get update -qq >/dev/null 2>&1 && apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null 2>&1; }) ||
    die "apt-get install ${need[*]} failed (no network, or linux-headers-$KVER no longer in the archive: refresh the bench cache so the kernel and headers match)"
fi

SOURCE_VERSION="$(dpkg-query -W -f='${Version}' linux-source-6.1)"
HEADERS="/usr/src/linux-headers-$KVER"
TARBALL=/usr/src/linux-source-6.1.tar.xz
[[ -f "$TARBALL" ]] || die "$TARBALL missing although linux-source-6.1 is installed: reinstall it (apt-get install --reinstall linux-source-6.1)"
note=""
if [[ -n "$IMAGE_VERSION" && "$IMAGE_VERSION" != "$SOURCE_VERSION" ]]; then
  note=" — WARNING: linux-source-6.1 is $SOURCE_VERSION but the image is $IMAGE_VERSION; gpio-sim and irq_sim rarely change within 6.1 but the module may not match the kernel's internals"
fi
STAMP="source $SOURCE_VERSION, headers $KVER"

if [[ -f "$OUT/gpio-sim.ko" && -f "$OUT/stamp" && "$(cat "$OUT/stamp")" == "$STAMP" && "$OUT/stamp" -nt "$0" ]]; then
  echo "build-gpio-sim: gpio-sim.ko cached ($STAMP)$note"
  exit 0
fi

SRC="$OUT/src"
rm -rf "$SRC" "$OUT/gpio-sim.ko" "$OUT/stamp"
mkdir -p "$SRC"
files=(drivers/gpio/gpio-sim.c drivers/gpio/gpiolib.h kernel/irq/irq_sim.c)
tar -xJf "$TARBALL" -C "$SRC" --strip-components=1 "${files[@]/#/linux-source-6.1/}" ||
  die "cannot extract ${files[*]} from $TARBALL" 1
mv "$SRC"/drivers/gpio/gpio-sim.c "$SRC/gpio_sim_main.c"
mv "$SRC"/drivers/gpio/gpiolib.h "$SRC"/kernel/irq/irq_sim.c "$SRC/"
rm -rf "$SRC/drivers" "$SRC/kernel"
grep -q 'handle_simple_irq(irq_to_desc(irqnum));' "$SRC/irq_sim.c" ||
  die "irq_sim.c of linux-source $SOURCE_VERSION no longer calls handle_simple_irq(irq_to_desc(irqnum)): update this script's patch" 1
sed -i 's/handle_simple_irq(irq_to_desc(irqnum));/generic_handle_irq(irqnum);/' "$SRC/irq_sim.c"
cat > "$SRC/Kbuild" <<'KBUILD'
obj-m := gpio-sim.o
gpio-sim-y := gpio_sim_main.o irq_sim.o
KBUILD

if ! make -C "$HEADERS" M="$SRC" CC=gcc-12 modules > "$OUT/build.log" 2>&1; then
  echo "build-gpio-sim: the module build failed against $HEADERS; log $OUT/build.log:" >&2
  tail -n 20 "$OUT/build.log" >&2
  exit 1
fi
cp "$SRC/gpio-sim.ko" "$OUT/gpio-sim.ko"
echo "$STAMP" > "$OUT/stamp"
echo "build-gpio-sim: built gpio-sim.ko ($STAMP)$note"

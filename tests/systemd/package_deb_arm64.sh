#!/usr/bin/env bash
# package_deb_arm64.sh BUILD_DIR SYSROOT: the arm64 Debian package of the
# cross build (preset arm64, cmake/GvsPackage.cmake): built with cpack as the
# amd64 one, it has Architecture arm64, the same files, aarch64 programs,
# Depends from the arm64 libraries' shlibs files (cmake/GvsCrossShlibs.cmake)
# naming the same Debian packages as the amd64 one, man pages written under
# qemu-user, and its gvsd reads its configuration under qemu-aarch64.
# Installing it on an arm64 board: docs/deployment.md, "The arm64 package".
set -euo pipefail
build_dir=$1 sysroot=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
for tool in cpack dpkg-deb qemu-aarch64 aarch64-linux-gnu-readelf; do
  command -v "$tool" >/dev/null || fail "$tool not installed (scripts/install-deps installs it)"
done

source "$(dirname "$0")/package_checks.sh"
package_build "$build_dir"
[[ "$deb" == *_arm64.deb ]] || fail "$(basename "$deb") is not named _arm64.deb"
[[ "$(dpkg-deb -f "$deb" Architecture)" == arm64 ]] || fail "Architecture is $(dpkg-deb -f "$deb" Architecture)"
package_check_depends libc6 libstdc++6 libgcc-s1 libopencv-core406 libopencv-imgproc406 libopencv-calib3d406 \
  libopencv-features2d406 libpng16-16 libspdlog1.10 libfmt9 libgpiod2 libfftw3-single3 systemd procps
package_check_control

root=$work/root
dpkg-deb -x "$deb" "$root"
for p in gvsd gvs; do
  aarch64-linux-gnu-readelf -h "$root/usr/bin/$p" | grep -q 'Machine:.*AArch64' || fail "/usr/bin/$p is not an AArch64 program"
done
for p in gvsd gvs; do
  zcat "$root/usr/share/man/man1/$p.1.gz" | grep -q '^\.SH OPTIONS' || fail "$p.1.gz has no OPTIONS section"
done
out=$(qemu-aarch64 -L "$sysroot" "$root/usr/bin/gvsd" --check-config --config "$root/etc/gvsd/gvsd.toml" 2>&1) ||
  fail "packaged gvsd --check-config under qemu-aarch64: $out"
echo "$out"
grep -q 'configuration OK' <<<"$out" || fail "packaged gvsd does not accept the packaged configuration"
echo "OK"

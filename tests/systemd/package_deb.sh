#!/usr/bin/env bash
# The Debian package (cmake/GvsPackage.cmake): builds it with cpack from the
# release build tree, checks its contents, dependencies, maintainer scripts
# and conffile, unpacks it into a scratch root and checks there that the unit
# verifies (`systemd-analyze verify --root`), that the packaged gvsd reads the
# packaged configuration, and that the packaged gvs finds its plot script.
# Installing it into a clean Debian root with apt is scripts/check-package-chroot
# (network and minutes: documented in docs/deployment.md, not run here).
set -euo pipefail
build_dir=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
for tool in cpack dpkg-deb dpkg-shlibdeps systemd-analyze; do
  command -v "$tool" >/dev/null || fail "$tool not installed (scripts/install-deps installs it)"
done

source "$(dirname "$0")/package_checks.sh"
package_build "$build_dir"
package_check_depends libc6 libstdc++6 libopencv-core406 libopencv-imgproc406 libpng16-16 libspdlog1.10 libgpiod2 \
  systemd procps
package_check_control
grep -q systemd-sysusers "$work/control/postinst" || fail "postinst does not create the gvsd user"
# What the package tells its user names files it ships.
for doc in $(grep -ohE '/usr/share/doc/gvs/[A-Za-z-]+\.md' "$work/control/postinst" <(dpkg-deb --fsys-tarfile "$deb" |
             tar -xO ./etc/gvsd/gvsd.toml) | sort -u); do
  grep -qxF ".$doc" <<<"$contents" || fail "the package points to $doc, which it does not ship"
done
grep -q '/usr/share/doc/gvs/deployment.md' "$work/control/postinst" || fail "postinst does not point to deployment.md"
grep -q 'docs/' <(dpkg-deb --fsys-tarfile "$deb" | tar -xO ./etc/gvsd/gvsd.toml) &&
  fail "the packaged gvsd.toml names docs/ paths the package does not have"

root=$work/root
dpkg-deb -x "$deb" "$root"
# The rest of a system the unit refers to: usrmerge as on Debian 12 (/bin
# and /lib are /usr's), systemd's own units (sysinit.target, ...) and kill.
ln -s usr/bin "$root/bin"; ln -s usr/lib "$root/lib"
cp -n /usr/lib/systemd/system/*.target /usr/lib/systemd/system/*.slice /usr/lib/systemd/system/*.socket \
   "$root/usr/lib/systemd/system/" 2>/dev/null || true
cp "$(readlink -f /bin/kill)" "$root/usr/bin/kill"
systemd-analyze verify --root="$root" --man=no gvsd.service >"$work/verify.log" 2>&1 ||
  { cat "$work/verify.log"; fail "systemd-analyze verify on the installed unit"; }
echo "systemd-analyze verify --root: passed"

grep -q '^uri = "socketcan:can0"' "$root/etc/gvsd/gvsd.toml" || fail "packaged configuration does not send on can0"
grep -q '^uri = "libcamera"' "$root/etc/gvsd/gvsd.toml" || fail "packaged configuration does not read the camera"
"$root/usr/bin/gvsd" --check-config --config "$root/etc/gvsd/gvsd.toml" || fail "packaged gvsd refuses the packaged configuration"
sed 's/^period_ms = 20 /period_ms = 0 /' "$root/etc/gvsd/gvsd.toml" > "$work/bad.toml"
if out=$("$root/usr/bin/gvsd" --check-config --config "$work/bad.toml" 2>&1); then fail "--check-config accepted period_ms = 0"; fi
grep -q period_ms <<<"$out" || fail "--check-config did not name period_ms: $out"
# gvs eval --plot finds <prefix>/share/gvs/gvs_plot.py beside <prefix>/bin/gvs.
"$root/usr/bin/gvs" sim --scenario stop --seconds 0.2 --out "$work/ds" >/dev/null
"$root/usr/bin/gvs" replay "$work/ds" --out "$work/est.csv" >/dev/null
if /usr/bin/python3 -c 'import matplotlib' 2>/dev/null; then
  (cd / && "$root/usr/bin/gvs" eval "$work/ds" "$work/est.csv" --plot "$work/p.png" >/dev/null) || fail "packaged gvs eval --plot"
  [[ -s "$work/p.png" ]] || fail "no plot written"
else
  fail "python3-matplotlib missing under /usr/bin/python3 (scripts/install-deps installs it)"
fi
echo "OK"

# Checks shared by package_deb.sh (amd64) and package_deb_arm64.sh, sourced
# after `work` (a scratch folder) and `fail` are set.

# package_build BUILD_DIR: cpack's .deb of the build tree in $deb, its file
# list in $contents, checked for every file the package must ship.
package_build() {
  (cd "$1" && cpack -G DEB -B "$work/out" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack -G DEB"; }
  deb=$(ls "$work"/out/gvs_*.deb 2>/dev/null | head -1)
  [[ -f "$deb" ]] || fail "no gvs_*.deb in $work/out"
  echo "package: $(basename "$deb"), $(du -k "$deb" | cut -f1) KiB"
  contents=$(dpkg-deb -c "$deb" | awk '{print $NF}')
  local f
  for f in ./usr/bin/gvsd ./usr/bin/gvs ./usr/lib/systemd/system/gvsd.service ./usr/lib/sysusers.d/gvsd.conf \
           ./usr/lib/udev/rules.d/60-gvsd.rules ./etc/gvsd/gvsd.toml ./usr/share/gvs/gvs.dbc \
           ./usr/share/gvs/gvs_plot.py ./usr/share/doc/gvs/deployment.md ./usr/share/doc/gvs/README.md \
           ./usr/share/man/man1/gvs.1.gz ./usr/share/man/man1/gvsd.1.gz; do
    grep -qxF "$f" <<<"$contents" || fail "$f is not in the package"
  done
}

# package_check_depends LIB...: Depends names every LIB and none of what the
# lean daemon (issue #22) leaves out: no image codecs (GDAL, Poppler, HDF5,
# ... come with them), no libsystemd (gvsd speaks sd_notify itself), no
# shared toml++. Depends in $depends.
package_check_depends() {
  depends=$(dpkg-deb -f "$deb" Depends)
  echo "Depends: $depends"
  local lib
  for lib in "$@"; do
    grep -q "$lib" <<<"$depends" || fail "Depends lacks $lib"
  done
  for lib in libopencv-imgcodecs libsystemd0 libtomlplusplus; do
    grep -q "$lib" <<<"$depends" && fail "Depends has $lib"
  done
  return 0
}

# package_check_control: the conffile and the maintainer scripts, unpacked
# into $work/control.
package_check_control() {
  dpkg-deb -e "$deb" "$work/control"
  grep -qx /etc/gvsd/gvsd.toml "$work/control/conffiles" || fail "/etc/gvsd/gvsd.toml is not a conffile"
  local s
  for s in postinst prerm postrm; do [[ -x "$work/control/$s" ]] || fail "maintainer script $s missing"; done
}

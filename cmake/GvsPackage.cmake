# Installation layout and the Debian package (cpack -G DEB).
#   cmake --preset release && cmake --build --preset release
#   (cd build/release && cpack -G DEB)    -> build/release/gvs_<version>_<arch>.deb
# Contents: gvsd and gvs in /usr/bin, the unit, its user (sysusers.d) and
# udev rules, the car configuration in /etc/gvsd/, the DBC and the plot
# script in /usr/share/gvs/, the docs in /usr/share/doc/gvs/, the manual
# pages gvs(1) and gvsd(1) in /usr/share/man/man1/. Dependencies
# come from dpkg-shlibdeps (Debian's own library packages).
# The arm64 cross build (preset arm64) packages the same files as
#   (cd build/arm64 && cpack -G DEB)      -> build/arm64/gvs_<version>_arm64.deb
# with its dependencies from the arm64 libraries' shlibs files
# (cmake/GvsCrossShlibs.cmake) and the man pages written under qemu-user.

include(GNUInstallDirs)

install(TARGETS gvsd gvs RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT gvs)
install(FILES ${PROJECT_SOURCE_DIR}/daemon/scripts/gvs_plot.py DESTINATION ${CMAKE_INSTALL_DATADIR}/gvs COMPONENT gvs)
install(FILES ${PROJECT_SOURCE_DIR}/can/gvs.dbc DESTINATION ${CMAKE_INSTALL_DATADIR}/gvs COMPONENT gvs)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/gvsd.service DESTINATION lib/systemd/system COMPONENT gvs)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/gvsd.sysusers DESTINATION lib/sysusers.d RENAME gvsd.conf COMPONENT gvs)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/60-gvsd.rules DESTINATION lib/udev/rules.d COMPONENT gvs)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/gvs-vcan.service DESTINATION ${CMAKE_INSTALL_DATADIR}/gvs/bench COMPONENT gvs)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/systemd/gvs-vcan.sh DESTINATION ${CMAKE_INSTALL_DATADIR}/gvs/bench COMPONENT gvs)

# The car's configuration: the documented example with the car's source and
# bus. Without a camera gvsd stops at start with a message (never a
# simulated velocity on a real car's bus).
file(READ ${PROJECT_SOURCE_DIR}/systemd/gvsd.toml gvs_car_toml)
string(REPLACE "uri = \"sim:sine\"" "uri = \"libcamera\"" gvs_car_toml "${gvs_car_toml}")
string(REPLACE "uri = \"candump:-\"" "uri = \"socketcan:can0\"" gvs_car_toml "${gvs_car_toml}")
# Its references to docs/X.md name the copies the package ships.
string(REGEX REPLACE "docs/([a-z-]+\\.md)" "/usr/share/doc/gvs/\\1" gvs_car_toml "${gvs_car_toml}")
file(WRITE ${PROJECT_BINARY_DIR}/package/gvsd.toml "${gvs_car_toml}")
install(FILES ${PROJECT_BINARY_DIR}/package/gvsd.toml DESTINATION /etc/gvsd COMPONENT gvs)

# Manual pages, written at build time from the programs' own --help (every
# subcommand's too, cmake/gvs_manpage.py), so they say what the programs say.
set(gvs_man_dir ${PROJECT_BINARY_DIR}/man)
set(gvs_man_pages)
foreach(program gvs gvsd)
  add_custom_command(OUTPUT ${gvs_man_dir}/${program}.1 ${gvs_man_dir}/${program}.1.gz
    COMMAND ${CMAKE_COMMAND} -E make_directory ${gvs_man_dir}
    COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/cmake/gvs_manpage.py $<TARGET_FILE:${program}>
            ${gvs_man_dir}/${program}.1 ${CMAKE_CROSSCOMPILING_EMULATOR}
    DEPENDS ${program} ${PROJECT_SOURCE_DIR}/cmake/gvs_manpage.py
    COMMENT "Manual page ${program}.1 from ${program} --help"
    VERBATIM)
  list(APPEND gvs_man_pages ${gvs_man_dir}/${program}.1 ${gvs_man_dir}/${program}.1.gz)
  install(FILES ${gvs_man_dir}/${program}.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT gvs)
endforeach()
add_custom_target(gvs_man_pages ALL DEPENDS ${gvs_man_pages})

file(GLOB gvs_docs ${PROJECT_SOURCE_DIR}/docs/*.md)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${gvs_docs} DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT gvs)

set(CPACK_PACKAGE_NAME gvs)
set(CPACK_PACKAGE_VENDOR "gvs")
set(CPACK_PACKAGE_CONTACT "gvs maintainers <gvs@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "ground velocity sensor daemon for Formula Student cars (camera to CAN)")
set(CPACK_PACKAGE_DESCRIPTION "gvsd turns frames of a downward-looking camera into the car's velocity over the ground and sends it on CAN every 20 ms; gvs simulates, replays, evaluates and monitors.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "systemd, procps")
if(CMAKE_CROSSCOMPILING)
  # The arm64 build (cmake/toolchain-aarch64-linux-gnu.cmake): dpkg-shlibdeps
  # knows only the host's libraries; the Depends come from the sysroot's
  # shlibs files instead (cmake/GvsCrossShlibs.cmake, run by cpack).
  if(NOT CMAKE_SYSTEM_PROCESSOR STREQUAL "aarch64")
    message(FATAL_ERROR "GvsPackage: cross packaging knows aarch64 (arm64) only, not ${CMAKE_SYSTEM_PROCESSOR}")
  endif()
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE arm64)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS OFF)
  find_program(GVS_READELF NAMES aarch64-linux-gnu-readelf readelf REQUIRED)
  set(CPACK_GVS_READELF "${GVS_READELF}")
  set(CPACK_GVS_CROSS_SHLIBS "${CMAKE_SYSROOT}/var/lib/gvs-sysroot/shlibs")
  set(CPACK_GVS_CROSS_BINARIES "${PROJECT_BINARY_DIR}/bin/gvsd" "${PROJECT_BINARY_DIR}/bin/gvs")
  set(CPACK_PROJECT_CONFIG_FILE "${PROJECT_SOURCE_DIR}/cmake/GvsCrossShlibs.cmake")
else()
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
endif()
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-matplotlib, can-utils")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
  ${PROJECT_SOURCE_DIR}/systemd/debian/postinst
  ${PROJECT_SOURCE_DIR}/systemd/debian/prerm
  ${PROJECT_SOURCE_DIR}/systemd/debian/postrm
  ${PROJECT_SOURCE_DIR}/systemd/debian/conffiles)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)

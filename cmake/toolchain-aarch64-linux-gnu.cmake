# Cross build for the car's arm64 computer (preset arm64): Debian 12's cross
# compiler (g++-aarch64-linux-gnu, GCC 12) against the arm64 sysroot of
# scripts/arm64-sysroot (Debian 12's arm64 libraries and headers). The test
# programs run under qemu-user (qemu-aarch64 -L SYSROOT) as ctest's emulator.
# The sysroot: GVS_ARM64_SYSROOT (environment or cache), else
# ~/.cache/gvs/sysroot-arm64-bookworm, where scripts/arm64-sysroot puts it.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

if(NOT GVS_ARM64_SYSROOT)
  if(DEFINED ENV{GVS_ARM64_SYSROOT} AND NOT "$ENV{GVS_ARM64_SYSROOT}" STREQUAL "")
    set(GVS_ARM64_SYSROOT "$ENV{GVS_ARM64_SYSROOT}")
  else()
    set(GVS_ARM64_SYSROOT "$ENV{HOME}/.cache/gvs/sysroot-arm64-bookworm")
  endif()
endif()
set(GVS_ARM64_SYSROOT "${GVS_ARM64_SYSROOT}" CACHE PATH "arm64 sysroot (scripts/arm64-sysroot)")
if(NOT EXISTS "${GVS_ARM64_SYSROOT}/var/lib/gvs-sysroot/stamp")
  message(FATAL_ERROR "arm64 sysroot ${GVS_ARM64_SYSROOT} missing or incomplete: run scripts/arm64-sysroot")
endif()
# try_compile projects read this file again: hand them the sysroot.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES GVS_ARM64_SYSROOT)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_SYSROOT "${GVS_ARM64_SYSROOT}")
# The libraries' own dependencies (e.g. libopencv_core's libtbb) are found
# by the linker in the sysroot's multiarch folder.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,-rpath-link,${GVS_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-Wl,-rpath-link,${GVS_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu")

set(CMAKE_FIND_ROOT_PATH "${GVS_ARM64_SYSROOT}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# pkg-config (FFTW, libgpiod, libcamera): the sysroot's .pc files only.
set(ENV{PKG_CONFIG_DIR} "")
set(ENV{PKG_CONFIG_LIBDIR} "${GVS_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:${GVS_ARM64_SYSROOT}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_SYSROOT_DIR} "${GVS_ARM64_SYSROOT}")

# Test programs (gtest_discover_tests, add_test) and the man pages' --help
# run under qemu-user.
find_program(GVS_QEMU_AARCH64 qemu-aarch64)
if(NOT GVS_QEMU_AARCH64)
  message(FATAL_ERROR "qemu-aarch64 not found: the arm64 build runs its tests and writes its man pages "
    "under it (scripts/install-deps installs qemu-user)")
endif()
set(CMAKE_CROSSCOMPILING_EMULATOR "${GVS_QEMU_AARCH64};-L;${GVS_ARM64_SYSROOT}")

# CPack project configuration file of a cross build (CPACK_PROJECT_CONFIG_FILE,
# cmake/GvsPackage.cmake): the package's Depends from the arm64 libraries'
# own Debian shlibs files, as dpkg-shlibdeps does for a native build. Run by
# cpack, not by cmake.
#
# dpkg-shlibdeps cannot be used here: it asks the host's dpkg database which
# package ships each library, and the arm64 libraries live in a sysroot
# (scripts/arm64-sysroot), not in the host's database. So, per the Debian
# policy's shlibs rule: every DT_NEEDED soname of gvsd and gvs
# (libNAME.so.VERSION, or libNAME-VERSION.so) is looked up in the shlibs
# files of the sysroot's packages (GVS_CROSS_SHLIBS, collected by
# scripts/arm64-sysroot), which name the package and its minimum version.
# A soname with no entry stops the packaging with its name.
if(NOT CPACK_GENERATOR STREQUAL "DEB" OR NOT CPACK_GVS_CROSS_SHLIBS)
  return()
endif()
file(STRINGS "${CPACK_GVS_CROSS_SHLIBS}" gvs_shlibs_lines)
set(gvs_deps)
foreach(binary IN LISTS CPACK_GVS_CROSS_BINARIES)
  execute_process(COMMAND ${CPACK_GVS_READELF} -d "${binary}"
    OUTPUT_VARIABLE gvs_dyn RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "GvsCrossShlibs: ${CPACK_GVS_READELF} -d ${binary} failed")
  endif()
  string(REGEX MATCHALL "\\(NEEDED\\)[^[]*\\[[^]]+\\]" needed "${gvs_dyn}")
  foreach(entry IN LISTS needed)
    string(REGEX REPLACE ".*\\[([^]]+)\\]" "\\1" soname "${entry}")
    if(soname MATCHES "^(.+)\\.so\\.(.+)$")
      set(name "${CMAKE_MATCH_1}")
      set(version "${CMAKE_MATCH_2}")
    elseif(soname MATCHES "^(.+)-([0-9][^-]*)\\.so$")
      set(name "${CMAKE_MATCH_1}")
      set(version "${CMAKE_MATCH_2}")
    else()
      message(FATAL_ERROR "GvsCrossShlibs: cannot read soname ${soname} of ${binary}")
    endif()
    set(dep)
    foreach(line IN LISTS gvs_shlibs_lines)
      # "[type:] library version dependencies"; udeb lines are for the installer
      if(line MATCHES "^([a-z-]+: )?([^ ]+) ([^ ]+) (.+)$" AND NOT CMAKE_MATCH_1
         AND CMAKE_MATCH_2 STREQUAL name AND CMAKE_MATCH_3 STREQUAL version)
        string(STRIP "${CMAKE_MATCH_4}" dep)
        break()
      endif()
    endforeach()
    if(NOT dep)
      message(FATAL_ERROR "GvsCrossShlibs: no shlibs entry for ${soname} (${binary}) in ${CPACK_GVS_CROSS_SHLIBS}")
    endif()
    list(APPEND gvs_deps "${dep}")
  endforeach()
endforeach()
list(REMOVE_DUPLICATES gvs_deps)
list(SORT gvs_deps)
list(JOIN gvs_deps ", " gvs_deps_text)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${CPACK_DEBIAN_PACKAGE_DEPENDS}, ${gvs_deps_text}")
message(STATUS "GvsCrossShlibs: Depends: ${CPACK_DEBIAN_PACKAGE_DEPENDS}")

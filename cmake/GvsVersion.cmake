# gvs_version: an interface target providing gvs/version.hpp (the project
# version and the git commit the build was configured from), for --version.
# The build reconfigures when HEAD moves, so the commit stays current; a
# source tree outside git says so instead of failing.
find_package(Git QUIET)
set(GVS_GIT_COMMIT "not built from a git checkout")
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} rev-parse --short=12 HEAD
    OUTPUT_VARIABLE _gvs_commit OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _gvs_rc ERROR_QUIET)
  if(_gvs_rc EQUAL 0 AND _gvs_commit)
    set(GVS_GIT_COMMIT "git ${_gvs_commit}")
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} rev-parse --git-path HEAD
      OUTPUT_VARIABLE _gvs_head OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} symbolic-ref -q HEAD
      OUTPUT_VARIABLE _gvs_ref OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} rev-parse --git-path packed-refs
      OUTPUT_VARIABLE _gvs_packed OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    set(_gvs_watch ${_gvs_head} ${_gvs_packed})
    if(_gvs_ref)
      execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} rev-parse --git-path ${_gvs_ref}
        OUTPUT_VARIABLE _gvs_ref_file OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      list(APPEND _gvs_watch ${_gvs_ref_file})
    endif()
    foreach(_f IN LISTS _gvs_watch)
      if(NOT IS_ABSOLUTE ${_f})
        set(_f ${PROJECT_SOURCE_DIR}/${_f})
      endif()
      if(EXISTS ${_f})
        set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_f})
      endif()
    endforeach()
  endif()
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/version.hpp.in ${PROJECT_BINARY_DIR}/generated/gvs/version.hpp @ONLY)
add_library(gvs_version INTERFACE)
target_include_directories(gvs_version INTERFACE ${PROJECT_BINARY_DIR}/generated)

# gvs_set_warnings(<target>): the warning set every gvs target is built with.
function(gvs_set_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
    -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual -Wnull-dereference
    -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
  if(GVS_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  gvs_sanitizer_warning_exceptions(${target})
endfunction()

# GCC 12 gives false -Wmaybe-uninitialized inside libstdc++ (std::regex,
# std::function) when built with sanitizers, which change inlining; GCC's
# manual warns this warning depends on optimisation. Off for sanitizer
# builds only: the release build keeps it.
function(gvs_sanitizer_warning_exceptions target)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_FLAGS MATCHES "-fsanitize")
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
endfunction()

# Warning flags applied to CageKit's own targets (not to third-party code).
function(cagekit_target_warnings target)
  # GCC's -Wshadow=local (a local shadowing a local); Clang has no such option (it would warn that
  # the option is unknown, once per translation unit) and its -Wshadow also flags globals: the GCC
  # build checks shadowing.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    set(shadow -Wshadow=local)
  else()
    set(shadow "")
  endif()
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic ${shadow} -Wnon-virtual-dtor>
    $<$<COMPILE_LANGUAGE:C>:-Wall -Wextra -Wpedantic>)
endfunction()

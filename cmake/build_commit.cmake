# Run at every build (CMakeLists.txt, persp_build_commit): writes OUT with
# the commit of the source tree SRC the build compiles, for `persp report`'s
# page ("+" when the tree differs from it; empty outside a git checkout).
# The file is rewritten only when that changes, so nothing recompiles
# otherwise.
execute_process(COMMAND git -C "${SRC}" rev-parse --short=12 HEAD
                OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE
                RESULT_VARIABLE found ERROR_QUIET)
if(NOT found EQUAL 0)
  set(commit "")
endif()
if(commit)
  execute_process(COMMAND git -C "${SRC}" diff --quiet HEAD -- RESULT_VARIABLE same ERROR_QUIET)
  if(NOT same EQUAL 0)
    set(commit "${commit}+")
  endif()
endif()
set(text "#define PERSP_BUILD_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()

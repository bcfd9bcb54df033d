# Writes build_info.hpp with the commit the sources are at, on every build (not only at configure
# time), so run.json never names a stale commit. configure_file leaves the header untouched when
# nothing changed, so an unchanged tree recompiles nothing.
# Usage: cmake -DSOURCE_DIR=... -DINPUT=build_info.hpp.in -DOUTPUT=... -DPROJECT_VERSION=...
#              -DCOMPILER=... -P build_info.cmake
execute_process(COMMAND git rev-parse --short=12 HEAD
  WORKING_DIRECTORY ${SOURCE_DIR} OUTPUT_VARIABLE CLOTHBENCH_GIT_COMMIT
  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE no_git)
if(no_git OR NOT CLOTHBENCH_GIT_COMMIT)
  set(CLOTHBENCH_GIT_COMMIT "unknown")
else()
  # uncommitted changes to tracked files: the commit alone does not say what was built
  execute_process(COMMAND git diff --quiet HEAD --
    WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE dirty ERROR_QUIET)
  if(dirty)
    string(APPEND CLOTHBENCH_GIT_COMMIT "-dirty")
  endif()
endif()
set(CLOTHBENCH_COMPILER "${COMPILER}")
configure_file(${INPUT} ${OUTPUT} @ONLY)

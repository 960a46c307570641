# Writes OUT from src/cli/version.cpp.in with the version and the git commit of SOURCE
# ("unknown" outside a git checkout; "-dirty" with uncommitted changes). Run at every build;
# configure_file leaves OUT untouched when nothing changed, so nothing recompiles then.
execute_process(COMMAND git -C ${SOURCE} describe --always --dirty --abbrev=12
                OUTPUT_VARIABLE QEX_GIT_COMMIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR QEX_GIT_COMMIT STREQUAL "")
  set(QEX_GIT_COMMIT unknown)
endif()
configure_file(${SOURCE}/src/cli/version.cpp.in ${OUT} @ONLY)

cmake_minimum_required(VERSION 3.25)
# Writes OUT (a header defining LRD_GIT_COMMIT) with the commit SOURCE is checked out at, as
# `git describe --always --dirty` says it ("unknown" outside a git checkout). Run at every build;
# configure_file rewrites the header only when the commit changed, so nothing recompiles otherwise.
execute_process(COMMAND git describe --always --dirty --abbrev=12 WORKING_DIRECTORY ${SOURCE}
                OUTPUT_VARIABLE LRD_GIT_COMMIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE status)
if(NOT status EQUAL 0 OR LRD_GIT_COMMIT STREQUAL "")
  set(LRD_GIT_COMMIT unknown)
endif()
file(CONFIGURE OUTPUT ${OUT} CONTENT "#pragma once\n#define LRD_GIT_COMMIT \"@LRD_GIT_COMMIT@\"\n" @ONLY)

# cmake -DSOURCE_DIR=... -DINPUT=version.hpp.in -DOUTPUT=magenc_version.hpp -DPROJECT_VERSION=x.y.z -P git_revision.cmake
# Run at every build (target magenc_git_revision): writes OUTPUT with the current `git describe --always
# --dirty` of SOURCE_DIR. configure_file leaves OUTPUT untouched when its text is unchanged, so only a
# new revision recompiles the files that include it.
execute_process(COMMAND git describe --always --dirty WORKING_DIRECTORY "${SOURCE_DIR}"
                OUTPUT_VARIABLE MAGENC_GIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT MAGENC_GIT)
  set(MAGENC_GIT "unknown")
endif()
configure_file("${INPUT}" "${OUTPUT}" @ONLY)

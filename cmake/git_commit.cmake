# Writes OUTPUT, a header defining ACCELCAL_GIT_COMMIT: the commit of SOURCE_DIR's checkout
# (12 hex digits, "-modified" when tracked files differ from it), or "unknown" without git or
# outside a checkout. Run at every build (src/CMakeLists.txt), the file rewritten only when the
# text changes, so that only what includes it recompiles. git runs with an argument vector.
find_program(ACCELCAL_GIT git)
set(commit "unknown")
if(ACCELCAL_GIT)
  execute_process(COMMAND ${ACCELCAL_GIT} -C ${SOURCE_DIR} rev-parse --short=12 HEAD
                  OUTPUT_VARIABLE head RESULT_VARIABLE status ERROR_QUIET
                  OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(status EQUAL 0 AND head MATCHES "^[0-9a-f]+$")
    set(commit "${head}")
    execute_process(COMMAND ${ACCELCAL_GIT} -C ${SOURCE_DIR} status --porcelain
                            --untracked-files=no
                    OUTPUT_VARIABLE changes RESULT_VARIABLE status ERROR_QUIET)
    if(status EQUAL 0 AND NOT changes STREQUAL "")
      set(commit "${commit}-modified")
    endif()
  endif()
endif()
set(text "#define ACCELCAL_GIT_COMMIT \"${commit}\"\n")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()

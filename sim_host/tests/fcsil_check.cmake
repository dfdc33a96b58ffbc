# Helpers of the check_*.cmake scripts (include()d from them).
#
# fcsil_run(OUT_JSON <file> ARGS...): runs ${FCSIL} with ARGS and --json
# <file> --quiet, fails the test if it does not exit 0, and sets `json` in
# the caller to the file's text.
function(fcsil_run)
  cmake_parse_arguments(PARSE_ARGV 0 run "" "OUT_JSON" "ARGS")
  execute_process(COMMAND "${FCSIL}" ${run_ARGS} --json "${run_OUT_JSON}" --quiet
                  RESULT_VARIABLE status ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "fc-sil failed (${status}): ${err}")
  endif()
  file(READ "${run_OUT_JSON}" text)
  set(json "${text}" PARENT_SCOPE)
endfunction()

# fcsil_check_png(<file>): with gnuplot on the PATH, the PNG --plot wrote
# must exist.
function(fcsil_check_png png)
  find_program(GNUPLOT gnuplot)
  if(NOT GNUPLOT)
    message(STATUS "gnuplot not found: the PNG is not checked")
    return()
  endif()
  get_filename_component(name "${png}" NAME)
  if(NOT EXISTS "${png}")
    message(FATAL_ERROR "${name} not written")
  endif()
  message(STATUS "${name} written")
endfunction()

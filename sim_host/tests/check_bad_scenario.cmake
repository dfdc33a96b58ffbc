# A bad scenario file: fc-sil exits with status 2, its error names the file,
# the line and the key (the lines "; expect-line:" and "; expect-key:" of the
# file say which), and no output is written.
#   cmake -DFCSIL=... -DSCENARIO=... -DWORK=... -P check_bad_scenario.cmake
file(STRINGS "${SCENARIO}" expect_line REGEX "^# expect-line: ")
file(STRINGS "${SCENARIO}" expect_key REGEX "^# expect-key: ")
string(REGEX REPLACE "^# expect-line: " "" expect_line "${expect_line}")
string(REGEX REPLACE "^# expect-key: " "" expect_key "${expect_key}")
if(expect_line STREQUAL "" OR expect_key STREQUAL "")
  message(FATAL_ERROR "${SCENARIO}: no expect-line / expect-key comment")
endif()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
execute_process(
  COMMAND "${FCSIL}" --scenario "${SCENARIO}" --json "${WORK}/out.json" --csv "${WORK}/out.csv"
          --plot "${WORK}/plots" --quiet
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "fc-sil said: ${err}")
if(NOT status EQUAL 2)
  message(FATAL_ERROR "exit status ${status}, expected 2")
endif()
string(REGEX REPLACE "([][+.*()^$?|\\\\])" "\\\\\\1" file_re "${SCENARIO}")
if(NOT err MATCHES "${file_re}:${expect_line}: ${expect_key}")
  message(FATAL_ERROR "the error does not name ${SCENARIO}:${expect_line}: ${expect_key}")
endif()
foreach(output out.json out.csv plots)
  if(EXISTS "${WORK}/${output}")
    message(FATAL_ERROR "${output} was written despite the error")
  endif()
endforeach()

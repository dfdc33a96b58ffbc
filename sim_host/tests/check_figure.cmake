# Flies one of section 4.5's figure scenarios (Figures 4.4-4.7) with the PD
# (pid, integral gains 0) and the SSC variants in one backend, short, with
# --plot: every run must end with 0 NaN outputs, and with gnuplot on the PATH
# the figure's PNG must be written.
#   cmake -DFCSIL=... -DSCENARIO=... -DFIGURE=4.5 -DNUMERIC=... -DDURATION=S -DWORK=DIR -P check_figure.cmake
set(controllers pid ssc ssc-adaptive)
list(JOIN controllers "," controller_list)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
execute_process(
  COMMAND "${FCSIL}" --scenario "${SCENARIO}" --controller "${controller_list}" --numeric "${NUMERIC}"
          --duration "${DURATION}" --json "${WORK}/runs.json" --plot "${WORK}" --quiet
  RESULT_VARIABLE status ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "fc-sil failed (${status}): ${err}")
endif()
file(READ "${WORK}/runs.json" json)
string(JSON runs LENGTH "${json}" results)
list(LENGTH controllers expected)
if(NOT runs EQUAL expected)
  message(FATAL_ERROR "${runs} runs in the JSON, ${expected} expected")
endif()
math(EXPR last "${runs} - 1")
foreach(i RANGE ${last})
  string(JSON variant GET "${json}" results ${i} variant)
  string(JSON nan GET "${json}" results ${i} nan_outputs)
  string(JSON max_tilt GET "${json}" results ${i} max_tilt_deg)
  message(STATUS "${SCENARIO} ${variant} ${NUMERIC}: nan_outputs = ${nan}, max_tilt_deg = ${max_tilt}")
  if(NOT nan EQUAL 0)
    message(FATAL_ERROR "${variant}: ${nan} NaN outputs")
  endif()
endforeach()
find_program(GNUPLOT gnuplot)
if(GNUPLOT)
  if(NOT EXISTS "${WORK}/fig${FIGURE}-${NUMERIC}.png")
    message(FATAL_ERROR "fig${FIGURE}-${NUMERIC}.png not written")
  endif()
  message(STATUS "fig${FIGURE}-${NUMERIC}.png written")
else()
  message(STATUS "gnuplot not found: the PNG is not checked")
endif()

# Flies one of section 4.5's figure scenarios (Figures 4.4-4.7) with the PD
# (pid, integral gains 0) and the SSC variants in one backend, short, with
# --plot: every run must end with 0 NaN outputs, and with gnuplot on the PATH
# the figure's PNG must be written.
#   cmake -DFCSIL=... -DSCENARIO=... -DFIGURE=4.5 -DNUMERIC=... -DDURATION=S -DWORK=DIR -P check_figure.cmake
include("${CMAKE_CURRENT_LIST_DIR}/fcsil_check.cmake")
set(controllers pid ssc ssc-adaptive)
list(JOIN controllers "," controller_list)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
fcsil_run(OUT_JSON "${WORK}/runs.json"
          ARGS --scenario "${SCENARIO}" --controller "${controller_list}" --numeric "${NUMERIC}"
               --duration "${DURATION}" --plot "${WORK}")
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
fcsil_check_png("${WORK}/fig${FIGURE}-${NUMERIC}.png")

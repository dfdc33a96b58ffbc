# Flies accel-feedback-mass-step in one backend with --plot: fc-sil flies it
# with the preset's k_a and again with k_a = 0. Both runs must end with 0 NaN
# outputs and not diverge; the run with the feedback must hold the horizontal
# position closer after the transient (settled_position_error_m) than the run
# without (what the figure shows); with gnuplot on the PATH the PNG must be written.
#   cmake -DFCSIL=... -DNUMERIC=... -DDURATION=S -DWORK=DIR -P check_accel_feedback.cmake
include("${CMAKE_CURRENT_LIST_DIR}/fcsil_check.cmake")
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
fcsil_run(OUT_JSON "${WORK}/runs.json"
          ARGS --scenario accel-feedback-mass-step --controller ssc --numeric "${NUMERIC}"
               --duration "${DURATION}" --plot "${WORK}")
string(JSON runs LENGTH "${json}" results)
if(NOT runs EQUAL 2)
  message(FATAL_ERROR "${runs} runs in the JSON, 2 expected (with and without the feedback)")
endif()
foreach(i 0 1)
  string(JSON name GET "${json}" results ${i} scenario)
  string(JSON gain GET "${json}" results ${i} firmware accel_fb_gain_per_s)
  string(JSON nan GET "${json}" results ${i} nan_outputs)
  string(JSON diverged GET "${json}" results ${i} diverged)
  string(JSON settled GET "${json}" results ${i} settled_position_error_m)
  message(STATUS "${name} ${NUMERIC}: k_a = ${gain}, settled_position_error_m = ${settled}, nan_outputs = ${nan}")
  if(NOT nan EQUAL 0 OR diverged)
    message(FATAL_ERROR "${name}: ${nan} NaN outputs, diverged ${diverged}")
  endif()
  set(gain_${i} ${gain})
  set(settled_${i} ${settled})
endforeach()
if(NOT gain_0 GREATER 0 OR NOT gain_1 EQUAL 0)
  message(FATAL_ERROR "expected the preset's k_a > 0 first, then k_a = 0: ${gain_0}, ${gain_1}")
endif()
if(NOT settled_0 LESS settled_1)
  message(FATAL_ERROR "with the feedback the position error is not smaller: ${settled_0} >= ${settled_1}")
endif()
fcsil_check_png("${WORK}/accel-feedback-ssc-${NUMERIC}.png")

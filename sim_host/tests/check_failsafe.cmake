# Flies a failsafe-* scenario and checks the failsafe's metrics in the JSON
# (issue 27, SPEC.md's safety contract): the firmware entered FAILSAFE, never
# stopped its motors in the air, output no NaN, held its descent within
# RATE_TOLERANCE (0.25) of failsafe.descent_mps and touched down at no more
# than TOUCHDOWN_FACTOR_PERCENT (150) % of it. One run, or with RUNS a Monte-Carlo
# whose every run must pass (its worst seeds are named for a replay).
#   cmake -DFCSIL=... -DSCENARIO=failsafe-cf2 -DNUMERIC=float -DOUT=...
#         [-DCONTROLLER=ssc,ssc-adaptive] [-DRUNS=20] [-DSETS=imu.accel_bias_mps2=0,0,0.2|...]
#         [-DTOUCHDOWN=OFF] -P check_failsafe.cmake
# TOUCHDOWN=OFF: the fault ends in the air (imu-lost), no touchdown is required.
if(NOT DEFINED RATE_TOLERANCE)
  set(RATE_TOLERANCE 0.25)
endif()
if(NOT DEFINED TOUCHDOWN_FACTOR_PERCENT)
  set(TOUCHDOWN_FACTOR_PERCENT 150)
endif()
if(NOT DEFINED TOUCHDOWN)
  set(TOUCHDOWN ON)
endif()

set(args --scenario "${SCENARIO}" --numeric "${NUMERIC}" --json "${OUT}" --quiet)
if(DEFINED CONTROLLER)
  list(APPEND args --controller "${CONTROLLER}")
endif()
if(DEFINED RUNS)
  list(APPEND args --runs ${RUNS} --seed 1)
endif()
# SETS: the --set overrides joined by '|' (a ';' would not survive ctest's command line)
string(REPLACE "|" ";" overrides "${SETS}")
foreach(override IN LISTS overrides)
  list(APPEND args --set "${override}")
endforeach()
list(JOIN args " " replay)
execute_process(COMMAND "${FCSIL}" ${args} RESULT_VARIABLE status ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "fc-sil failed (${status}): ${err}")
endif()
file(READ "${OUT}" json)

# value x percent / 100 for a plain decimal value ("0.30000001192092896"), as
# a decimal string with six places in <out>: CMake's math is integer only.
function(scaled_decimal value percent out)
  if(NOT value MATCHES "^([0-9]+)(\\.([0-9]*))?$")
    message(FATAL_ERROR "failsafe_descent_mps: unexpected number format ${value}")
  endif()
  set(whole "${CMAKE_MATCH_1}")
  string(SUBSTRING "${CMAKE_MATCH_3}000000" 0 6 micro)
  string(REGEX REPLACE "^0+([0-9])" "\\1" micro "${micro}") # no leading zeros for math()
  math(EXPR scaled "(${whole} * 1000000 + ${micro}) * ${percent} / 100")
  math(EXPR whole "${scaled} / 1000000")
  math(EXPR fraction "${scaled} % 1000000 + 1000000")
  string(SUBSTRING "${fraction}" 1 6 fraction)
  set(${out} "${whole}.${fraction}" PARENT_SCOPE)
endfunction()

# The failsafe metrics of the run at the JSON path ARGN, as variables fs_<metric>
# in the caller, and in <why> what of the contract it breaks ("" if nothing).
macro(read_run why descent_mps bound_mps)
  foreach(metric failsafe_entered failsafe_motor_stops_airborne failsafe_descent_rate_mps
                 failsafe_descent_rate_rel_error failsafe_touchdown_speed_mps failsafe_time_to_motors_off_s nan_outputs
                 max_tilt_deg)
    string(JSON fs_${metric} GET "${json}" ${ARGN} ${metric})
    if(fs_${metric} STREQUAL "")
      set(fs_${metric} null) # CMake reads a JSON null as ""
    endif()
  endforeach()
  set(${why} "")
  if(NOT fs_failsafe_entered STREQUAL "ON")
    list(APPEND ${why} "failsafe never entered")
  endif()
  if(NOT fs_failsafe_motor_stops_airborne EQUAL 0)
    list(APPEND ${why} "${fs_failsafe_motor_stops_airborne} motor stop(s) in the air")
  endif()
  if(NOT fs_nan_outputs EQUAL 0)
    list(APPEND ${why} "${fs_nan_outputs} NaN outputs")
  endif()
  if(fs_failsafe_entered STREQUAL "ON" AND fs_failsafe_descent_rate_rel_error STREQUAL "null")
    list(APPEND ${why} "no descent measured")
  elseif(fs_failsafe_descent_rate_rel_error GREATER RATE_TOLERANCE)
    list(APPEND ${why} "descent ${fs_failsafe_descent_rate_mps} m/s, target ${descent_mps}")
  endif()
  if(TOUCHDOWN AND fs_failsafe_touchdown_speed_mps STREQUAL "null")
    list(APPEND ${why} "no touchdown")
  elseif(fs_failsafe_touchdown_speed_mps GREATER ${bound_mps})
    list(APPEND ${why} "touchdown at ${fs_failsafe_touchdown_speed_mps} m/s")
  endif()
  list(JOIN ${why} ", " ${why})
endmacro()

set(failures "")
string(JSON count ERROR_VARIABLE single LENGTH "${json}" results)
if(single)
  set(count 1)
endif()
math(EXPR last_record "${count} - 1")
foreach(i RANGE ${last_record})
  if(single)
    set(path "")
  else()
    set(path results ${i})
  endif()
  string(JSON variant GET "${json}" ${path} variant)
  string(JSON backend GET "${json}" ${path} backend)
  set(label "${SCENARIO} ${variant} ${backend}")
  string(JSON descent_mps GET "${json}" ${path} firmware failsafe_descent_mps)
  scaled_decimal(${descent_mps} ${TOUCHDOWN_FACTOR_PERCENT} bound_mps)
  string(JSON runs ERROR_VARIABLE one_run GET "${json}" ${path} runs)
  if(one_run)
    read_run(why ${descent_mps} ${bound_mps} ${path})
    message(STATUS "${label}: entered ${fs_failsafe_entered}, airborne motor stops "
                   "${fs_failsafe_motor_stops_airborne}, descent ${fs_failsafe_descent_rate_mps} m/s (target "
                   "${descent_mps}, rel. error ${fs_failsafe_descent_rate_rel_error}), touchdown "
                   "${fs_failsafe_touchdown_speed_mps} m/s (bound ${bound_mps}), motors off after "
                   "${fs_failsafe_time_to_motors_off_s} s, NaN outputs ${fs_nan_outputs}, max tilt "
                   "${fs_max_tilt_deg} deg")
    if(why)
      string(APPEND failures "\n  ${label}: ${why}")
    endif()
    continue()
  endif()
  # a Monte-Carlo record: its summary, then every run against the contract
  foreach(field failsafe_entered_runs airborne_motor_stop_runs nan_output_runs)
    string(JSON ${field} GET "${json}" ${path} ${field})
  endforeach()
  foreach(metric failsafe_descent_rate_mps failsafe_touchdown_speed_mps failsafe_time_to_motors_off_s)
    foreach(stat min median max worst_seed count)
      string(JSON ${metric}_${stat} GET "${json}" ${path} metrics ${metric} ${stat})
      if(${metric}_${stat} STREQUAL "")
        set(${metric}_${stat} -) # no run measured it
      endif()
    endforeach()
  endforeach()
  message(STATUS "${label}: ${runs} runs, failsafe entered in ${failsafe_entered_runs}, motors stopped in the "
                 "air in ${airborne_motor_stop_runs}, NaN outputs in ${nan_output_runs}; descent (target "
                 "${descent_mps} m/s) min ${failsafe_descent_rate_mps_min} median "
                 "${failsafe_descent_rate_mps_median} max ${failsafe_descent_rate_mps_max} in "
                 "${failsafe_descent_rate_mps_count} runs; touchdown (bound ${bound_mps} m/s) median "
                 "${failsafe_touchdown_speed_mps_median} max ${failsafe_touchdown_speed_mps_max} (seed "
                 "${failsafe_touchdown_speed_mps_worst_seed}) in ${failsafe_touchdown_speed_mps_count} runs; "
                 "motors off after median ${failsafe_time_to_motors_off_s_median} s")
  set(bad 0)
  math(EXPR last_run "${runs} - 1")
  foreach(k RANGE ${last_run})
    read_run(why ${descent_mps} ${bound_mps} ${path} per_run ${k})
    if(why)
      math(EXPR bad "${bad} + 1")
      if(bad LESS_EQUAL 10)
        string(JSON seed GET "${json}" ${path} per_run ${k} seed)
        string(APPEND failures "\n  ${label} seed ${seed}: ${why}")
      endif()
    endif()
  endforeach()
  if(bad GREATER 0)
    string(APPEND failures "\n  ${label}: ${bad} of ${runs} runs break the contract")
  endif()
endforeach()
if(failures)
  message(FATAL_ERROR "the failsafe breaks the safety contract:${failures}\n(replay: fc-sil ${replay}; "
                      "one Monte-Carlo seed: --runs 1 --seed S)")
endif()

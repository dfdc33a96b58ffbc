# tilting-deck (a deck that heaves, rolls and pitches), descent shaping on or off.
# One landing (SHAPING=on|off): no NaN output, LANDED, the new metrics present.
#   cmake -DFCSIL=... -DNUMERIC=float|fixed -DSHAPING=on -DOUT=file.json -P check_tilting_deck.cmake
# A short campaign (RUNS=N, no SHAPING): N seeds from 1 with shaping and the
# same N without; every run lands, no NaN output, no diverged run in either.
# The comparison itself (early contacts, p99 touchdown speed) needs hundreds
# of runs: sim_host/README.md gives the commands.
#   cmake -DFCSIL=... -DNUMERIC=float -DRUNS=12 -DOUT=prefix -P check_tilting_deck.cmake
include("${CMAKE_CURRENT_LIST_DIR}/fcsil_check.cmake")
if(DEFINED SHAPING)
  fcsil_run(OUT_JSON "${OUT}" ARGS --scenario tilting-deck --numeric ${NUMERIC} --descent-shaping ${SHAPING})
  string(JSON nan_outputs GET "${json}" nan_outputs)
  string(JSON final GET "${json}" landing final_state)
  string(JSON tilt GET "${json}" touchdown_rel_tilt_deg)
  string(JSON early GET "${json}" early_contact)
  string(JSON speed GET "${json}" touchdown_rel_speed_mps)
  message(STATUS "shaping ${SHAPING} (${NUMERIC}): ${final}, touchdown ${speed} m/s, relative tilt ${tilt} deg, "
                 "early contact ${early}, NaN outputs ${nan_outputs}")
  if(NOT nan_outputs EQUAL 0 OR NOT final STREQUAL "landed")
    message(FATAL_ERROR "expected landed with no NaN output")
  endif()
  return()
endif()
foreach(shaping on off)
  fcsil_run(OUT_JSON "${OUT}-${shaping}.json"
            ARGS --scenario tilting-deck --numeric ${NUMERIC} --descent-shaping ${shaping} --runs ${RUNS} --seed 1)
  string(JSON runs GET "${json}" runs)
  string(JSON diverged GET "${json}" diverged_runs)
  string(JSON nan_runs GET "${json}" nan_output_runs)
  string(JSON touchdowns GET "${json}" metrics touchdown_rel_speed_mps count)
  string(JSON speed_max GET "${json}" metrics touchdown_rel_speed_mps max)
  string(JSON tilt_median GET "${json}" metrics touchdown_rel_tilt_deg median)
  string(JSON early_count GET "${json}" metrics early_contact max)
  message(STATUS "shaping ${shaping} (${NUMERIC}), ${runs} runs: ${touchdowns} touchdowns, speed max ${speed_max}, "
                 "relative tilt median ${tilt_median} deg, any early contact ${early_count}, "
                 "diverged ${diverged}, NaN runs ${nan_runs}")
  if(NOT touchdowns EQUAL RUNS OR NOT diverged EQUAL 0 OR NOT nan_runs EQUAL 0)
    message(FATAL_ERROR "${touchdowns} touchdowns in ${runs} runs, ${diverged} diverged, ${nan_runs} with NaN")
  endif()
endforeach()

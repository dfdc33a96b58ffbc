# A short landing campaign: --runs N of SCENARIO from seed 1 in one backend;
# fails on a NaN output, a diverged run, a run that never touched down, a
# touchdown faster than SPEED_MAX or any bounce.
#   cmake -DFCSIL=... -DSCENARIO=m600-deck -DCONTROLLER=ssc -DNUMERIC=float|fixed -DRUNS=20
#         -DSPEED_MAX=0.15 -DOUT=... -P check_landing_campaign.cmake
include("${CMAKE_CURRENT_LIST_DIR}/fcsil_check.cmake")
fcsil_run(OUT_JSON "${OUT}"
          ARGS --scenario ${SCENARIO} --controller ${CONTROLLER} --numeric ${NUMERIC} --runs ${RUNS} --seed 1)
string(JSON runs GET "${json}" runs)
string(JSON diverged GET "${json}" diverged_runs)
string(JSON nan_runs GET "${json}" nan_output_runs)
string(JSON touchdowns GET "${json}" metrics touchdown_rel_speed_mps count)
string(JSON speed_p99 GET "${json}" metrics touchdown_rel_speed_mps p99)
string(JSON speed_max GET "${json}" metrics touchdown_rel_speed_mps max)
string(JSON speed_worst GET "${json}" metrics touchdown_rel_speed_mps worst_seed)
string(JSON bounces_max GET "${json}" metrics bounces max)
string(JSON bounces_worst GET "${json}" metrics bounces worst_seed)
message(STATUS "${SCENARIO} (${NUMERIC}), ${runs} runs: touchdown speed p99 ${speed_p99} max ${speed_max} "
               "(seed ${speed_worst}), bounces max ${bounces_max} (seed ${bounces_worst}), "
               "diverged ${diverged}, NaN runs ${nan_runs}")
if(NOT runs EQUAL RUNS OR NOT touchdowns EQUAL RUNS)
  message(FATAL_ERROR "${touchdowns} touchdowns in ${runs} runs, expected ${RUNS}")
endif()
if(NOT diverged EQUAL 0 OR NOT nan_runs EQUAL 0)
  message(FATAL_ERROR "${diverged} diverged runs, ${nan_runs} runs with NaN outputs")
endif()
if(speed_max GREATER SPEED_MAX)
  message(FATAL_ERROR "touchdown speed ${speed_max} m/s (seed ${speed_worst}) above ${SPEED_MAX}")
endif()
if(NOT bounces_max EQUAL 0)
  message(FATAL_ERROR "${bounces_max} bounces (seed ${bounces_worst})")
endif()

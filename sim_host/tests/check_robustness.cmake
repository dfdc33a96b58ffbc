# A small robustness campaign (issue 9): --runs N of the robustness scenario
# in one backend; fails on any diverged run or NaN output, and checks the
# summary's per-metric statistics (min <= median <= p90 <= p99 <= max, the
# worst seed among the runs) and the per-run divergence entries.
#   cmake -DFCSIL=... -DNUMERIC=float|fixed -DRUNS=20 -DOUT=... -P check_robustness.cmake
execute_process(COMMAND "${FCSIL}" --scenario robustness --numeric ${NUMERIC} --runs ${RUNS} --seed 1
                        --json "${OUT}" --quiet
                RESULT_VARIABLE status ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "fc-sil failed (${status}): ${err}")
endif()
file(READ "${OUT}" json)
string(JSON runs GET "${json}" runs)
string(JSON n LENGTH "${json}" per_run)
string(JSON diverged GET "${json}" diverged_runs)
string(JSON nan_runs GET "${json}" nan_output_runs)
string(JSON nan_total GET "${json}" nan_outputs_total)
message(STATUS "${RUNS} runs (${NUMERIC}): diverged ${diverged}, NaN outputs ${nan_total} in ${nan_runs} runs")
if(NOT runs EQUAL RUNS OR NOT n EQUAL RUNS)
  message(FATAL_ERROR "runs ${runs}, per_run entries ${n}, expected ${RUNS}")
endif()
math(EXPR last "${RUNS} - 1")
foreach(i RANGE ${last})
  string(JSON d GET "${json}" per_run ${i} diverged)
  if(d)
    string(JSON seed GET "${json}" per_run ${i} seed)
    string(JSON why GET "${json}" per_run ${i} diverged_reasons)
    message(SEND_ERROR "seed ${seed} diverged: ${why} (replay: fc-sil --scenario robustness --numeric ${NUMERIC} --runs 1 --seed ${seed})")
  endif()
endforeach()
if(NOT diverged EQUAL 0 OR NOT nan_runs EQUAL 0 OR NOT nan_total EQUAL 0)
  message(FATAL_ERROR "${diverged} diverged runs, ${nan_runs} runs with NaN outputs")
endif()
math(EXPR last_seed "${RUNS}")
foreach(metric rms_error_m max_abs_error_m mass_step_peak_error_m control_tv_per_s theta_rel_error max_tilt_deg)
  foreach(stat min median p90 p99 max worst_seed)
    string(JSON ${stat} GET "${json}" metrics ${metric} ${stat})
  endforeach()
  message(STATUS "${metric}: median ${median} p90 ${p90} p99 ${p99} max ${max} worst seed ${worst_seed}")
  if(median LESS min OR p90 LESS median OR p99 LESS p90 OR max LESS p99 OR worst_seed LESS 1
     OR worst_seed GREATER last_seed)
    message(FATAL_ERROR "${metric}: inconsistent statistics")
  endif()
endforeach()

#!/usr/bin/env bash
# The whole test suite: installs what it needs, then configures, builds and
# tests every preset (host float/fixed, host under ASan+UBSan float/fixed,
# the cross builds for the Crazyflie and the ATmega in both backends, whose
# tests check the archives, and the libFuzzer harnesses with a bounded budget
# in both backends: fuzz, fuzz-fixed), then the processor-in-the-loop runs
# (tools/pil.sh) and the static analysis (tools/static-analysis.sh). Prints
# one total line at the end.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install-deps.sh

presets=(host host-fixed host-asan host-asan-fixed cf2 cf2-fixed atmega atmega-fixed fuzz fuzz-fixed)
passed=0
failed=0
failed_presets=()
for preset in "${presets[@]}"; do
  echo "=== preset $preset"
  log=$(mktemp)
  if cmake --workflow --preset "$preset" --fresh 2>&1 | tee "$log"; then status=0; else status=1; fi
  # ctest's summary: "100% tests passed, 0 tests failed out of 42"
  summary=$(grep -E 'tests passed, [0-9]+ tests? failed out of [0-9]+' "$log" | tail -1 || true)
  if [ -n "$summary" ]; then
    total=$(sed -E 's/.* out of ([0-9]+).*/\1/' <<<"$summary")
    nfail=$(sed -E 's/.*passed, ([0-9]+) tests? failed.*/\1/' <<<"$summary")
    passed=$((passed + total - nfail))
    failed=$((failed + nfail))
  fi
  if [ $status -ne 0 ] || [ -z "$summary" ]; then
    failed_presets+=("$preset")
    [ -z "$summary" ] && failed=$((failed + 1))
  fi
  rm -f "$log"
done

# processor in the loop (tools/pil.sh): the ATmega image flies seed-4.4 (ssc,
# ssc-adaptive), cf2-pad and hexa-deck in simavr and must match the host's
# fixed-point run exactly; 20 s of each flight (cf2-pad lands and ends
# before), one test each
echo "=== processor in the loop"
pil_log=$(mktemp)
tools/pil.sh --no-deps --duration 20 2>&1 | tee "$pil_log" || true
pil_cases=$(sed -nE 's/^pil: ([0-9]+) cases, ([0-9]+) failed$/\1/p' "$pil_log")
pil_failed=$(sed -nE 's/^pil: ([0-9]+) cases, ([0-9]+) failed$/\2/p' "$pil_log")
if [ -z "$pil_cases" ]; then
  failed=$((failed + 1))
  failed_presets+=(pil)
else
  passed=$((passed + pil_cases - pil_failed))
  failed=$((failed + pil_failed))
  [ "$pil_failed" = 0 ] || failed_presets+=(pil)
fi
rm -f "$pil_log"

# static analysis (tools/static-analysis.sh: cppcheck, MISRA C:2012, gcc
# -fanalyzer, clang-tidy), counted as one test
echo "=== static analysis"
if tools/static-analysis.sh; then
  passed=$((passed + 1))
else
  failed=$((failed + 1))
  failed_presets+=(static-analysis)
fi

if [ ${#failed_presets[@]} -ne 0 ]; then
  echo "failing presets: ${failed_presets[*]}"
fi
echo "total: $passed passed, $failed failed"
[ ${#failed_presets[@]} -eq 0 ]

#!/usr/bin/env bash
# Processor in the loop (issue 7): the ATmega2560 image flies the SIL plant.
#
# Builds fc-atmega-pil.elf (atmega-fixed preset: the library as flashed on the
# ATmega, around a mailbox loop, platform/atmega/pil/) and fc-sil (host
# preset), then flies each case twice: once with the controller step run by
# the image in simavr, cycle by cycle (fc-sil --numeric pil), once with the
# host's fixed-point build (--numeric fixed). The two must agree exactly, every
# metric and every trace cell (tools/pil-compare.py). Prints the comparison and
# the cycles of fc_controller_step on the ATmega over each flight.
#
# Usage: tools/pil.sh [--no-deps] [--duration S]
#   --duration S  fly S seconds of each case instead of the scenario's length
#                 (the tests use a short flight; a full seed-4.4 takes ~2 min)
# Outputs in build/pil/: <case>-{pil,fixed}.{json,csv}, <case>-pil.log.
set -euo pipefail
cd "$(dirname "$0")/.."

deps=1
duration=()
while [ $# -gt 0 ]; do
  case $1 in
  --no-deps) deps=0 ;;
  --duration) duration=(--duration "$2"); shift ;;
  *) echo "usage: tools/pil.sh [--no-deps] [--duration S]" >&2; exit 2 ;;
  esac
  shift
done
[ $deps = 1 ] && tools/install-deps.sh

cmake --preset atmega-fixed >/dev/null
cmake --build --preset atmega-fixed --target fc-atmega-pil >/dev/null
cmake --preset host >/dev/null
cmake --build --preset host --target fc-sil >/dev/null
image=build/atmega-fixed/platform/atmega/fc-atmega-pil.elf
sil=build/host/sim_host/fc-sil
out=build/pil
mkdir -p "$out"
echo "built $image and $sil"

# case name, scenario, altitude law
cases=("seed-4.4-ssc seed-4.4 ssc" "seed-4.4-ssc-adaptive seed-4.4 ssc-adaptive" "cf2-pad cf2-pad ssc"
       "hexa-deck hexa-deck ssc")

fly() { # name scenario variant: the PIL flight and the host's, side by side (2 cores)
  local name=$1 scenario=$2 variant=$3
  "$sil" --scenario "$scenario" --controller "$variant" "${duration[@]}" --quiet --numeric pil --pil-image "$image" \
    --json "$out/$name-pil.json" --csv "$out/$name-pil.csv" >"$out/$name-pil.log" 2>&1 &
  local pil_job=$!
  "$sil" --scenario "$scenario" --controller "$variant" "${duration[@]}" --quiet --numeric fixed \
    --json "$out/$name-fixed.json" --csv "$out/$name-fixed.csv" >"$out/$name-fixed.log" 2>&1
  wait $pil_job || { cat "$out/$name-pil.log" >&2; return 1; }
}

failed=0
for c in "${cases[@]}"; do
  read -r name scenario variant <<<"$c"
  if ! fly "$name" "$scenario" "$variant"; then
    echo "$name: the PIL run failed"
    failed=$((failed + 1))
    continue
  fi
  python3 tools/pil-compare.py "$name" "$out/$name-pil.json" "$out/$name-fixed.json" "$out/$name-pil.csv" \
    "$out/$name-fixed.csv" || failed=$((failed + 1))
  sed -n 's/^pil: /  /p' "$out/$name-pil.log"
done
echo "pil: ${#cases[@]} cases, $failed failed"
[ $failed = 0 ]

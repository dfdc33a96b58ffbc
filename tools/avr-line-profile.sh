#!/usr/bin/env bash
# Line profile of fc_controller_step on the ATmega2560 (simavr): which source
# lines its cycles go to, for the bench workload of tools/bench.sh.
#
#   tools/avr-line-profile.sh [PRESET] [WORKLOAD] [TOP]
#     PRESET    atmega-fixed (default) or atmega
#     WORKLOAD  cf (the Crazyflie's landing mission, default), hexa or f450
#               (the ATmega image's airframe at 500 Hz, as tools/bench.sh)
#     TOP       lines listed (default 40)
#
# Builds the preset's library again with -g (same code: -g changes no
# instruction) under build/line-profile/PRESET, links bench_avr.c as
# tools/bench.sh does, runs avr_bench --profile fc_controller_step
# --pc-cycles, prints the most frequent call edges (CALLER callee caller
# calls-per-step) and maps the addresses onto lines (tools/line-profile.py).
# Needs what tools/bench.sh needs (tools/install-deps.sh).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
preset=${1:-atmega-fixed}
workload=${2:-cf}
top=${3:-40}
case $preset in atmega) fx=0 ;; atmega-fixed) fx=1 ;; *) echo "preset: atmega or atmega-fixed" >&2; exit 2 ;; esac
case $workload in
cf) cf=1 f450=0 ;;
hexa) cf=0 f450=0 ;;
f450) cf=0 f450=1 ;;
*) echo "workload: cf, hexa or f450" >&2; exit 2 ;;
esac

out=$root/build/line-profile/$preset
mkdir -p "$out"
cmake --preset "$preset" -B "$out/build" -DCMAKE_C_FLAGS_MINSIZEREL="-Os -DNDEBUG -g" >/dev/null
cmake --build "$out/build" -j2 --target fc >/dev/null

warn=(-Wall -Wextra -Werror -Wdouble-promotion -Wshadow -Wundef)
avr-gcc -mmcu=atmega2560 -DF_CPU=16000000UL -maccumulate-args -Os -g -DNDEBUG -std=gnu11 "${warn[@]}" \
  -I"$root/firmware/include" -I"$root/tools/bench" -ffunction-sections -fdata-sections \
  -DFC_NUMERIC_FIXED="$fx" -DBENCH_WORKLOAD_CRAZYFLIE="$cf" -DBENCH_WORKLOAD_F450="$f450" \
  -o "$out/bench.elf" "$root/platform/atmega/bench/bench_avr.c" "$out/build/firmware/libfc.a" -lm -Wl,--gc-sections
cc -std=gnu11 -O2 "${warn[@]}" -isystem /usr/include/simavr "$root/tools/simavr/bench_host.c" \
   -o "$out/avr_bench" -lsimavr -lelf
"$out/avr_bench" --elf "$out/bench.elf" --time fc_controller_step --profile fc_controller_step \
  --pc-cycles "$out/pc-cycles.txt" >"$out/run.txt"
grep -E '^(CYCLES|DIGEST)' "$out/run.txt"
grep '^CALLER' "$out/run.txt" | awk 'NR <= 40'
python3 "$root/tools/line-profile.py" --elf "$out/bench.elf" --pc-cycles "$out/pc-cycles.txt" --top "$top"

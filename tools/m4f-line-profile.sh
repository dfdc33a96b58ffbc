#!/usr/bin/env bash
# Line profile of fc_controller_step on the Cortex-M4F (QEMU's TCG plugin,
# estimated cycles), for the bench workload of tools/bench.sh: where the
# estimated cycles go, by source line and by inlined call chain (the
# library that flies is one translation unit inlined into
# fc_controller_step, so the chain is the by-module view).
#
#   tools/m4f-line-profile.sh [PRESET] [WORKLOAD] [DEPTH] [TOP]
#     PRESET    cf2 (float, default) or cf2-fixed
#     WORKLOAD  cf (the Crazyflie's landing mission, default) or hexa
#     DEPTH     inlined calls per chain (default 3)
#     TOP       rows listed (default 40)
#
# Builds the preset's library again with -g (same code) under
# build/line-profile/PRESET, links bench_m4.c as tools/bench.sh does, runs
# it, prints the INSNS/CYCEST/PERCALL lines of fc_controller_step and
# tools/line-profile.py's tables. Needs what tools/bench.sh needs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
preset=${1:-cf2}
workload=${2:-cf}
depth=${3:-3}
top=${4:-40}
case $preset in cf2) fx=0 ;; cf2-fixed) fx=1 ;; *) echo "preset: cf2 or cf2-fixed" >&2; exit 2 ;; esac
case $workload in cf) cf=1 ;; hexa) cf=0 ;; *) echo "workload: cf or hexa" >&2; exit 2 ;; esac

out=$root/build/line-profile/$preset-$workload
mkdir -p "$out"
cmake --preset "$preset" -B "$out/build" -DCMAKE_C_FLAGS_MINSIZEREL="-Os -DNDEBUG -g" >/dev/null
cmake --build "$out/build" -j2 --target fc >/dev/null

flags_of() { sed -n "s/^$1 := //p" "$root/firmware/flags.mk"; }
read -ra warn <<< "$(flags_of FC_WARNINGS)"
read -ra m4f_flags <<< "$(flags_of FC_M4F_CPU)"
cd "$out"
cc -std=gnu11 -O2 "${warn[@]}" -shared -fPIC "$root/platform/cortex-m4-bench/insn_count.c" -o insn_count.so
arm-none-eabi-gcc "${m4f_flags[@]}" -Os -g -DNDEBUG -std=gnu11 "${warn[@]}" -I"$root/firmware/include" \
  -I"$root/tools/bench" -ffunction-sections -fdata-sections -DFC_NUMERIC_FIXED="$fx" -DBENCH_WORKLOAD_CRAZYFLIE="$cf" \
  --specs=rdimon.specs -nostartfiles -T "$root/platform/cortex-m4-bench/stm32f405.ld" -Wl,--gc-sections \
  -o bench.elf "$root/platform/cortex-m4-bench/bench_m4.c" "$out/build/firmware/libfc.a" -lm -lrdimon
sym() { arm-none-eabi-nm bench.elf | awk -v s="$1" '$3 == s { print "0x" $1 }'; }
pargs="begin=$(sym bench_timed_begin),end=$(sym bench_timed_end),out=$out/plugin.txt,profile=fc_controller_step"
pargs+=",fn=fc_controller_step@$(sym fc_controller_step)"
rm -f plugin.txt
timeout 600 qemu-system-arm -M netduinoplus2 -nographic -monitor none -serial none \
  -semihosting-config enable=on,target=native -kernel bench.elf -plugin "$out/insn_count.so,$pargs" >run.txt
grep -E '^(INSNS|CYCEST|PERCALL) ' plugin.txt
calls=$(awk '$1 == "INSNS" && $2 == "fc_controller_step" { print $6; exit }' plugin.txt)
python3 "$root/tools/line-profile.py" --elf bench.elf --pcprof plugin.txt --calls "$calls" \
  --addr2line arm-none-eabi-addr2line --nm arm-none-eabi-nm --top "$top" --chain "$depth"

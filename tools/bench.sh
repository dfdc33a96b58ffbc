#!/usr/bin/env bash
# The timing benchmark (issue 7): builds the atmega, atmega-fixed, cf2 and
# cf2-fixed presets, builds one bench image per preset on the same fixed input
# vectors (tools/bench/bench_run.h: init, warm-up, 2 rounds x 8
# vectors, armed), measures, and prints one table:
#   ATmega2560: exact cycles per call from simavr (atmega2560, 16 MHz), each
#               function timed from outside by symbol address and return
#               address (tools/simavr/bench_host.c);
#   Cortex-M4F: executed instructions per call in QEMU (netduinoplus2 =
#               STM32F405), counted by a TCG plugin the same way
#               (platform/cortex-m4-bench/insn_count.c); not cycles.
# then the flat profile of fc_controller_step on the AVR (exclusive cycles per
# call of each function, from the same run: bench_host.c --profile),
# and per image: flash, static RAM, the largest stack frame (-fstack-usage)
# and, on the AVR, the measured stack peak; and the ATmega's F450 (its
# image's airframe) against issue 28's targets.
# Usage: tools/bench.sh [--no-deps]   (everything lands in build/bench/: the
# printed tables in report.txt, the raw figures in results.txt)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

if [ "${1:-}" != "--no-deps" ]; then
  tools/install-deps.sh
fi

presets=(atmega atmega-fixed cf2 cf2-fixed)
for p in "${presets[@]}"; do
  cmake --preset "$p" >/dev/null
  cmake --build --preset "$p" >/dev/null
  echo "built $p: build/$p" >&2
done

out=$root/build/bench
mkdir -p "$out"
# the library's flags, defined once (firmware/flags.mk)
flags_of() { sed -n "s/^$1 := //p" "$root/firmware/flags.mk"; }
read -ra warn <<< "$(flags_of FC_WARNINGS)"
read -ra library_warn <<< "$(flags_of FC_LIBRARY_WARNINGS)"
read -ra m4f_flags <<< "$(flags_of FC_M4F_CPU)"
read -ra m4f_optimise <<< "$(flags_of FC_M4F_OPTIMISE)"
common=(-Os -DNDEBUG -std=gnu11 "${warn[@]}" -I"$root/firmware/include" -I"$root/tools/bench"
        -ffunction-sections -fdata-sections -fstack-usage)
# the modules timed on their own: the hexa runs the filter; the Crazyflie flies
# on the platform's attitude (as its app does), so its filter only forms the rate
modules=(fc_attitude_estimator_step fc_attitude_control_step fc_allocation_speeds
         fc_altitude_reference_step fc_altitude_control_step fc_controller_step)
modules_cf=(fc_attitude_estimator_rate_step "${modules[@]:1}")

# ---- host tools: the simavr runner and the QEMU plugin ----
cc -std=gnu11 -O2 "${warn[@]}" -isystem /usr/include/simavr "$root/tools/simavr/bench_host.c" \
   -o "$out/avr_bench" -lsimavr -lelf
cc -std=gnu11 -O2 "${warn[@]}" -shared -fPIC "$root/platform/cortex-m4-bench/insn_count.c" -o "$out/insn_count.so"

fixed_of() { case $1 in *-fixed) echo 1 ;; *) echo 0 ;; esac; }

# m4f_link ELF LIBRARY [FLAG...]: the M4F bench image of this run ($fx, $cf) on LIBRARY
m4f_link() {
  local elf=$1 lib=$2
  shift 2
  arm-none-eabi-gcc "${m4f_flags[@]}" "${common[@]}" -DFC_NUMERIC_FIXED="$fx" -DBENCH_WORKLOAD_CRAZYFLIE=$cf "$@" \
    --specs=rdimon.specs -nostartfiles -T "$root/platform/cortex-m4-bench/stm32f405.ld" -Wl,--gc-sections \
    -o "$elf" "$root/platform/cortex-m4-bench/bench_m4.c" "$lib" -lm -lrdimon
}
# m4f_library FIXED: libfc-sep.a here, firmware/src/*.c compiled one by one
# with the flags of the cf2 presets' library (firmware/CMakeLists.txt)
m4f_library() {
  local objs=()
  for c in "$root"/firmware/src/*.c; do
    arm-none-eabi-gcc "${m4f_flags[@]}" "${m4f_optimise[@]}" -DNDEBUG -std=gnu11 "${warn[@]}" \
      "${library_warn[@]}" -ffunction-sections -fdata-sections -I"$root/firmware/include" \
      -DFC_NUMERIC_FIXED="$1" -c "$c" -o "$(basename "$c" .c).o"
    objs+=("$(basename "$c" .c).o")
  done
  rm -f libfc-sep.a
  arm-none-eabi-ar rcs libfc-sep.a "${objs[@]}"
}
# m4f_run LIBRARY TAG FUNCTION...: bench.elf here on LIBRARY, run in QEMU with
# the plugin timing each FUNCTION (and profiling fc_controller_step's PCs);
# results under TAG, TAG~est and TAG~est2
m4f_run() {
  local lib=$1 tag=$2
  shift 2
  m4f_link bench.elf "$lib"
  sym() { arm-none-eabi-nm bench.elf | awk -v s="$1" '$3 == s { print "0x" $1 }'; }
  local pargs="begin=$(sym bench_timed_begin),end=$(sym bench_timed_end),out=$PWD/plugin.txt,profile=fc_controller_step"
  for m in "$@"; do pargs+=",fn=$m@$(sym "$m")"; done
  rm -f plugin.txt
  timeout 600 qemu-system-arm -M netduinoplus2 -nographic -monitor none -serial none \
    -semihosting-config enable=on,target=native -kernel bench.elf -plugin "$out/insn_count.so,$pargs" >run.txt ||
    { cat run.txt >&2; echo "bench: $tag run failed" >&2; exit 1; }
  grep -q ': done' run.txt || { cat run.txt >&2; echo "bench: $tag did not finish" >&2; exit 1; }
  awk -v p="$tag" '$1 == "INSNS" { print p, "calls", $2, $3, $4, $5, $6 }
                 $1 == "CYCEST" { print p "~est", "calls", $2, $3, $4, $5, $6 }
                 $1 == "CYCEST2" { print p "~est2", "calls", $2, $3, $4, $5, $6 }' plugin.txt >>"$results"
}

# largest frame among the library's and the bench image's .su files: "bytes function"
largest_frame() { # preset run
  find "$root/build/$1/firmware" "$out/$2" -name '*.su' -print0 | xargs -0 cat |
    awk -F'\t' '{ n = split($1, a, ":"); print $2, a[n] }' | sort -rn | awk 'NR == 1'
}

results=$out/results.txt
: >"$results"
# what this prints, kept beside the raw figures: the results file of the run
exec > >(tee "$out/report.txt")
# three workloads (bench_run.h): the hexa tracking the pad (results under the
# preset's name), the Crazyflie's landing mission (under <preset>-cf) and, on
# the ATmega only, the F450 tracking the pad (<preset>-f450: the ATmega
# image's airframe)
for run in "${presets[@]}" "${presets[@]/%/-cf}" atmega-f450 atmega-fixed-f450; do
  p=${run%-cf}
  p=${p%-f450}
  cf=0
  [ "$run" = "$p-cf" ] && cf=1
  f450=0
  [ "$run" = "$p-f450" ] && f450=1
  fx=$(fixed_of "$p")
  timed=("${modules[@]}")
  [ "$cf" = 1 ] && timed=("${modules_cf[@]}")
  mkdir -p "$out/$run"
  cd "$out/$run"
  case $p in
  atmega*)
    avr-gcc -mmcu=atmega2560 -DF_CPU=16000000UL -maccumulate-args "${common[@]}" -DFC_NUMERIC_FIXED="$fx" -DBENCH_WORKLOAD_CRAZYFLIE=$cf -DBENCH_WORKLOAD_F450=$f450 \
      -o bench.elf "$root/platform/atmega/bench/bench_avr.c" "$root/build/$p/firmware/libfc.a" -lm \
      -Wl,--gc-sections
    if [ "$fx" = 1 ]; then
      sf=$(avr-nm bench.elf | awk '{ print $NF }' |
           grep -E '^__[a-z]+sf[0-9]?$|^__[a-z]+sf[a-z]+$|^__fp_|^(sqrt|sin|cos|tan|atan|atan2|asin|acos|exp|log|pow)f?$' || true)
      if [ -n "$sf" ]; then
        echo "bench: soft-float routines in the fixed AVR image: $sf" >&2
        exit 1
      fi
    fi
    targs=()
    for m in "${timed[@]}"; do targs+=(--time "$m"); done
    "$out/avr_bench" --elf bench.elf "${targs[@]}" --profile fc_controller_step >run.txt || { cat run.txt >&2; echo "bench: $p run failed" >&2; exit 1; }
    awk -v p="$run" '$1 == "CYCLES" { print p, "calls", $2, $3, $4, $5, $6 } $1 == "STACK" { print p, "peak", $2 }' run.txt >>"$results"
    read -r text data bss < <(avr-size -B bench.elf | awk 'NR == 2 { print $1, $2, $3 }')
    ;;
  cf2*)
    # what flies: the preset's library, one translation unit (firmware/amalgamation/fc_library.c)
    m4f_run "$root/build/$p/firmware/libfc.a" "$run" fc_controller_step
    awk -v p="$run" '$1 == "STACK" { print p, "peak", $2 }' run.txt >>"$results"
    # the same image timing each step with DWT->CYCCNT, for a Crazyflie (not run here: CYCCNT reads 0 in QEMU)
    m4f_link bench-dwt.elf "$root/build/$p/firmware/libfc.a" -DBENCH_DWT=1
    read -r text data bss < <(arm-none-eabi-size -B bench.elf | awk 'NR == 2 { print $1, $2, $3 }')
    # the modules: the same sources compiled one by one, so that each step is a
    # call of its own that can be timed (the one unit inlines them); the
    # profile below is of this image too. The library is built once per
    # preset, by its first workload (the hexa's), and the Crazyflie's reuses it
    mkdir -p sep
    sep_lib="$out/$p/sep/libfc-sep.a"
    if [ "$cf" = 0 ]; then
      ( cd sep && m4f_library "$fx" )
    fi
    ( cd sep && m4f_run "$sep_lib" "$run+sep" "${timed[@]}" )
    ;;
  esac
  # worst-case stack of fc_controller_step in this image (call graph + -fstack-usage)
  case $p in atmega*) arch=avr; od=avr-objdump ;; *) arch=arm; od=arm-none-eabi-objdump ;; esac
  python3 "$root/tools/stack-depth.py" --arch "$arch" --objdump "$od" --elf bench.elf \
    --su "$root/build/$p/firmware" --su "$out/$run" --target "$p" >stack-depth.txt ||
    { cat stack-depth.txt >&2; echo "bench: $p stack depth failed" >&2; exit 1; }
  read -r fbytes fname < <(largest_frame "$p" "$run")
  echo "$run size $((text + data)) $((data + bss)) $fbytes $fname" >>"$results"
  cd "$root"
done

# ---- the tables ----
# table SUFFIX TITLE [sizes]: the timing table of one workload (SUFFIX '' or -cf)
table() {
local mods="${modules[*]}"
[ "$1" = -cf ] && mods="${modules_cf[*]}"
awk -v mods="$mods" -v w="$1" -v title="$2" -v sizes="${3:-0}" '
  $2 == "calls" { mn[$1, $3] = $4; mx[$1, $3] = $5; mean[$1, $3] = $6; n[$1, $3] = $7 }
  $2 == "peak"  { peak[$1] = $3 }
  $2 == "size"  { flash[$1] = $3; ram[$1] = $4; fr[$1] = $5 " B " $6 }
  function rng(p, m) { return (p, m) in mn ? sprintf("%d-%d", mn[p, m], mx[p, m]) : "n/a" }
  function ratio(a, b, m) { return mean[b, m] > 0 && mean[a, m] > 0 ? sprintf("%.2f", mean[b, m] / mean[a, m]) : "n/a" }
  # the M4F run of row m: a module from the image of separately compiled
  # sources (+sep), fc_controller_step from the one-unit library that flies
  function m4(p, m, kind) { return (m == "fc_controller_step" ? p w : p w "+sep") kind }
  END {
    k = split(mods, M, " ")
    printf "%s: per call, %d calls each (2 rounds x 8 fixed input vectors, armed, dt 0.002 s)\n", title, n["atmega" w, "fc_controller_step"]
    printf "AVR: ATmega2560 cycles, exact (simavr). M4F ins: Cortex-M4F executed instructions, exact (QEMU TCG plugin);\n"
    printf "M4F est: cycles ESTIMATED from the Cortex-M4 instruction timings and its LDR/STR pipelining (no flash wait\n"
    printf "states; see insn_count.c).\n"
    printf "ratio: fixed/float, of the means.\n\n"
    printf "%-31s|%16s |%16s |%6s |%14s |%14s |%6s |%14s |%14s\n", "function", "AVR float cyc", "AVR fixed cyc", "ratio", "M4F float ins", "M4F fixed ins", "ratio", "M4F float est", "M4F fixed est"
    printf "%-31s|%16s-|%16s-|%6s-|%14s-|%14s-|%6s-|%14s-|%14s\n", "-------------------------------", "----------------", "----------------", "------", "--------------", "--------------", "------", "--------------", "--------------"
    for (i = 1; i <= k; i++) {
      m = M[i]
      printf "%-31s|%16s |%16s |%6s |%14s |%14s |%6s |%14s |%14s\n", m, rng("atmega" w, m), rng("atmega-fixed" w, m), ratio("atmega" w, "atmega-fixed" w, m), rng(m4("cf2", m, ""), m), rng(m4("cf2-fixed", m, ""), m), ratio(m4("cf2", m, ""), m4("cf2-fixed", m, ""), m), rng(m4("cf2", m, "~est"), m), rng(m4("cf2-fixed", m, "~est"), m)
    }
    m = "fc_controller_step"
    printf "%-31s|%16s |%16s |%6s |%14s |%14s |%6s |%14s |%14s\n", m " mean", sprintf("%d", mean["atmega" w, m]), sprintf("%d", mean["atmega-fixed" w, m]), "", sprintf("%d", mean["cf2" w, m]), sprintf("%d", mean["cf2-fixed" w, m]), "", sprintf("%d", mean["cf2" w "~est", m]), sprintf("%d", mean["cf2-fixed" w "~est", m])
    printf "(mean over the 16 calls, the load per step: each part of the outer group runs in one minor frame of every 5 steps)\n"
    printf "%-31s|%16s |%16s |%6s |%14s |%14s |%6s |%14s |%14s\n", "  M4F, sources one by one", "", "", "", rng("cf2" w "+sep", m), rng("cf2-fixed" w "+sep", m), "", rng("cf2" w "+sep~est", m), rng("cf2-fixed" w "+sep~est", m)
    printf "(M4F: fc_controller_step of the library that flies, one translation unit (firmware/amalgamation/fc_library.c), which\n"
    printf "inlines the modules; the module rows and the row above are the same sources compiled one by one, the modules calls)\n"
    printf "%-31s|%16s |%16s |%6s |%14s |%14s |%6s |%14s |%14s\n", "  est, LDR/STR at 2 cyc", "", "", "", "", "", "", rng("cf2" w "~est2", m), rng("cf2-fixed" w "~est2", m)
    printf "(fc_controller_step estimated with every LDR/STR at 2 cycles, no pipelining: the upper side of the load/store\n"
    printf "timing, and the estimate of the notes before the pipelining was modelled)\n"
    if (!sizes) { printf "\n"; exit }
    printf "\n%-13s | %12s | %10s | %-40s | %s\n", "image", "flash bytes", "RAM bytes", "largest stack frame (-fstack-usage)", "stack peak, run"
    printf "%-13s-+-%12s-+-%10s-+-%-40s-+-%s\n", "-------------", "------------", "----------", "----------------------------------------", "---------------"
    split("atmega atmega-fixed cf2 cf2-fixed", P, " ")
    for (i = 1; i <= 4; i++) {
      p = P[i]
      printf "%-13s | %12d | %10d | %-40s | %s\n", p, flash[p], ram[p], fr[p], (p in peak) ? peak[p] " B" : "n/a"
    }
    printf "\nflash = .text + .data, RAM = .data + .bss (static), of the bench image (library + bench_run.h + startup;\n"
    printf "on the M4F newlib semihosting printf). Stack peak of the run from reset (init included): AVR lowest SP\n"
    printf "in simavr; M4F painted-stack high-water mark. Images and raw output: build/bench/<preset>/;\n"
    printf "bench-dwt.elf there times each step with DWT->CYCCNT on a real STM32F405 (Crazyflie).\n"
  }' "$results"
}
table "" "Hexa 4 kg, ssc-adaptive, tracking the pad (TRACK_PAD)"
table -cf "Crazyflie 2.x, ssc, landing mission (LAND), a range sample on 2 of the 8 vectors"
table "" "Hexa 4 kg (the images' sizes below are the same for both workloads)" 1 | sed -n '/^image/,$p'

# ---- the ATmega's F450 against issue 28's targets ----
echo
echo "ATmega2560, F450 quad, ssc-adaptive, tracking the pad, 500 Hz (the ATmega image's airframe): exact cycles per"
echo "call, min-max (mean). inner modules: the sum of the means of the modules that run on every step (filter,"
echo "attitude law, reference, altitude law, allocation), without the controller's glue; issue 28's targets beside."
awk -v mods="${modules[*]}" '
  $2 == "calls" { mn[$1, $3] = $4; mx[$1, $3] = $5; mean[$1, $3] = $6 }
  END {
    k = split(mods, M, " ")
    printf "  %-30s | %-26s | %-26s | %s\n", "function", "float", "fixed", "float/fixed"
    for (i = 1; i <= k; i++) {
      m = M[i]
      printf "  %-30s | %-26s | %-26s | %.2f\n", m, \
        sprintf("%d-%d (%d)", mn["atmega-f450", m], mx["atmega-f450", m], mean["atmega-f450", m]), \
        sprintf("%d-%d (%d)", mn["atmega-fixed-f450", m], mx["atmega-fixed-f450", m], mean["atmega-fixed-f450", m]), \
        (mean["atmega-fixed-f450", m] > 0 ? mean["atmega-f450", m] / mean["atmega-fixed-f450", m] : 0)
      if (m != "fc_controller_step") { inner_fl += mean["atmega-f450", m]; inner_fx += mean["atmega-fixed-f450", m] }
    }
    printf "  %-30s | %-26d | %-26d | %.2f   (target: fixed <= 16000, ratio >= 3)\n", "inner modules (sum of means)", inner_fl, inner_fx, (inner_fx > 0 ? inner_fl / inner_fx : 0)
    m = "fc_controller_step"
    printf "  %-30s | %-26d | %-26d |        (target: fixed <= 24000)\n", "worst step", mx["atmega-f450", m], mx["atmega-fixed-f450", m]
    printf "  %-30s | %-26d | %-26d |        (target: fixed <= 20000)\n", "mean step", mean["atmega-f450", m], mean["atmega-fixed-f450", m]
  }' "$results"
# the flight image (platform/atmega, its controller from the build-time snapshot), not the bench image
flight_flash() { avr-size -B "$root/build/$1/platform/atmega/fc-atmega.elf" | awk 'NR == 2 { print $1 + $2 }'; }
printf "  %-30s | %-26d | %-26d |        (target: fixed <= 131072)\n", "flight image flash, bytes" \
  "$(flight_flash atmega)" "$(flight_flash atmega-fixed)"

# ---- the M4F float step call by call: which minor frames cost what ----
echo
echo "Cortex-M4F float, fc_controller_step of each timed call in order (est cycles, the library that flies): the"
echo "first is the arming step; the outer group's parts (position loop, pad model, the pieces of its work ahead) come once in 5."
for run in cf2 cf2-cf; do
  awk -v r="$run" '$1 == "PERCALL" { $1 = ""; $2 = ""; printf "  %-7s%s\n", r, $0 }' "$out/$run/plugin.txt"
done
echo "ATmega2560, fc_controller_step of the same calls (exact cycles):"
for run in atmega atmega-fixed atmega-cf atmega-fixed-cf; do
  awk -v r="$run" '$1 == "PERCALL" && $2 == "fc_controller_step" { $1 = ""; $2 = ""; printf "  %-16s%s\n", r, $0 }' "$out/$run/run.txt"
done

# ---- where fc_controller_step's AVR cycles go ----
echo
echo "Flat profile of fc_controller_step on the ATmega2560 (simavr, same run): exclusive cycles per step"
echo "charged to the function holding the PC, calls per step, share; top 15 (all: build/bench/<preset>/run.txt)."
for p in atmega-fixed atmega atmega-fixed-cf; do
  echo "$p:"
  # (no "| head": under pipefail its early exit fails the pipeline)
  awk '$1 == "PROFILE" && ++n <= 15 { printf "  %-34s %8d cyc %7.2f calls %5.1f %%\n", $2, $3, $4, $5 }' "$out/$p/run.txt"
done
echo
echo "The same cycles of fc_controller_step by kind of AVR instruction (cycles per step, share):"
printf "  %-26s" "kind"
class_files=()
for r in atmega-cf atmega-fixed-cf atmega atmega-fixed; do
  printf " | %-16s" "$r"
  class_files+=("$out/$r/run.txt")
done
printf "\n"
awk '
  FNR == 1 { file++ }
  $1 == "CLASS" { kind = $2; for (i = 3; i < NF - 1; i++) kind = kind " " $i
                  if (!(kind in seen)) { seen[kind] = 1; order[++k] = kind }
                  cyc[kind, file] = $(NF - 1); pct[kind, file] = $NF }
  END { for (j = 1; j <= k; j++) { printf "  %-26s", order[j]
          for (f = 1; f <= file; f++) printf " | %7d %5.1f %%", cyc[order[j], f], pct[order[j], f]
          printf "\n" } }' "${class_files[@]}"
echo
echo "Flat profile of fc_controller_step on the Cortex-M4F (QEMU plugin, the image of the sources compiled one by"
echo "one, where each function keeps its own code): instructions and estimated cycles per step charged to the"
echo "function holding the PC; top 15."
for p in cf2 cf2-fixed cf2-cf; do
  echo "$p:"
  n=$(awk '$1 == "INSNS" && $2 == "fc_controller_step" { print $6 }' "$out/$p/sep/plugin.txt")
  python3 "$root/tools/pc-profile.py" --nm arm-none-eabi-nm --elf "$out/$p/sep/bench.elf" --calls "$n" --top 15 \
    "$out/$p/sep/plugin.txt"
done

# ---- worst-case stack depth of fc_controller_step (tools/stack-depth.py) ----
echo
echo "Worst-case stack of fc_controller_step per image: call graph from the disassembly, frames from"
echo "-fstack-usage (\"est\": a toolchain routine's frame read from its disassembly); AVR with return addresses."
for p in "${presets[@]}"; do
  sed -n '1,2p' "$out/$p/stack-depth.txt"
done

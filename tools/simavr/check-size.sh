#!/usr/bin/env bash
# Size of the ATmega image: flash (.text + .data) against the 248 KiB below
# the Arduino Mega's 8 KiB stk500v2 bootloader (README: flashing over USB
# through it; an ISP programmer would give the whole 256 KiB), static RAM
# (.data + .bss + .noinit) against 8 KiB; the stack comes on top of the
# static RAM (avr_loop_test measures its peak in simavr). On the fixed
# backend the linked image must hold no soft-float routine at all.
# FLASH_MAX, if given, is a tighter flash budget in bytes (the flight image's).
#   check-size.sh ELF SIZE NM NUMERIC [FLASH_MAX]
set -euo pipefail
elf=$1
size=$2
nm=$3
numeric=$4
flash_max=${5:-253952} # 256 KiB - the 8 KiB boot section
read -r text data bss noinit < <("$size" -A "$elf" | awk '
  $1 == ".text" { t = $2 } $1 == ".data" { d = $2 } $1 == ".bss" { b = $2 } $1 == ".noinit" { n = $2 }
  END { print t + 0, d + 0, b + 0, n + 0 }')
flash=$((text + data))
ram=$((data + bss + noinit))
status=0
echo "image $(basename "$elf") ($numeric): text $text, data $data, bss $bss, noinit $noinit bytes"
echo "flash $flash of $flash_max bytes ($((flash * 100 / flash_max))%), $((flash_max - flash)) left; static RAM $ram of 8192 bytes ($((ram * 100 / 8192))%), $((8192 - ram)) bytes left for the stack"
if [ "$flash" -gt "$flash_max" ] || [ "$ram" -ge 8192 ]; then
  echo "DOES NOT FIT"
  status=1
fi
float_routines=$("$nm" "$elf" | awk '{ print $NF }' |
  grep -E '^__[a-z]+sf[0-9]?$|^__[a-z]+sf[a-z]+$|^__fp_|^(sqrt|sin|cos|tan|atan|atan2|asin|acos|exp|log|pow)f?$' || true)
if [ "$numeric" = fixed ]; then
  if [ -n "$float_routines" ]; then
    echo "SOFT-FLOAT in the fixed image: $(tr '\n' ' ' <<<"$float_routines")"
    status=1
  else
    echo "no soft-float routine linked"
  fi
else
  echo "soft-float routines linked: $(wc -l <<<"$float_routines")"
fi
exit $status

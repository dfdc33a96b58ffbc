#!/usr/bin/env bash
# Installs the Debian packages the build and the tests need; does nothing
# when they are all present already. Run as root (or with sudo available).
set -euo pipefail

packages=(
  build-essential cmake pkg-config      # host build
  libcmocka-dev                         # unit tests
  libeigen3-dev                         # the independent oracle for the math tests
  libinih-dev libcjson-dev gnuplot-nox  # sim_host: scenario files, JSON metrics, figures
  gcc-arm-none-eabi libnewlib-arm-none-eabi   # Crazyflie 2.x (Cortex-M4F)
  gcc-avr avr-libc binutils-avr         # ATmega2560
  simavr libsimavr-dev libelf-dev       # ATmega2560 loop test in simavr (tools/simavr)
  clang libclang-rt-14-dev              # libFuzzer harnesses (tests/fuzz, presets fuzz, fuzz-fixed)
  qemu-system-arm                       # Cortex-M4F benchmark in QEMU (tools/bench.sh)
  cppcheck python3 clang-tidy-14        # tools/static-analysis.sh (cppcheck + MISRA addon, clang-tidy); python3
                                        # also for tools/stack-depth.py (cross.stack_depth, bench.sh)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"

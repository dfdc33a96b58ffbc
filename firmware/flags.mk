# The library's compile flags, defined once. Read by CMake (cmake/fc-flags.cmake:
# every preset), by the Crazyflie app's Kbuild (platform/crazyflie/fclib/Kbuild)
# and by tools/bench.sh. One "NAME := flags" per line, so make includes the file
# as it is and the others read the lines.

# Every C source of every target, the library's, the tests' and the tools'.
FC_WARNINGS := -Wall -Wextra -Werror -Wdouble-promotion -Wshadow -Wundef
# The library's sources besides: no silent narrowing (the fixed-point code).
FC_LIBRARY_WARNINGS := -Wconversion -Wsign-conversion
# The Cortex-M4F (STM32F405) core and its single-precision FPU.
FC_M4F_CPU := -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -fno-math-errno
# The Crazyflie has the flash for speed: the library at -O3; small zeroing
# loops stay a few stores instead of memset calls (a call each, every step).
FC_M4F_OPTIMISE := -O3 -fno-tree-loop-distribute-patterns
# The inliner's limits raised, so that in the amalgamation
# (firmware/amalgamation/fc_library.c) the module steps and their helpers are
# inlined into fc_controller_step.
FC_M4F_INLINE := --param=max-inline-insns-auto=1000 --param=inline-unit-growth=10000 --param=large-function-growth=10000

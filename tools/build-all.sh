#!/usr/bin/env bash
# Builds the library for every target and backend and prints what each costs.
# (A convenience beside the README's two commands.)
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install-deps.sh

for preset in host host-fixed cf2 cf2-fixed atmega atmega-fixed; do
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" >/dev/null
  echo "built $preset: build/$preset"
done
for preset in cf2 cf2-fixed atmega atmega-fixed; do
  ctest --preset "$preset" -R 'cross.(size|stack_usage)' -V 2>/dev/null | grep -E 'library size|largest stack frame' | sed 's/^[0-9]*: //'
done

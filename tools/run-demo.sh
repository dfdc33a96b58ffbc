#!/usr/bin/env bash
# The SIL landing demo (the README's main command): installs what it needs,
# builds the host preset, flies the dissertation's 4.4 scenario (seed-4.4) with
# SSC without and with adaptation through the firmware library, and leaves the
# metrics and the figures (the dissertation's Figures 4.2 and 4.3 and a summary
# per run) in results/seed-4.4/. Extra arguments go to fc-sil (e.g. --numeric fixed).
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install-deps.sh

build=${FC_DEMO_BUILD_DIR:-build/host}   # the host preset's directory unless told otherwise
cmake --preset host -B "$build" >/dev/null
cmake --build "$build" -j2 --target fc-sil >/dev/null
echo "built $build/sim_host/fc-sil"

out=results/seed-4.4
rm -rf "$out"
mkdir -p "$out"
"$build/sim_host/fc-sil" --scenario seed-4.4 --controller ssc,ssc-adaptive \
  --json "$out/metrics.json" --csv "$out/trace.csv" --plot "$out" "$@"
echo
echo "results in $out:"
ls "$out"/*.png "$out"/*.json | sed 's/^/  /'

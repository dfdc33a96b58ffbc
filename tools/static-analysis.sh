#!/usr/bin/env bash
# Static analysis of the tree (issue 9); every finding is an error.
#
#   cppcheck   plain (--enable=warning,style,performance,portability) over
#              firmware/src/*.c in both numeric backends and over the host code
#              (sim_host/*.c, platform/crazyflie/cf_convert.c);
#   misra      cppcheck's MISRA C:2012 addon over firmware/src/*.c in both
#              backends, minus the deviations of docs/misra-deviations.md
#              (tools/misra-suppressions*.txt);
#   analyzer   gcc -fanalyzer -Werror on every library source, sim_host's
#              firmware adapter and platform/crazyflie/cf_convert.c, both backends;
#   tidy       clang-tidy 14 with the committed .clang-tidy (WarningsAsErrors)
#              over the same files plus the rest of sim_host/.
#
# The file lists are globs (firmware/src/*.c, sim_host/*.c) and the compile
# commands come from CMake's compile database (a host configure in
# build/static-analysis, nothing is built), so new modules are picked up.
# Usage: tools/static-analysis.sh [cppcheck] [misra] [analyzer] [tidy]   (no argument: all)
# Environment: JOBS (parallel jobs, default 2).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
out=$root/build/static-analysis
jobs=${JOBS:-2}
steps=("$@")
[ ${#steps[@]} -eq 0 ] && steps=(cppcheck misra analyzer tidy)
mkdir -p "$out"

failed=()
summary=()
note() { summary+=("$(printf '%-9s %-7s %s' "$1" "$2" "$3")"); }

firmware_sources=("$root"/firmware/src/*.c)
host_sources=("$root"/sim_host/*.c "$root"/platform/crazyflie/cf_convert.c)

# ---- the compile database ------------------------------------------------
# One host configure gives every command we need: the firmware sources in both
# backends (sim_host's fsw_objs_float / fsw_objs_fixed), the adapter, the SIL
# core and cf_convert.c. Split into one database per backend, one entry per file.
compile_db() {
  [ -f "$out/db/fixed/compile_commands.json" ] && [ "${FC_SA_RECONFIGURE:-1}" = 0 ] && return 0
  cmake -S "$root" -B "$out/cmake" -DFC_NUMERIC=float -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >"$out/cmake.log" 2>&1 ||
    { cat "$out/cmake.log" >&2; echo "static-analysis: configure failed" >&2; exit 1; }
  python3 - "$root" "$out" <<'EOF'
import json, os, re, shlex, sys
root, out = sys.argv[1], sys.argv[2]
db = json.load(open(os.path.join(out, "cmake", "compile_commands.json")))
wanted = lambda f: (f.startswith(root + "/firmware/src/") or
                    (f.startswith(root + "/sim_host/") and os.path.dirname(f) == root + "/sim_host") or
                    f == root + "/platform/crazyflie/cf_convert.c")
per = {"float": {}, "fixed": {}}
for e in db:
    f = os.path.normpath(os.path.join(e["directory"], e["file"]))
    if not wanted(f):
        continue
    args = e["arguments"] if "arguments" in e else shlex.split(e["command"])
    m = [a for a in args if a.startswith("-DFC_NUMERIC_FIXED=")]
    if not m:                      # the SIL core: no firmware header, one backend
        per["float"].setdefault(f, args)
        continue
    for backend, value in (("float", "0"), ("fixed", "1")):
        # cf_convert.c is only configured in this build's backend: the other by substitution
        a = [("-DFC_NUMERIC_FIXED=" + value if x.startswith("-DFC_NUMERIC_FIXED=") else x) for x in args]
        a = [("-DFSW_BACKEND=" + backend if x.startswith("-DFSW_BACKEND=") else x) for x in a]
        old = per[backend].get(f)
        # prefer sim_host's objects (fsw_objs_<backend>) for the firmware: same flags as libfc
        if old is None or any(x == "-DFSW_BACKEND=" + backend for x in a):
            per[backend][f] = a
for backend, entries in per.items():
    d = os.path.join(out, "db", backend)
    os.makedirs(d, exist_ok=True)
    json.dump([{"directory": os.path.join(out, "cmake"), "file": f, "arguments": a}
               for f, a in sorted(entries.items())], open(os.path.join(d, "compile_commands.json"), "w"), indent=1)
    # one analyzer command per line (output to /dev/null), for xargs
    with open(os.path.join(d, "analyzer.cmds"), "w") as fh:
        for f, a in sorted(entries.items()):
            a = list(a)
            if "-o" in a:
                i = a.index("-o"); del a[i:i + 2]
            a = [x for x in a if not x.startswith(("-MD", "-MF", "-MT")) ]
            fh.write(shlex.join(a + ["-fanalyzer", "-fdiagnostics-plain-output", "-o", "/dev/null"]) + "\n")
    with open(os.path.join(d, "files"), "w") as fh:
        fh.write("\n".join(sorted(entries)) + "\n")
EOF
  for f in "${firmware_sources[@]}"; do
    for b in float fixed; do
      grep -qxF "$f" "$out/db/$b/files" || { echo "static-analysis: $f not in the $b compile database" >&2; exit 1; }
    done
  done
}

# count "file:line:col: severity:" lines of a log
count() { grep -cE '^[^ :]+:[0-9]+:([0-9]+:)? ?(warning|error|style|performance|portability|information)' "$1" || true; }

run_cppcheck() {
  local log=$out/cppcheck.log n
  : >"$log"
  local common=(-q --std=c11 --platform=unix64 --enable=warning,style,performance,portability
                --inline-suppr --error-exitcode=1 -j "$jobs" -I"$root/firmware/include")
  local status=0
  for fx in 0 1; do
    cppcheck "${common[@]}" -DFC_NUMERIC_FIXED=$fx "${firmware_sources[@]}" 2>>"$log" || status=1
  done
  cppcheck "${common[@]}" -I"$root/sim_host" -I"$root/platform/crazyflie" "${host_sources[@]}" 2>>"$log" || status=1
  n=$(count "$log")
  note cppcheck "$n" "findings (firmware float+fixed, sim_host, cf_convert; $log)"
  if [ $status -ne 0 ] || [ "$n" -ne 0 ]; then cat "$log"; failed+=(cppcheck); fi
}

run_misra() {
  local log=$out/misra.log n status=0
  : >"$log"
  for fx in 0 1; do
    local supp=(--suppressions-list="$root/tools/misra-suppressions.txt")
    [ $fx = 1 ] && supp+=(--suppressions-list="$root/tools/misra-suppressions-fixed.txt")
    cppcheck -q --std=c11 --platform=unix64 --addon=misra --inline-suppr --error-exitcode=1 -j "$jobs" \
      "${supp[@]}" -I"$root/firmware/include" -DFC_NUMERIC_FIXED=$fx \
      "${firmware_sources[@]}" 2>>"$log" || status=1
  done
  n=$(count "$log")
  note misra "$n" "findings outside docs/misra-deviations.md (firmware float+fixed; $log)"
  if [ $status -ne 0 ] || [ "$n" -ne 0 ]; then cat "$log"; failed+=(misra); fi
}

run_analyzer() {
  compile_db
  local log=$out/analyzer.log n status=0
  : >"$log"
  for b in float fixed; do
    # only the firmware, the adapter and cf_convert.c: the SIL core is host tooling
    grep -E '/firmware/src/|/fsw_adapter\.c|/cf_convert\.c' "$out/db/$b/analyzer.cmds" |
      (cd "$out/cmake" && xargs -P "$jobs" -I{} sh -c '{}') 2>>"$log" || status=1
  done
  n=$(count "$log")
  note analyzer "$n" "warnings of gcc -fanalyzer -Werror (firmware, fsw_adapter, cf_convert; float+fixed; $log)"
  if [ $status -ne 0 ] || [ "$n" -ne 0 ]; then cat "$log"; failed+=(analyzer); fi
}

run_tidy() {
  compile_db
  local log=$out/clang-tidy.log n status=0
  : >"$log"
  for b in float fixed; do
    # fixed: only what depends on the backend (the SIL core does not)
    local files
    if [ $b = fixed ]; then
      files=$(grep -E '/firmware/src/|/fsw_adapter\.c|/cf_convert\.c' "$out/db/$b/files")
    else
      files=$(cat "$out/db/$b/files")
    fi
    # -Wcomma: the comma operator, which MISRA 12.3 forbids (docs/misra-deviations.md)
    tr '\n' '\0' <<<"$files" | xargs -0 -P "$jobs" -n 4 clang-tidy-14 --quiet -p "$out/db/$b" \
      --extra-arg=-Wcomma >>"$log" 2>"$out/clang-tidy.stderr" || status=1
  done
  n=$(grep -cE '^[^ :]+:[0-9]+:[0-9]+: (warning|error):' "$log" || true)
  note tidy "$n" "findings of clang-tidy ($root/.clang-tidy; firmware float+fixed, sim_host, cf_convert; $log)"
  if [ $status -ne 0 ] || [ "$n" -ne 0 ]; then cat "$log" "$out/clang-tidy.stderr"; failed+=(tidy); fi
}

for s in "${steps[@]}"; do
  start=$SECONDS
  case $s in
  cppcheck) run_cppcheck ;;
  misra) run_misra ;;
  analyzer) run_analyzer ;;
  tidy) run_tidy ;;
  *) echo "usage: $0 [cppcheck] [misra] [analyzer] [tidy]" >&2; exit 2 ;;
  esac
  summary[-1]+=" [$((SECONDS - start)) s]"
done

echo "static analysis:"
printf '  %s\n' "${summary[@]}"
if [ ${#failed[@]} -ne 0 ]; then
  echo "static analysis FAILED: ${failed[*]}"
  exit 1
fi
echo "static analysis: no findings"

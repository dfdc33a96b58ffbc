#!/usr/bin/env python3
"""Compare a processor-in-the-loop run with the host's fixed-point run of the
same scenario (tools/pil.sh): every metric of fc-sil's JSON and every cell of
the CSV traces must be identical, since the ATmega image and the host run the
same fixed-point code on the same inputs. Prints one line per scenario and
exits 1 on any difference.

usage: pil-compare.py NAME PIL.json FIXED.json PIL.csv FIXED.csv
"""
import csv
import json
import sys

# what depends on the machine, not on the controller
IGNORED = {"backend", "wall_time_s", "real_time_factor", "cpu_time_s"}


def metrics(path):
    with open(path) as f:
        doc = json.load(f)
    runs = doc if isinstance(doc, list) else [doc]
    return [{k: v for k, v in run.items() if k not in IGNORED} for run in runs]


def rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    name, pil_json, fixed_json, pil_csv, fixed_csv = sys.argv[1:]
    problems = []
    pil_m, fixed_m = metrics(pil_json), metrics(fixed_json)
    if len(pil_m) != len(fixed_m):
        problems.append(f"{len(pil_m)} PIL runs, {len(fixed_m)} host runs")
    for a, b in zip(pil_m, fixed_m):
        for key in sorted(set(a) | set(b)):
            if a.get(key) != b.get(key):
                problems.append(f"{key}: PIL {a.get(key)!r}, host fixed {b.get(key)!r}")
    pil_rows, fixed_rows = rows(pil_csv), rows(fixed_csv)
    if len(pil_rows) != len(fixed_rows):
        problems.append(f"trace: {len(pil_rows)} PIL rows, {len(fixed_rows)} host rows")
    differing = [i for i, (a, b) in enumerate(zip(pil_rows, fixed_rows)) if a != b]
    if differing:
        problems.append(f"trace: {len(differing)} rows differ, the first is row {differing[0]}")
    shown = ", ".join(f"{k} {pil_m[0].get(k)}" for k in ("rms_error_m", "touchdown_rel_speed_mps", "theta_rel_error")
                      if pil_m and pil_m[0].get(k) is not None)
    if problems:
        print(f"{name}: PIL and host fixed DIFFER")
        for p in problems[:20]:
            print(f"  {p}")
        return 1
    print(f"{name}: PIL = host fixed: {len(pil_m[0])} metrics and {len(pil_rows) - 1} trace rows x "
          f"{len(pil_rows[0]) if pil_rows else 0} columns identical ({shown})")
    return 0


if __name__ == "__main__":
    sys.exit(main())

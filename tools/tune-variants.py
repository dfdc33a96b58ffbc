#!/usr/bin/env python3
"""Tunes every altitude-law variant by one procedure (issue 29's fair comparison).

For each scenario and variant, fc-sil flies the same 5 x 5 grid of the two
knobs (controller.bandwidth_scale x controller.authority_scale, factors on the
variant's preset gains; sim_host/fsw_adapter.c's scale_law_gains says which
gains) over the same seeds. Objective: the median over the seeds of
rms_error_m x control_tv_per_s. A cell is admissible only if every seed runs
with no NaN output, no divergence, no thrust saturation after the transient
(thrust_saturated_s = 0) and, in a landing, a touchdown no faster than
TOUCHDOWN_MAX_MPS or, where the preset (1, 1) lands faster, than the preset's
worst. The admissible cell of least objective wins; with none, the
preset (1, 1) stays and the table says so.

Writes sim_host/results/tuning.md (winner and preset per scenario and variant)
and sim_host/results/tuned.json (the winning knobs, which
tools/compare-variants.sh flies).

  tools/tune-variants.py [--numeric float|fixed] [--scenario NAME ...] [--coarse] [--cached-only]

The seeds (TUNING_SEEDS) are not the comparison's (1..RUNS). fc-sil runs under
nice -n 19, at most JOBS at a time; each cell's JSON is kept in
build/results/tuning-runs/ (one directory per fc-sil build) and not run again.
"""
import argparse
import concurrent.futures
import datetime
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FC_SIL = os.path.join(ROOT, "build", "host", "sim_host", "fc-sil")
# the results, kept in the repository (sim_host/README.md points to them)
OUT_DIR = os.path.join(ROOT, "sim_host", "results")
# the runs behind them, per fc-sil build
CACHE_DIR = os.path.join(ROOT, "build", "results", "tuning-runs")

BANDWIDTH = (0.5, 0.7, 1.0, 1.4, 2.0)
AUTHORITY = (0.25, 0.5, 1.0, 2.0, 4.0)
TUNING_SEEDS = (1001, 3)  # first seed, count
JOBS = 2
# every scenario's --set beyond the knobs: seed-4.4 with its sensors' noise on,
# as tools/compare-variants.sh flies it
SCENARIOS = {
    "seed-4.4": ["montecarlo.noise_scale_min=1", "montecarlo.noise_scale_max=1"],
    "robustness": [],
    "cf2-pad": [],
    "hexa-deck": [],
}
# issue 29's landing bounds (its Monte-Carlo p99 targets), on every tuning seed
TOUCHDOWN_MAX_MPS = {"cf2-pad": 0.05, "hexa-deck": 0.10}


def cell_path(cache_dir, cell):
    """The cached JSON of cell (scenario, variant, bandwidth, authority)."""
    return os.path.join(cache_dir, "{}-{}-{}-{}.json".format(*cell))


def run_cell(scenario, variant, bandwidth, authority, numeric, cache_dir):
    """fc-sil's JSON for one grid cell ({"per_run": [...]}), or {"error": why it did not run}."""
    path = cell_path(cache_dir, (scenario, variant, bandwidth, authority))
    if not os.path.exists(path):
        sets = SCENARIOS[scenario] + [f"controller.bandwidth_scale={bandwidth}",
                                      f"controller.authority_scale={authority}"]
        cmd = ["nice", "-n", "19", FC_SIL, "--scenario", scenario, "--controller", variant,
               "--numeric", numeric, "--runs", str(TUNING_SEEDS[1]), "--seed", str(TUNING_SEEDS[0]),
               "--quiet", "--json", path + ".tmp"]
        for s in sets:
            cmd += ["--set", s]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            last = (proc.stderr.strip().splitlines() or ["fc-sil failed"])[-1]
            # e.g. "fc_controller_init failed (a parameter out of range)"
            with open(path + ".tmp", "w") as f:
                json.dump({"error": last.rsplit(": ", 1)[-1]}, f)
        os.replace(path + ".tmp", path)
    with open(path) as f:
        return json.load(f)


def worst_touchdown_mps(runs):
    return max(r["touchdown_rel_speed_mps"] or float("inf") for r in runs)


def judge(runs, touchdown_max_mps):
    """(objective, why not admissible or None) of one cell's runs."""
    for r in runs:
        if r["nan_outputs"]:
            return None, "NaN output"
        if r["diverged"]:
            return None, "diverged"
        if r["thrust_saturated_s"] is None or r["thrust_saturated_s"] > 0.0:
            return None, "thrust saturated"
    if touchdown_max_mps is not None and not worst_touchdown_mps(runs) <= touchdown_max_mps:
        return None, f"touchdown > {touchdown_max_mps:.3g} m/s"
    return statistics.median(r["rms_error_m"] * r["control_tv_per_s"] for r in runs), None


def variants():
    out = subprocess.run([FC_SIL, "--list-controllers"], capture_output=True, text=True, check=True)
    return out.stdout.split()


def tune(scenarios, numeric, cached_only, grid):
    """{(scenario, variant, bandwidth, authority): fc-sil's JSON}, every cell of grid run (or
    cached; cached_only: only the cached cells)."""
    # the cache: one directory per fc-sil build, so that a rebuilt fc-sil runs again
    stamp = os.stat(FC_SIL)
    cache_dir = os.path.join(CACHE_DIR, f"{numeric}-{int(stamp.st_mtime)}-{stamp.st_size}")
    os.makedirs(cache_dir, exist_ok=True)
    cells = [(s, v, b, a) for s in scenarios for v in variants() for b in grid[0] for a in grid[1]]
    if cached_only:
        cells = [c for c in cells if os.path.exists(cell_path(cache_dir, c))]
    results = {}
    with concurrent.futures.ThreadPoolExecutor(JOBS) as pool:
        futures = {pool.submit(run_cell, *cell, numeric, cache_dir): cell for cell in cells}
        for done, future in enumerate(concurrent.futures.as_completed(futures), 1):
            results[futures[future]] = future.result()
            print(f"\rtune-variants: {done}/{len(cells)}", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    return results


def winners(results, scenarios):
    """{scenario: {variant: entry}}: the winning knobs, their objective, the preset's."""
    table = {s: {} for s in scenarios}
    for (s, v, b, a), cell in sorted(results.items()):
        entry = table[s].setdefault(v, {"bandwidth_scale": 1.0, "authority_scale": 1.0, "objective": None,
                                        "preset_objective": None, "preset_rejected": "not run",
                                        "admissible_cells": 0, "cells_run": 0})
        entry["cells_run"] += 1
        preset = results.get((s, v, 1.0, 1.0), {})
        # a landing no faster than the stated bound, or than the preset where it lands faster
        touchdown_max_mps = TOUCHDOWN_MAX_MPS.get(s)
        if touchdown_max_mps is not None and "per_run" in preset:
            touchdown_max_mps = max(touchdown_max_mps, worst_touchdown_mps(preset["per_run"]))
        objective, why = judge(cell["per_run"], touchdown_max_mps) if "per_run" in cell else (None, cell["error"])
        if (b, a) == (1.0, 1.0):
            entry.update(preset_objective=objective, preset_rejected=why)
        if objective is None:
            continue
        entry["admissible_cells"] += 1
        if entry["objective"] is None or objective < entry["objective"]:
            runs = cell["per_run"]
            entry.update(bandwidth_scale=b, authority_scale=a, objective=objective,
                         rms_error_m=statistics.median(r["rms_error_m"] for r in runs),
                         control_tv_per_s=statistics.median(r["control_tv_per_s"] for r in runs))
    order = variants()  # fc-sil's
    return {s: dict(sorted(by_variant.items(), key=lambda e: order.index(e[0]))) for s, by_variant in table.items()}


def fmt(objective):
    """rms x control_tv in mm N/s."""
    return "-" if objective is None else f"{objective * 1000.0:.4g}"


def write_markdown(path, table, numeric, command, grid):
    revision = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True,
                              text=True).stdout.strip() or "unknown"
    lines = ["# Altitude-law variants tuned by one procedure", "",
             f"Generated by `{command}` at {revision}, {datetime.date.today()}, backend {numeric}.",
             f"Grid: bandwidth_scale {list(grid[0])} x authority_scale {list(grid[1])} on each variant's "
             f"preset gains; seeds {TUNING_SEEDS[0]}..{TUNING_SEEDS[0] + TUNING_SEEDS[1] - 1}; objective: median "
             "over the seeds of rms_error_m x control_tv_per_s (mm N/s; rms and control_tv: the winner's "
             "medians); admissible: no NaN output, no divergence, thrust_saturated_s = 0"
             + "".join(f", {s} touchdown <= {v} m/s" for s, v in TOUCHDOWN_MAX_MPS.items())
             + " (or the preset's worst, where it lands faster), on every seed. "
             "No admissible cell: the preset stays (winner `-`)."]
    for scenario, by_variant in table.items():
        lines += ["", f"## {scenario}", "",
                  "| variant | bandwidth | authority | objective | rms [mm] | control_tv [N/s] | preset objective "
                  "| admissible/run cells |",
                  "|---|---|---|---|---|---|---|---|"]
        for variant, e in by_variant.items():
            preset = fmt(e["preset_objective"]) if e["preset_rejected"] is None else e["preset_rejected"]
            won = e["objective"] is not None
            knobs = (e["bandwidth_scale"], e["authority_scale"]) if won else ("-", "-")
            medians = (f"{e['rms_error_m'] * 1000.0:.4g}", f"{e['control_tv_per_s']:.4g}") if won else ("-", "-")
            lines.append(f"| {variant} | {knobs[0]} | {knobs[1]} | {fmt(e['objective'])} | {medians[0]} | "
                         f"{medians[1]} | {preset} | "
                         f"{e['admissible_cells']}/{e['cells_run']} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--numeric", default="float", choices=("float", "fixed"))
    parser.add_argument("--scenario", nargs="+", default=list(SCENARIOS), choices=list(SCENARIOS))
    parser.add_argument("--coarse", action="store_true",
                        help="every other value of each grid (3 x 3), when time is short")
    parser.add_argument("--cached-only", action="store_true",
                        help="judge the cells already run (an interrupted tuning), run none")
    args = parser.parse_args()
    if not os.access(FC_SIL, os.X_OK):
        sys.exit(f"tune-variants: {FC_SIL} missing (cmake --preset host && cmake --build build/host -j2)")
    grid = (BANDWIDTH[::2], AUTHORITY[::2]) if args.coarse else (BANDWIDTH, AUTHORITY)
    table = winners(tune(args.scenario, args.numeric, args.cached_only, grid), args.scenario)
    os.makedirs(OUT_DIR, exist_ok=True)
    command = " ".join(["tools/tune-variants.py"] + sys.argv[1:])
    write_markdown(os.path.join(OUT_DIR, "tuning.md"), table, args.numeric, command, grid)
    tuned = {"numeric": args.numeric, "bandwidth_grid": grid[0], "authority_grid": grid[1],
             "seeds": list(range(TUNING_SEEDS[0], sum(TUNING_SEEDS))), "scenarios": table}
    with open(os.path.join(OUT_DIR, "tuned.json"), "w") as f:
        json.dump(tuned, f, indent=1)
        f.write("\n")
    print(f"tune-variants: {OUT_DIR}/tuning.md, {OUT_DIR}/tuned.json")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Tunes every altitude-law variant by one procedure (issue 29's fair comparison).

For each scenario and variant, fc-sil flies the same 6 x 6 log grid of the two
knobs (controller.bandwidth_scale x controller.authority_scale, factors on the
variant's preset gains; sim_host/fsw_adapter.c's scale_law_gains says which
gains) over the same TUNING_SEEDS. Objective: the median over the seeds of
rms_error_m x control_tv_per_s. A cell is admissible only if
  - on every seed: no NaN output, no divergence, no thrust saturation after the
    transient (thrust_saturated_s = 0) and, in a landing, a touchdown no faster
    than TOUCHDOWN_MAX_MPS (issue 29's p99 bounds; the preset gets no
    allowance: a variant that lands harder everywhere keeps its presets);
  - every neighbouring cell (one grid step along either knob) that flew passes
    these tests too: a margin against their boundary, which the comparison's 100
    other seeds would otherwise find (tuned on three seeds, robustness ssc
    diverged in 14 of them; on ten, hexa-deck ssc-adaptive's best cell touched
    down within 0.10 m/s on every seed, and faster on 15 of the 100);
    --no-margin drops this test.
The admissible cell of least objective then flies CONFIRM_SEEDS (40 more
seeds, neither the tuning's nor the comparison's) and wins if it passes the
same tests there; if it fails, that counts as the cell's own failure (its
neighbours lose the margin) and the next admissible cell is tried.
A knob at its grid's end is marked (the optimum may lie beyond); with none
confirmed, the preset (1, 1) stays and the table says so.

Writes sim_host/results/tuning.md (winner and preset per scenario and variant,
the rejected cells by reason) and sim_host/results/tuned.json (the winning
knobs, which tools/compare-variants.sh flies).

  tools/tune-variants.py [--numeric float|fixed] [--scenario NAME ...] [--variant NAME ...]
                         [--coarse] [--no-margin] [--cached-only]

The seeds (TUNING_SEEDS) are not the comparison's (1..RUNS). fc-sil runs under
nice -n 19, at most JOBS at a time; each cell's JSON is kept in
build/results/tuning-runs/ (one directory per fc-sil build and seed set) and
not run again: an interrupted tuning goes on where it stopped.
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

# log grids, the same for every variant: bandwidth in steps of sqrt(2), authority in
# steps of 2; both hold the preset 1
BANDWIDTH = (0.707, 1.0, 1.41, 2.0, 2.83, 4.0)
AUTHORITY = (0.125, 0.25, 0.5, 1.0, 2.0, 4.0)
PRESET = (1.0, 1.0)
TUNING_SEEDS = (1001, 10)  # first seed, count
# the winner's confirmation: more seeds, neither the tuning's nor the comparison's
CONFIRM_SEEDS = (2001, 40)
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


def cell_path(cache_dir, cell, seeds=TUNING_SEEDS):
    """The cached JSON of cell (scenario, variant, bandwidth, authority) on seeds."""
    tag = "" if seeds == TUNING_SEEDS else "-seeds{}x{}".format(*seeds)
    return os.path.join(cache_dir, "{}-{}-{}-{}".format(*cell) + tag + ".json")


def run_cell(scenario, variant, bandwidth, authority, numeric, cache_dir, seeds=TUNING_SEEDS):
    """fc-sil's JSON for one grid cell ({"per_run": [...]}) on seeds, or {"error": why it did not run}."""
    path = cell_path(cache_dir, (scenario, variant, bandwidth, authority), seeds)
    if not os.path.exists(path):
        sets = SCENARIOS[scenario] + [f"controller.bandwidth_scale={bandwidth}",
                                      f"controller.authority_scale={authority}"]
        cmd = ["nice", "-n", "19", FC_SIL, "--scenario", scenario, "--controller", variant,
               "--numeric", numeric, "--runs", str(seeds[1]), "--seed", str(seeds[0]),
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


def touchdown_mps(run):
    """A run's touchdown speed; a landing that never touched down counts as too fast."""
    speed = run["touchdown_rel_speed_mps"]
    return float("inf") if speed is None else speed


def rejection(runs, touchdown_max_mps):
    """Why one cell is not admissible (the first failed test, on any seed), or None."""
    tests = (("NaN output", lambda r: r["nan_outputs"]),
             ("diverged", lambda r: r["diverged"]),
             ("thrust saturated", lambda r: r["thrust_saturated_s"] is None or r["thrust_saturated_s"] > 0.0),
             ("touchdown too fast", lambda r: touchdown_max_mps is not None
              and not touchdown_mps(r) <= touchdown_max_mps),
             ("no rms or control_tv", lambda r: r["rms_error_m"] is None or r["control_tv_per_s"] is None))
    for why, failed in tests:
        if any(failed(r) for r in runs):
            return why
    return None


def objective(runs):
    """The median over the seeds of rms_error_m x control_tv_per_s (None where a metric is missing)."""
    if any(r["rms_error_m"] is None or r["control_tv_per_s"] is None for r in runs):
        return None
    return statistics.median(r["rms_error_m"] * r["control_tv_per_s"] for r in runs)


def neighbours(knobs, grid):
    """The grid's cells one step from knobs along either knob."""
    i, j = grid[0].index(knobs[0]), grid[1].index(knobs[1])
    steps = ((i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1))
    return [(grid[0][m], grid[1][n]) for m, n in steps if 0 <= m < len(grid[0]) and 0 <= n < len(grid[1])]


def on_edge(knobs, grid):
    """knobs at the smallest or largest value of either grid."""
    return knobs[0] in (grid[0][0], grid[0][-1]) or knobs[1] in (grid[1][0], grid[1][-1])


def variants():
    out = subprocess.run([FC_SIL, "--list-controllers"], capture_output=True, text=True, check=True)
    return out.stdout.split()


def cache_dir_of(numeric):
    """The cache: one directory per fc-sil build and tuning seeds, so that a rebuilt fc-sil runs again."""
    stamp = os.stat(FC_SIL)
    path = os.path.join(CACHE_DIR, f"{numeric}-{int(stamp.st_mtime)}-{stamp.st_size}"
                        f"-seeds{TUNING_SEEDS[0]}x{TUNING_SEEDS[1]}")
    os.makedirs(path, exist_ok=True)
    return path


def tune(scenarios, variant_names, numeric, cached_only, grid):
    """{(scenario, variant, bandwidth, authority): fc-sil's JSON}, every cell of grid run (or
    cached; cached_only: only the cached cells)."""
    cache_dir = cache_dir_of(numeric)
    knobs = sorted(set((b, a) for b in grid[0] for a in grid[1]) | {PRESET})
    cells = [(s, v, b, a) for s in scenarios for v in variant_names for b, a in knobs]
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


def judge_variant(s, cells, grid, margin, confirm):
    """The entry of one scenario and variant: cells {(bandwidth, authority): fc-sil's JSON};
    confirm(knobs): the JSON on CONFIRM_SEEDS, or None where not run (--cached-only)."""
    touchdown_max_mps = TOUCHDOWN_MAX_MPS.get(s)
    in_grid = [k for k in cells if k[0] in grid[0] and k[1] in grid[1]]
    own = {k: rejection(c["per_run"], touchdown_max_mps) if "per_run" in c else c["error"]
           for k, c in cells.items()}
    preset = cells.get(PRESET)
    entry = {"bandwidth_scale": PRESET[0], "authority_scale": PRESET[1], "objective": None,
             "on_edge": False, "confirmed": None,
             "preset_objective": objective(preset["per_run"]) if preset and "per_run" in preset else None,
             "preset_rejected": own.get(PRESET, "not run"), "cells_run": len(in_grid)}
    while True:
        # a candidate passes every test, as do its neighbours that flew (a neighbour that
        # fc-sil could not initialise, its knobs out of the law's range, is no flight failure)
        why = {k: "a neighbour failed" if margin and own[k] is None
               and any(own.get(n) is not None and "per_run" in cells[n]
                       for n in neighbours(k, grid) if n in cells) else own[k]
               for k in in_grid}
        candidates = [k for k in in_grid if why[k] is None]
        entry.setdefault("admissible_cells", len(candidates))
        if not candidates:
            break
        # the best candidate must pass the tests on CONFIRM_SEEDS too; if it fails, that
        # counts as its own failure (its neighbours lose the margin) and the next best is tried
        best = min(candidates, key=lambda k: objective(cells[k]["per_run"]))
        check = confirm(best)
        failed = None if check is None else rejection(check["per_run"], touchdown_max_mps) \
            if "per_run" in check else check["error"]
        if failed is not None:
            own[best] = f"confirmation: {failed}"
            continue
        runs = cells[best]["per_run"]
        entry.update(bandwidth_scale=best[0], authority_scale=best[1], objective=objective(runs),
                     on_edge=on_edge(best, grid), confirmed=check is not None,
                     rms_error_m=statistics.median(r["rms_error_m"] for r in runs),
                     control_tv_per_s=statistics.median(r["control_tv_per_s"] for r in runs))
        if touchdown_max_mps is not None:
            entry["worst_touchdown_mps"] = max(touchdown_mps(r) for r in runs + (check or {}).get("per_run", []))
        break
    entry["rejected"] = {}
    for reason in why.values():
        if reason is not None:
            entry["rejected"][reason] = entry["rejected"].get(reason, 0) + 1
    return entry


def winners(results, scenarios, grid, numeric, cached_only, margin=True):
    """{scenario: {variant: entry}}: the winning knobs, their objective, the preset's, why cells lost
    (margin: a cell next to one that failed a test is not admissible)."""
    cache_dir = cache_dir_of(numeric)

    def confirm(s, v, knobs):
        cell = (s, v) + knobs
        if cached_only and not os.path.exists(cell_path(cache_dir, cell, CONFIRM_SEEDS)):
            return None
        return run_cell(*cell, numeric, cache_dir, CONFIRM_SEEDS)

    pairs = sorted({cell[:2] for cell in results})
    with concurrent.futures.ThreadPoolExecutor(JOBS) as pool:
        entries = pool.map(lambda sv: judge_variant(
            sv[0], {cell[2:]: c for cell, c in results.items() if cell[:2] == sv}, grid, margin,
            lambda knobs: confirm(*sv, knobs)), pairs)
        table = {}
        for (s, v), entry in zip(pairs, entries):
            table.setdefault(s, {})[v] = entry
    order = variants()  # fc-sil's
    return {s: dict(sorted(table.get(s, {}).items(), key=lambda e: order.index(e[0]))) for s in scenarios}


def fmt(objective):
    """rms x control_tv in mm N/s."""
    return "-" if objective is None else f"{objective * 1000.0:.4g}"


def write_markdown(path, table, numeric, command, grid, margin):
    revision = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True,
                              text=True).stdout.strip() or "unknown"
    seeds = f"{TUNING_SEEDS[0]}..{TUNING_SEEDS[0] + TUNING_SEEDS[1] - 1}"
    lines = ["# Altitude-law variants tuned by one procedure", "",
             f"Generated by `{command}` at {revision}, {datetime.date.today()}, backend {numeric}.", "",
             f"- Grid, the same for every variant: bandwidth_scale {list(grid[0])} x authority_scale "
             f"{list(grid[1])}, factors on the variant's preset gains (`scale_law_gains`, "
             "sim_host/fsw_adapter.c); each cell flown on the seeds " + seeds + ".",
             "- Objective: the median over the seeds of rms_error_m x control_tv_per_s (mm N/s; rms and "
             "control_tv below: the winner's medians).",
             "- Admissible: on every seed no NaN output, no divergence, thrust_saturated_s = 0"
             + "".join(f", {s} touchdown <= {v} m/s" for s, v in TOUCHDOWN_MAX_MPS.items())
             + " (issue 29's p99 bounds, on the worst seed)"
             + ("; and so must every neighbour (one grid step along either knob): a margin against the "
                "boundary of these tests, which the comparison's other seeds may cross."
                if margin else "; no margin to a neighbour that failed (--no-margin)."),
             "- Confirmation: the admissible cell of least objective flies the seeds "
             f"{CONFIRM_SEEDS[0]}..{sum(CONFIRM_SEEDS) - 1} and wins if it passes the same tests there; if it "
             "fails, that counts as its own failure (its neighbours lose the margin) and the next is tried "
             "(`unconfirmed`: judged with --cached-only, its confirmation not run). ↑, ↓: a knob at its "
             "grid's largest, smallest value (the optimum may lie beyond). None confirmed: the preset (1, 1) "
             "stays (winner `-`).",
             "- Rejected: cells per first failed test."]
    for scenario, by_variant in table.items():
        landing = scenario in TOUCHDOWN_MAX_MPS
        lines += ["", f"## {scenario}", "",
                  "| variant | bandwidth | authority | objective | rms [mm] | control_tv [N/s] "
                  + ("| worst touchdown [m/s] " if landing else "")
                  + "| preset objective | admissible/run cells | rejected |",
                  "|---|---|---|---|---|---|" + ("---|" if landing else "") + "---|---|---|"]
        for variant, e in by_variant.items():
            preset = fmt(e["preset_objective"]) if e["preset_rejected"] is None else e["preset_rejected"]
            won = e["objective"] is not None
            knobs = (e["bandwidth_scale"], e["authority_scale"]) if won else ("-", "-")
            medians = (f"{e['rms_error_m'] * 1000.0:.4g}", f"{e['control_tv_per_s']:.4g}") if won else ("-", "-")
            touchdown = (f"| {e['worst_touchdown_mps']:.3g} " if won else "| - ") if landing else ""
            rejected = ", ".join(f"{why} {n}" for why, n in sorted(e["rejected"].items())) or "-"
            knobs = [f"{k}" + ("↑" if k == g[-1] else "↓" if k == g[0] else "") if won else k
                     for k, g in zip(knobs, grid)]
            unconfirmed = " unconfirmed" if e["confirmed"] is False else ""
            lines.append(f"| {variant} | {knobs[0]} | {knobs[1]} "
                         f"| {fmt(e['objective'])}{unconfirmed} | {medians[0]} | {medians[1]} {touchdown}| {preset} "
                         f"| {e['admissible_cells']}/{e['cells_run']} | {rejected} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--numeric", default="float", choices=("float", "fixed"))
    parser.add_argument("--scenario", nargs="+", default=list(SCENARIOS), choices=list(SCENARIOS))
    parser.add_argument("--variant", nargs="+", help="these variants only (default: every one)")
    parser.add_argument("--coarse", action="store_true",
                        help="every other value of each grid (3 x 3), when time is short (the preset is flown too)")
    parser.add_argument("--no-margin", action="store_true",
                        help="admit a cell next to one that failed (the cell's own seeds' tests alone)")
    parser.add_argument("--cached-only", action="store_true",
                        help="judge the cells already run (an interrupted tuning), run none")
    args = parser.parse_args()
    if not os.access(FC_SIL, os.X_OK):
        sys.exit(f"tune-variants: {FC_SIL} missing (cmake --preset host && cmake --build build/host -j2)")
    grid = (BANDWIDTH[::2], AUTHORITY[::2]) if args.coarse else (BANDWIDTH, AUTHORITY)
    table = winners(tune(args.scenario, args.variant or variants(), args.numeric, args.cached_only, grid),
                    args.scenario, grid, args.numeric, args.cached_only, margin=not args.no_margin)
    os.makedirs(OUT_DIR, exist_ok=True)
    command = " ".join(["tools/tune-variants.py"] + sys.argv[1:])
    write_markdown(os.path.join(OUT_DIR, "tuning.md"), table, args.numeric, command, grid, not args.no_margin)
    tuned = {"numeric": args.numeric, "bandwidth_grid": grid[0], "authority_grid": grid[1],
             "neighbour_margin": not args.no_margin,
             "seeds": list(range(TUNING_SEEDS[0], sum(TUNING_SEEDS))),
             "confirmation_seeds": list(range(CONFIRM_SEEDS[0], sum(CONFIRM_SEEDS))), "scenarios": table}
    with open(os.path.join(OUT_DIR, "tuned.json"), "w") as f:
        json.dump(tuned, f, indent=1)
        f.write("\n")
    print(f"tune-variants: {OUT_DIR}/tuning.md, {OUT_DIR}/tuned.json")


if __name__ == "__main__":
    main()

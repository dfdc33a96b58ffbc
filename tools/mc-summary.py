#!/usr/bin/env python3
"""Summarise the landing goals of a Monte-Carlo JSON from fc-sil (issue 6).

    build/host/sim_host/fc-sil --scenario cf2-pad --runs 1000 --seed 1 --json mc.json
    tools/mc-summary.py mc.json --speed-max 0.10

Prints, per landing metric, the runs that have it, the median, the p99 (p1
for the clearance, where low is bad) and the worst value with its seed; then
the goals: runs with a touchdown at or under --speed-max, runs with a contact
before the planned touchdown (early_contact: the first contact, at the
plant's step, before the firmware's touchdown window opened; from files
without it, min_clearance_m < 0) and runs with a bounce.
The percentiles are nearest-rank, as fc-sil's own table.
"""
import argparse
import json
import math


def nearest_rank(sorted_values, fraction):
    rank = max(1, math.ceil(fraction * len(sorted_values)))
    return sorted_values[rank - 1]


def campaigns(paths):
    """Each campaign of the files: one, or (several backends or variants) a list under "results"."""
    for path in paths:
        with open(path) as f:
            d = json.load(f)
        yield from d.get("results", [d])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("json_files", nargs="+")
    ap.add_argument("--speed-max", type=float, default=None,
                    help="the touchdown relative speed goal, m/s")
    args = ap.parse_args()
    metrics = [("touchdown_rel_speed_mps", "high"), ("touchdown_time_s", "high"),
               ("min_clearance_m", "low"), ("bounces", "high"), ("max_tilt_deg", "high"),
               ("touchdown_rel_tilt_deg", "high")]
    for d in campaigns(args.json_files):
        runs = d["per_run"]
        print(f"## {d['scenario']} ({d['backend']}, {d['variant']}): {len(runs)} runs from seed {d['seed']}")
        print("| metric | runs with it | median | p99 (p1 for clearance) | worst (seed) |")
        print("|---|---|---|---|---|")
        for name, bad in metrics:
            pairs = [(r[name], r["seed"]) for r in runs if r.get(name) is not None]
            if not pairs:
                continue
            values = sorted(v for v, _ in pairs)
            worst = min(pairs) if bad == "low" else max(pairs)
            tail = nearest_rank(values, 0.01) if bad == "low" else nearest_rank(values, 0.99)
            median = nearest_rank(values, 0.5)
            print(f"| {name} | {len(pairs)} | {median:.4g} | {tail:.4g} | {worst[0]:.4g} ({worst[1]}) |")
        speeds = [r["touchdown_rel_speed_mps"] for r in runs if r.get("touchdown_rel_speed_mps") is not None]
        no_touchdown = [r["seed"] for r in runs if r.get("touchdown_rel_speed_mps") is None]
        if any("early_contact" in r for r in runs):
            early = [r["seed"] for r in runs if (r.get("early_contact") or 0) > 0]
        else:
            early = [r["seed"] for r in runs if r.get("min_clearance_m") is not None and r["min_clearance_m"] < 0]
        bounced = [r["seed"] for r in runs if (r.get("bounces") or 0) > 0]
        diverged = [r["seed"] for r in runs if r.get("diverged")]
        if args.speed_max is not None:
            within = sum(1 for v in speeds if v <= args.speed_max)
            print(f"touchdown speed <= {args.speed_max} m/s: {within} of {len(runs)} runs "
                  f"({100.0 * within / len(runs):.1f} %)")
        print(f"no touchdown: {len(no_touchdown)} {no_touchdown[:20]}")
        print(f"contact before the planned touchdown: {len(early)} {early[:20]}")
        print(f"bounces: {len(bounced)} runs {bounced[:20]}")
        print(f"diverged: {len(diverged)} {diverged[:20]}")
        print()


if __name__ == "__main__":
    main()

/*
 * output.h - what a set of runs leaves behind: JSON metrics (libcjson), CSV
 * traces, and PNG figures drawn by gnuplot from data files in the plot dir.
 */
#ifndef SIM_OUTPUT_H
#define SIM_OUTPUT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "robustness.h"
#include "scenario.h"
#include "sim.h"

/* Statistics of one metric over Monte-Carlo runs (NaN when no run had it). */
typedef struct metric_stats {
    double min, median, p90, p95, p99, max; /* percentiles by nearest rank */
    uint64_t worst_seed;
    int count;                 /* runs where the metric applied */
} metric_stats;

/* One line of results: a variant in a backend, one run or a Monte-Carlo set. */
typedef struct run_record {
    const scenario *sc;
    int variant;
    const char *backend;
    int runs;                  /* 1: a single run (result, trace); > 1: Monte-Carlo */
    uint64_t seed;
    sim_result result;         /* single run (Monte-Carlo: the nominal fields of the first run) */
    sim_trace trace;           /* single run, when kept */
    sim_metrics *per_run;      /* Monte-Carlo: runs entries */
    uint64_t *per_run_seed;
    metric_stats stats[SIM_METRIC_COUNT];
    /* robustness (robustness.h), over the runs */
    int diverged_runs;         /* runs with any divergence reason */
    int diverged_by_reason[SIM_DIVERGED_REASON_COUNT];
    int nan_output_runs;       /* runs with nan_outputs > 0 */
    double nan_outputs_total;  /* steps with a NaN output, all runs */
    /* the failsafe, over the runs */
    int failsafe_entered_runs;    /* runs whose firmware entered FAILSAFE */
    int airborne_motor_stop_runs; /* runs with failsafe_motor_stops_airborne > 0 */
    double wall_s;             /* all of its runs */
    bool failed;               /* the flight software did not start (--compare goes on) */
    char error[256];
} run_record;

void output_compute_stats(run_record *r);

/* Writes the JSON file: one record flat, several as {"scenario", "results": [...]}. */
bool output_json(const char *path, const run_record *records, int count, char *err, size_t err_len);

/* Writes the trace of one record as CSV. */
bool output_csv(const char *path, const run_record *r, char *err, size_t err_len);

/* The CSV path of a record when several are written: FILE with "-variant-backend" before the extension. */
void output_csv_path(const char *base, const run_record *r, int count, char *out, size_t out_len);

/* Data files, a gnuplot script and the PNGs in dir: a summary figure per run
 * with a trace, and the dissertation's Figures 4.2 and 4.3 when the records
 * hold ssc and ssc-adaptive in the same backend. Returns false on an I/O
 * error; a missing gnuplot is reported on stderr and is not an error. */
bool output_plots(const char *dir, const run_record *records, int count, bool quiet, char *err, size_t err_len);

/* Prints the per-run metrics (or Monte-Carlo statistics) as a table on stdout. */
void output_print(const run_record *records, int count, bool compare);

#endif /* SIM_OUTPUT_H */

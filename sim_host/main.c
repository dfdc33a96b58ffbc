/*
 * fc-sil - the software-in-the-loop simulator: a multirotor plant flown by
 * the firmware library through fc_controller_init / fc_controller_step, in
 * either numeric backend, over the scenarios of sim_host/scenarios.
 *
 *   fc-sil --scenario seed-4.4 --controller ssc,ssc-adaptive --numeric float \
 *          --json out.json --csv trace.csv --plot figs/
 *
 * Exit status: 0 done, 1 a run or an output failed, 2 bad usage or a bad
 * scenario file (nothing is run and nothing is written).
 */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fsw_adapter.h"
#include "output.h"
#include "scenario.h"
#include "sim.h"

#define MAX_RECORDS 64

static void usage(FILE *f)
{
    fprintf(f,
            "usage: fc-sil [options]\n"
            "  --scenario NAME|FILE   a scenario of sim_host/scenarios (NAME) or an INI file (default seed-4.4)\n"
            "  --set SECTION.KEY=VALUE  replaces a key of the scenario file (repeatable, up to 32)\n"
            "  --numeric float|fixed|both|pil  the firmware's numeric backend (a comma list too; default float);\n"
            "                         pil: the fixed step run by the ATmega image --pil-image in simavr\n"
            "  --pil-image FILE       the ATmega PIL image (build/atmega-fixed/platform/atmega/fc-atmega-pil.elf)\n"
            "  --controller NAME[,NAME...]  altitude-law variant(s) (default: the scenario's); 'all' for every one\n"
            "  --json FILE            metrics as JSON (SPEC.md's names, with scenario, variant, backend)\n"
            "  --csv FILE             the run's trace as CSV (several runs: FILE-variant-backend.csv)\n"
            "  --plot DIR             data files, plots.gp and PNG figures (gnuplot) in DIR\n"
            "  --descent-shaping on|off  the landing descent with or without (2.25)-(2.28)\n"
            "                         (the same as --set landing.descent_shaping=on|off)\n"
            "  --duration S           fly S seconds instead of the scenario's duration_s\n"
            "  --runs N --seed S      Monte-Carlo: N runs perturbed per [montecarlo], seeds S..S+N-1;\n"
            "                         per-metric min/median/p95/max and the worst seed\n"
            "  --compare              the comparison table: every variant (or the --controller list) x metrics;\n"
            "                         with --runs also rms, control_tv, theta_err as median and p95\n"
            "  --benchmark            time the runs (best of --runs, default 5) and print the real-time factor\n"
            "  --list-controllers     the variant names, one a line\n"
            "  --list-scenarios       the shipped scenarios, one a line\n"
            "  --quiet                no progress bar, no table\n"
            "  --help\n");
}

/* ---------------------------------------------------------------------- */
/* progress bar (stderr, only on a terminal)                                */
/* ---------------------------------------------------------------------- */

typedef struct progress {
    bool enabled;
    int done, total;           /* runs */
    const char *label;
    char label_text[64];       /* the label of the records being filled */
    double last_draw;
} progress;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void progress_draw(double fraction, void *user)
{
    progress *p = user;
    const double t = now_s();
    if (fraction < 1.0 && t - p->last_draw < 0.05) {
        return;
    }
    p->last_draw = t;
    const double overall = (p->done + fraction) / p->total;
    const int width = 30, filled = (int)(overall * width + 0.5);
    fprintf(stderr, "\r[");
    for (int i = 0; i < width; i++) {
        fputc(i < filled ? '#' : '.', stderr);
    }
    fprintf(stderr, "] %3d%%  run %d/%d  %-32s", (int)(overall * 100.0 + 0.5), p->done + 1 > p->total ? p->total : p->done + 1,
            p->total, p->label);
    fflush(stderr);
}

static void progress_end(progress *p)
{
    if (p->enabled) {
        fprintf(stderr, "\r%*s\r", 80, "");
        fflush(stderr);
    }
}

/* ---------------------------------------------------------------------- */
/* arguments                                                               */
/* ---------------------------------------------------------------------- */

typedef struct args {
    const char *scenario, *numeric, *controller, *json, *csv, *plot;
    const char *pil_image;   /* --pil-image */
    const char *overrides[SCENARIO_OVERRIDES_MAX]; /* --set, in order */
    int override_count;
    double duration_s;       /* 0: the scenario's */
    long runs;
    bool runs_given;
    unsigned long long seed;
    bool seed_given;
    bool compare, benchmark, quiet;
} args;

static bool parse_long(const char *s, long lo, long hi, long *out)
{
    char *end;
    const long v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi) {
        return false;
    }
    *out = v;
    return true;
}

/* Splits a comma list into the backends it names. */
static int parse_backends(const char *text, const fsw_backend *out[2])
{
    int n = 0;
    char buf[128];
    snprintf(buf, sizeof buf, "%s", text);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
        const fsw_backend *b = NULL;
        if (strcmp(tok, "both") == 0) {
            out[0] = &fsw_float_backend;
            out[1] = &fsw_fixed_backend;
            return 2;
        }
        if (strcmp(tok, "float") == 0) {
            b = &fsw_float_backend;
        } else if (strcmp(tok, "fixed") == 0) {
            b = &fsw_fixed_backend;
#if FSW_HAVE_PIL
        } else if (strcmp(tok, "pil") == 0) {
            b = &fsw_pil_backend;
#endif
        } else {
            return -1;
        }
        if (n < 2 && (n == 0 || out[0] != b)) {
            out[n++] = b;
        }
    }
    return n;
}

static int parse_variants(const char *text, int out[FSW_VARIANT_COUNT], char *bad, size_t bad_len)
{
    if (strcmp(text, "all") == 0) {
        for (int i = 0; i < FSW_VARIANT_COUNT; i++) {
            out[i] = i;
        }
        return FSW_VARIANT_COUNT;
    }
    int n = 0;
    char buf[512];
    snprintf(buf, sizeof buf, "%s", text);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
        const int v = sim_variant_from_name(tok);
        if (v < 0) {
            snprintf(bad, bad_len, "%s", tok);
            return -1;
        }
        bool dup = false;
        for (int i = 0; i < n; i++) {
            dup = dup || out[i] == v;
        }
        if (!dup && n < FSW_VARIANT_COUNT) {
            out[n++] = v;
        }
    }
    return n;
}

static void emit_name(const char *name, void *user)
{
    (void)user;
    printf("%s\n", name);
}

/* ---------------------------------------------------------------------- */
/* runs                                                                    */
/* ---------------------------------------------------------------------- */

static bool run_record_fill(run_record *rec, const scenario *sc, int variant, const fsw_backend *be, long runs,
                            bool mc, uint64_t seed, bool want_trace, progress *prog, char *err, size_t err_len)
{
    memset(rec, 0, sizeof *rec);
    rec->sc = sc;
    rec->variant = variant;
    rec->backend = be->name;
    rec->runs = (int)runs;
    rec->seed = seed;
    sim_options opt;
    memset(&opt, 0, sizeof opt);
    opt.backend = be;
    opt.variant = variant;
    opt.trace_decimation = 1;
    opt.progress = prog->enabled ? progress_draw : NULL;
    opt.progress_user = prog;
    snprintf(prog->label_text, sizeof prog->label_text, "%s %s", sim_variant_names[variant], be->name);
    prog->label = prog->label_text;
    const double t0 = now_s();
    if (!mc || runs == 1) {
        scenario one = *sc;
        one.seed = seed;
        if (mc) {
            scenario_perturb(&one, seed); /* one Monte-Carlo seed, with its trace */
        }
        opt.want_trace = want_trace;
        const bool ok = sim_run(&one, &opt, &rec->result, want_trace ? &rec->trace : NULL, err, err_len);
        prog->done++;
        rec->wall_s = now_s() - t0;
        if (ok) {
            output_compute_stats(rec);
        }
        prog->label = "";
        return ok;
    }
    rec->per_run = calloc((size_t)runs, sizeof *rec->per_run);
    rec->per_run_seed = calloc((size_t)runs, sizeof *rec->per_run_seed);
    if (rec->per_run == NULL || rec->per_run_seed == NULL) {
        snprintf(err, err_len, "out of memory");
        return false;
    }
    for (long i = 0; i < runs; i++) {
        scenario one = *sc;
        const uint64_t s = seed + (uint64_t)i;
        scenario_perturb(&one, s);
        sim_result res;
        if (!sim_run(&one, &opt, &res, NULL, err, err_len)) {
            return false;
        }
        if (i == 0) {
            rec->result = res;
        }
        rec->per_run[i] = res.metrics;
        rec->per_run_seed[i] = s;
        prog->done++;
    }
    rec->wall_s = now_s() - t0;
    prog->label = "";
    output_compute_stats(rec);
    return true;
}

static void run_record_free(run_record *r)
{
    sim_trace_free(&r->trace);
    free(r->per_run);
    free(r->per_run_seed);
}

static int benchmark(const scenario *sc, const int *variants, int nv, const fsw_backend *const *backends, int nb,
                     long repeats)
{
    printf("benchmark: scenario %s, %.0f s of flight, controller %.0f Hz, plant %.0f Hz, best of %ld\n", sc->name,
           sc->duration_s, sc->controller_rate_hz, sc->plant_rate_hz, repeats);
    printf("%-18s %-6s %10s %10s %14s %14s %14s\n", "controller", "numeric", "wall [s]", "cpu [s]",
           "real-time x", "us/ctrl step", "ns/plant step");
    for (int b = 0; b < nb; b++) {
        for (int v = 0; v < nv; v++) {
            sim_options opt;
            memset(&opt, 0, sizeof opt);
            opt.backend = backends[b];
            opt.variant = variants[v];
            double best_wall = (double)INFINITY, best_cpu = (double)INFINITY;
            sim_result res;
            memset(&res, 0, sizeof res); /* read after the loop even if it ran zero times */
            for (long r = 0; r < repeats; r++) {
                char err[256];
                if (!sim_run(sc, &opt, &res, NULL, err, sizeof err)) {
                    fprintf(stderr, "fc-sil: %s\n", err);
                    return 1;
                }
                best_wall = res.wall_s < best_wall ? res.wall_s : best_wall;
                best_cpu = res.cpu_s < best_cpu ? res.cpu_s : best_cpu;
            }
            /* the real-time factor on the CPU time: what one core does when it is not shared */
            printf("%-18s %-6s %10.4f %10.4f %14.1f %14.2f %14.1f\n", sim_variant_names[variants[v]],
                   backends[b]->name, best_wall, best_cpu, sc->duration_s / best_cpu,
                   1e6 * best_cpu / (double)res.controller_steps, 1e9 * best_cpu / (double)res.plant_steps);
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    args a;
    memset(&a, 0, sizeof a);
    a.scenario = "seed-4.4";
    a.numeric = "float";
    a.runs = 1;
    enum {
        OPT_LIST_CONTROLLERS = 256,
        OPT_LIST_SCENARIOS,
        OPT_COMPARE,
        OPT_BENCHMARK,
        OPT_QUIET,
        OPT_PIL_IMAGE,
        OPT_SET,
        OPT_DESCENT_SHAPING
    };
    static const struct option options[] = {
        {"scenario", required_argument, NULL, 's'},
        {"numeric", required_argument, NULL, 'n'},
        {"controller", required_argument, NULL, 'c'},
        {"json", required_argument, NULL, 'j'},
        {"csv", required_argument, NULL, 'v'},
        {"plot", required_argument, NULL, 'p'},
        {"runs", required_argument, NULL, 'r'},
        {"duration", required_argument, NULL, 'd'},
        {"seed", required_argument, NULL, 'S'},
        {"compare", no_argument, NULL, OPT_COMPARE},
        {"benchmark", no_argument, NULL, OPT_BENCHMARK},
        {"list-controllers", no_argument, NULL, OPT_LIST_CONTROLLERS},
        {"list-scenarios", no_argument, NULL, OPT_LIST_SCENARIOS},
        {"quiet", no_argument, NULL, OPT_QUIET},
        {"pil-image", required_argument, NULL, OPT_PIL_IMAGE},
        {"set", required_argument, NULL, OPT_SET},
        {"descent-shaping", required_argument, NULL, OPT_DESCENT_SHAPING},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    int c;
    long value;
    while ((c = getopt_long(argc, argv, "h", options, NULL)) != -1) {
        switch (c) {
        case 's': a.scenario = optarg; break;
        case 'n': a.numeric = optarg; break;
        case 'c': a.controller = optarg; break;
        case 'j': a.json = optarg; break;
        case 'v': a.csv = optarg; break;
        case 'p': a.plot = optarg; break;
        case 'r':
            if (!parse_long(optarg, 1, 1000000, &value)) {
                fprintf(stderr, "fc-sil: --runs needs a count from 1\n");
                return 2;
            }
            a.runs = value;
            a.runs_given = true;
            break;
        case 'd': {
            char *end;
            a.duration_s = strtod(optarg, &end);
            if (end == optarg || *end != '\0' || !(a.duration_s > 0.0) || a.duration_s > 36000.0) {
                fprintf(stderr, "fc-sil: --duration needs seconds in (0, 36000]\n");
                return 2;
            }
            break;
        }
        case 'S': {
            char *end;
            a.seed = strtoull(optarg, &end, 10);
            if (end == optarg || *end != '\0') {
                fprintf(stderr, "fc-sil: --seed needs a non-negative integer\n");
                return 2;
            }
            a.seed_given = true;
            break;
        }
        case OPT_COMPARE: a.compare = true; break;
        case OPT_BENCHMARK: a.benchmark = true; break;
        case OPT_QUIET: a.quiet = true; break;
        case OPT_PIL_IMAGE: a.pil_image = optarg; break;
        case OPT_SET:
            if (a.override_count == SCENARIO_OVERRIDES_MAX) {
                fprintf(stderr, "fc-sil: at most %d --set\n", SCENARIO_OVERRIDES_MAX);
                return 2;
            }
            a.overrides[a.override_count++] = optarg;
            break;
        case OPT_DESCENT_SHAPING:
            if (strcmp(optarg, "on") != 0 && strcmp(optarg, "off") != 0) {
                fprintf(stderr, "fc-sil: --descent-shaping needs on or off\n");
                return 2;
            }
            if (a.override_count == SCENARIO_OVERRIDES_MAX) {
                fprintf(stderr, "fc-sil: at most %d --set\n", SCENARIO_OVERRIDES_MAX);
                return 2;
            }
            a.overrides[a.override_count++] =
                strcmp(optarg, "on") == 0 ? "landing.descent_shaping=on" : "landing.descent_shaping=off";
            break;
        case OPT_LIST_CONTROLLERS:
            for (int i = 0; i < FSW_VARIANT_COUNT; i++) {
                printf("%s\n", sim_variant_names[i]);
            }
            return 0;
        case OPT_LIST_SCENARIOS:
            scenario_list(argv[0], emit_name, NULL);
            return 0;
        case 'h': usage(stdout); return 0;
        default: usage(stderr); return 2;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "fc-sil: unexpected argument '%s'\n", argv[optind]);
        usage(stderr);
        return 2;
    }

    const fsw_backend *backends[2];
    const int nb = parse_backends(a.numeric, backends);
    if (nb <= 0) {
        fprintf(stderr, "fc-sil: --numeric must be float, fixed, both%s, not '%s'\n",
                FSW_HAVE_PIL ? " or pil" : " (pil: this fc-sil was built without libsimavr)", a.numeric);
        return 2;
    }

    char path[SCENARIO_PATH_MAX];
    if (!scenario_resolve(a.scenario, argv[0], path, sizeof path)) {
        fprintf(stderr, "fc-sil: scenario '%s' not found (fc-sil --list-scenarios lists them)\n", a.scenario);
        return 2;
    }
    static scenario sc;
    char err[1024];
    if (!scenario_load(path, a.overrides, a.override_count, &sc, err, sizeof err)) {
        fprintf(stderr, "fc-sil: %s\n", err);
        return 2;
    }

    if (a.duration_s > 0.0) {
        sc.duration_s = a.duration_s;
    }
    sc.fsw.target_image = a.pil_image;
    int variants[FSW_VARIANT_COUNT];
    int nv;
    if (a.controller != NULL) {
        char bad[128];
        nv = parse_variants(a.controller, variants, bad, sizeof bad);
        if (nv <= 0) {
            fprintf(stderr, "fc-sil: unknown controller '%s' (fc-sil --list-controllers lists them)\n",
                    nv < 0 ? bad : a.controller);
            return 2;
        }
    } else if (a.compare) {
        nv = parse_variants("all", variants, err, sizeof err);
    } else {
        variants[0] = sc.fsw.variant;
        nv = 1;
    }

    if (a.benchmark) {
        return benchmark(&sc, variants, nv, backends, nb, a.runs_given ? a.runs : 5);
    }

    /* figure = accel-feedback: every run flown again with k_a = 0, as the
     * scenario "NAME-without" (unless the gain is 0 already) */
    const scenario *flown[2] = {&sc, NULL};
    int ns = 1;
    static scenario without;
    if (sc.figure == FIGURE_ACCEL_FEEDBACK && !(sc.fsw.accel_fb_gain_per_s == 0.0)) {
        without = sc;
        without.fsw.accel_fb_gain_per_s = 0.0;
        snprintf(without.name, sizeof without.name, "%.*s-without", (int)sizeof without.name - 9, sc.name);
        flown[ns++] = &without;
    }
    const bool mc = a.runs_given;
    const uint64_t seed = a.seed_given ? (uint64_t)a.seed : sc.seed;
    const int count = nv * nb * ns;
    if (count > MAX_RECORDS) {
        fprintf(stderr, "fc-sil: too many runs at once\n");
        return 2;
    }
    if (mc && a.runs > 1 && a.csv != NULL) {
        fprintf(stderr, "fc-sil: --csv writes a single run's trace; Monte-Carlo (--runs) keeps none\n");
        return 2;
    }
    static run_record records[MAX_RECORDS];
    progress prog = {.enabled = isatty(2) != 0 && !a.quiet,
                     .done = 0,
                     .total = (int)(count * (mc ? a.runs : 1)),
                     .label = "",
                     .label_text = "",
                     .last_draw = 0.0};
    const bool want_trace = (!mc || a.runs == 1) && (a.csv != NULL || a.plot != NULL);
    int filled = 0;
    int status = 0;
    for (int b = 0; b < nb && status == 0; b++) {
        for (int k = 0; k < nv * ns && status == 0; k++) {
            const int v = k / ns;
            const scenario *one = flown[k % ns];
            if (!run_record_fill(&records[filled], one, variants[v], backends[b], mc ? a.runs : 1, mc, seed,
                                 want_trace, &prog, err, sizeof err)) {
                if (a.compare) {
                    /* the table shows which variant could not start, and goes on */
                    records[filled].failed = true;
                    snprintf(records[filled].error, sizeof records[filled].error, "%.200s", err);
                    prog.done = (filled + 1) * (int)(mc ? a.runs : 1);
                    filled++;
                    continue;
                }
                progress_end(&prog);
                fprintf(stderr, "fc-sil: %s, %s, %s: %s\n", one->name, sim_variant_names[variants[v]],
                        backends[b]->name, err);
                status = 1;
            }
            filled++;
        }
    }
    progress_end(&prog);
    if (status == 0) {
        if (!a.quiet) {
            output_print(records, count, a.compare);
        }
        if (a.plot != NULL && !output_plots(a.plot, records, count, a.quiet, err, sizeof err)) {
            fprintf(stderr, "fc-sil: %s\n", err);
            status = 1;
        }
        for (int i = 0; i < count && status == 0 && a.csv != NULL; i++) {
            if (records[i].failed) {
                continue;
            }
            char csv[1200];
            output_csv_path(a.csv, &records[i], count, csv, sizeof csv);
            if (!output_csv(csv, &records[i], err, sizeof err)) {
                fprintf(stderr, "fc-sil: %s\n", err);
                status = 1;
            }
        }
        if (status == 0 && a.json != NULL && !output_json(a.json, records, count, err, sizeof err)) {
            fprintf(stderr, "fc-sil: %s\n", err);
            status = 1;
        }
    }
    for (int i = 0; i < filled; i++) {
        run_record_free(&records[i]);
    }
    return status;
}

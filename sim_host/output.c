/* output.c - JSON, CSV, figures and the printed tables (output.h). */
#include "output.h"

#include <cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

/* ---------------------------------------------------------------------- */
/* statistics                                                              */
/* ---------------------------------------------------------------------- */

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Lower is worse for the clearance and for having entered the failsafe;
 * higher is worse for every other metric. */
static bool lower_is_worse(int metric)
{
    return strcmp(sim_metric_names[metric], "min_clearance_m") == 0 ||
           strcmp(sim_metric_names[metric], "failsafe_entered") == 0;
}

/* A yes/no metric: a boolean in the JSON. */
static bool metric_is_flag(int metric)
{
    return strcmp(sim_metric_names[metric], "failsafe_entered") == 0;
}

/* The value at percentile p of n sorted values, nearest rank. */
static double nearest_rank(const double *sorted, int n, double p)
{
    int rank = (int)ceil(p * n);
    rank = rank < 1 ? 1 : (rank > n ? n : rank);
    return sorted[rank - 1];
}

static const sim_metrics *run_metrics(const run_record *r, int i)
{
    return r->runs > 1 ? &r->per_run[i] : &r->result.metrics;
}

void output_compute_stats(run_record *r)
{
    r->diverged_runs = r->nan_output_runs = r->failsafe_entered_runs = r->airborne_motor_stop_runs = 0;
    r->nan_outputs_total = 0.0;
    memset(r->diverged_by_reason, 0, sizeof r->diverged_by_reason);
    for (int i = 0; i < r->runs; i++) {
        const sim_metrics *m = run_metrics(r, i);
        const unsigned reasons = sim_divergence(m, &r->sc->montecarlo);
        r->diverged_runs += reasons != 0u;
        for (int b = 0; b < SIM_DIVERGED_REASON_COUNT; b++) {
            r->diverged_by_reason[b] += (reasons & (1u << b)) != 0u;
        }
        r->nan_output_runs += m->nan_outputs > 0.0;
        r->nan_outputs_total += m->nan_outputs;
        r->failsafe_entered_runs += m->failsafe_entered > 0.0;
        r->airborne_motor_stop_runs += m->failsafe_motor_stops_airborne > 0.0;
    }
    double *values = malloc((size_t)r->runs * sizeof *values);
    for (int k = 0; k < SIM_METRIC_COUNT; k++) {
        metric_stats *s = &r->stats[k];
        s->min = s->median = s->p90 = s->p95 = s->p99 = s->max = (double)NAN;
        s->worst_seed = r->seed;
        s->count = 0;
        double worst = (double)NAN;
        for (int i = 0; i < r->runs; i++) {
            const double v = r->runs > 1 ? sim_metric_value(&r->per_run[i], k) : sim_metric_value(&r->result.metrics, k);
            if (!isfinite(v)) {
                continue;
            }
            values[s->count++] = v;
            const bool is_worse = isnan(worst) || (lower_is_worse(k) ? v < worst : v > worst);
            if (is_worse) {
                worst = v;
                s->worst_seed = r->runs > 1 ? r->per_run_seed[i] : r->seed;
            }
        }
        if (s->count == 0) {
            continue;
        }
        qsort(values, (size_t)s->count, sizeof *values, compare_double);
        s->min = values[0];
        s->max = values[s->count - 1];
        s->median = s->count % 2 == 1 ? values[s->count / 2]
                                      : 0.5 * (values[s->count / 2 - 1] + values[s->count / 2]);
        s->p90 = nearest_rank(values, s->count, 0.90);
        s->p95 = nearest_rank(values, s->count, 0.95);
        s->p99 = nearest_rank(values, s->count, 0.99);
    }
    free(values);
}

/* ---------------------------------------------------------------------- */
/* JSON                                                                    */
/* ---------------------------------------------------------------------- */

static void add_number(cJSON *obj, const char *name, double v)
{
    if (isfinite(v)) {
        cJSON_AddNumberToObject(obj, name, v);
    } else {
        cJSON_AddNullToObject(obj, name);
    }
}

static void add_metrics(cJSON *obj, const sim_metrics *m)
{
    for (int k = 0; k < SIM_METRIC_COUNT; k++) {
        const double v = sim_metric_value(m, k);
        if (metric_is_flag(k) && isfinite(v)) {
            cJSON_AddBoolToObject(obj, sim_metric_names[k], v > 0.0);
        } else {
            add_number(obj, sim_metric_names[k], v);
        }
    }
}

/* The landing mission's course: final state, aborts, the planned touchdown, every transition. */
static void add_landing(cJSON *o, const sim_result *res)
{
    cJSON *l = cJSON_AddObjectToObject(o, "landing");
    cJSON_AddStringToObject(l, "final_state", sim_landing_state_names[res->final_landing_state]);
    cJSON_AddNumberToObject(l, "aborts", res->aborts);
    add_number(l, "touchdown_planned_s", res->touchdown_planned_s);
    cJSON_AddStringToObject(l, "descent_blocked_by", sim_landing_reason_names[res->descent_blocked_by]);
    cJSON *events = cJSON_AddArrayToObject(l, "events");
    for (int i = 0; i < res->event_count; i++) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "t_s", res->events[i].t_s);
        cJSON_AddStringToObject(e, "state", sim_landing_state_names[res->events[i].state]);
        cJSON_AddStringToObject(e, "reason", sim_landing_reason_names[res->events[i].reason]);
        cJSON_AddItemToArray(events, e);
    }
}

static void add_divergence(cJSON *obj, const sim_metrics *m, const montecarlo_params *mc)
{
    const unsigned reasons = sim_divergence(m, mc);
    cJSON_AddBoolToObject(obj, "diverged", reasons != 0u);
    cJSON *why = cJSON_AddArrayToObject(obj, "diverged_reasons");
    for (int b = 0; b < SIM_DIVERGED_REASON_COUNT; b++) {
        if ((reasons & (1u << b)) != 0u) {
            cJSON_AddItemToArray(why, cJSON_CreateString(sim_divergence_reason_name(b)));
        }
    }
    add_number(obj, "max_position_error_m", m->max_position_error_m);
    add_number(obj, "settled_position_error_m", m->settled_position_error_m);
}

static cJSON *record_json(const run_record *r)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "scenario", r->sc->name);
    cJSON_AddStringToObject(o, "scenario_file", r->sc->path);
    cJSON_AddStringToObject(o, "variant", sim_variant_names[r->variant]);
    cJSON_AddStringToObject(o, "backend", r->backend);
    cJSON_AddNumberToObject(o, "seed", (double)r->seed);
    cJSON_AddNumberToObject(o, "duration_s", r->sc->duration_s);
    cJSON_AddNumberToObject(o, "controller_rate_hz", r->sc->controller_rate_hz);
    cJSON_AddNumberToObject(o, "plant_rate_hz", r->sc->plant_rate_hz);
    if (r->sc->override_count > 0) {
        cJSON *set = cJSON_AddArrayToObject(o, "overrides");
        for (int i = 0; i < r->sc->override_count; i++) {
            cJSON_AddItemToArray(set, cJSON_CreateString(r->sc->overrides[i]));
        }
    }
    if (r->failed) {
        cJSON_AddStringToObject(o, "error", r->error);
        for (int k = 0; k < SIM_METRIC_COUNT; k++) {
            cJSON_AddNullToObject(o, sim_metric_names[k]);
        }
        return o;
    }
    /* what the firmware was configured with */
    const fsw_info *fi = &r->result.info;
    cJSON *fw = cJSON_AddObjectToObject(o, "firmware");
    add_number(fw, "nominal_mass_kg", fi->mass_kg);
    add_number(fw, "theta0_kg", fi->theta0_kg);
    add_number(fw, "theta_min_kg", fi->theta_min_kg);
    add_number(fw, "theta_max_kg", fi->theta_max_kg);
    add_number(fw, "thrust_min_n", fi->thrust_min_n);
    add_number(fw, "thrust_max_n", fi->thrust_max_n);
    add_number(fw, "ground_gain_max", fi->ground_gain_max);
    add_number(fw, "rho_n", fi->rho_n);
    add_number(fw, "gamma", fi->gamma);
    add_number(fw, "z_r_tau_s", fi->ref_tau_s);
    add_number(fw, "z_r_init_m", fi->ref_offset_init_m);
    add_number(fw, "z_r_bias_m", fi->ref_bias_m);
    add_number(fw, "accel_fb_gain_per_s", fi->accel_fb_gain_per_s);
    add_number(fw, "failsafe_descent_mps", fi->failsafe_descent_mps);
    cJSON_AddNumberToObject(fw, "state_bytes", (double)fi->state_bytes);
    if (r->runs <= 1) {
        add_metrics(o, &r->result.metrics);
        add_number(o, "theta_end_kg", r->result.metrics.theta_end_kg);
        add_number(o, "theta_star_end_kg", r->result.metrics.theta_star_end_kg);
        add_divergence(o, &r->result.metrics, &r->sc->montecarlo);
        add_number(o, "wall_time_s", r->result.wall_s);
        add_number(o, "real_time_factor", r->result.wall_s > 0.0 ? r->sc->duration_s / r->result.wall_s : (double)NAN);
        if (r->sc->mission.command == MISSION_LAND || isfinite(r->result.metrics.failsafe_entered)) {
            add_landing(o, &r->result);
        }
        return o;
    }
    cJSON_AddNumberToObject(o, "runs", r->runs);
    /* robustness: how many runs diverged (robustness.h), by reason, and the NaN outputs */
    const montecarlo_params *mc = &r->sc->montecarlo;
    cJSON *dv = cJSON_AddObjectToObject(o, "divergence");
    cJSON_AddNumberToObject(dv, "error_m", mc->diverged_error_m);
    cJSON_AddNumberToObject(dv, "position_m", mc->diverged_position_m);
    cJSON_AddNumberToObject(dv, "tilt_deg", mc->diverged_tilt_deg);
    cJSON_AddNumberToObject(o, "diverged_runs", r->diverged_runs);
    cJSON *by = cJSON_AddObjectToObject(o, "diverged_by_reason");
    for (int b = 0; b < SIM_DIVERGED_REASON_COUNT; b++) {
        cJSON_AddNumberToObject(by, sim_divergence_reason_name(b), r->diverged_by_reason[b]);
    }
    cJSON_AddNumberToObject(o, "nan_output_runs", r->nan_output_runs);
    cJSON_AddNumberToObject(o, "nan_outputs_total", r->nan_outputs_total);
    cJSON_AddNumberToObject(o, "failsafe_entered_runs", r->failsafe_entered_runs);
    cJSON_AddNumberToObject(o, "airborne_motor_stop_runs", r->airborne_motor_stop_runs);
    cJSON *stats = cJSON_AddObjectToObject(o, "metrics");
    for (int k = 0; k < SIM_METRIC_COUNT; k++) {
        const metric_stats *s = &r->stats[k];
        cJSON *m = cJSON_AddObjectToObject(stats, sim_metric_names[k]);
        add_number(m, "min", s->min);
        add_number(m, "median", s->median);
        add_number(m, "p90", s->p90);
        add_number(m, "p95", s->p95);
        add_number(m, "p99", s->p99);
        add_number(m, "max", s->max);
        if (s->count > 0) {
            cJSON_AddNumberToObject(m, "worst_seed", (double)s->worst_seed);
        } else {
            cJSON_AddNullToObject(m, "worst_seed");
        }
        cJSON_AddNumberToObject(m, "count", s->count);
    }
    cJSON *runs = cJSON_AddArrayToObject(o, "per_run");
    for (int i = 0; i < r->runs; i++) {
        cJSON *one = cJSON_CreateObject();
        cJSON_AddNumberToObject(one, "seed", (double)r->per_run_seed[i]);
        add_metrics(one, &r->per_run[i]);
        add_divergence(one, &r->per_run[i], mc);
        cJSON_AddItemToArray(runs, one);
    }
    add_number(o, "wall_time_s", r->wall_s);
    return o;
}

bool output_json(const char *path, const run_record *records, int count, char *err, size_t err_len)
{
    cJSON *root;
    if (count == 1) {
        root = record_json(&records[0]);
    } else {
        root = cJSON_CreateObject();
        cJSON_AddStringToObject(root, "scenario", records[0].sc->name);
        cJSON *results = cJSON_AddArrayToObject(root, "results");
        for (int i = 0; i < count; i++) {
            cJSON_AddItemToArray(results, record_json(&records[i]));
        }
    }
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    FILE *f = fopen(path, "w");
    if (f == NULL || text == NULL) {
        snprintf(err, err_len, "%s: cannot write: %s", path, strerror(errno));
        free(text);
        if (f != NULL) {
            fclose(f);
        }
        return false;
    }
    fputs(text, f);
    fputc('\n', f);
    free(text);
    if (fclose(f) != 0) {
        snprintf(err, err_len, "%s: write failed", path);
        return false;
    }
    return true;
}

/* ---------------------------------------------------------------------- */
/* CSV and data files                                                      */
/* ---------------------------------------------------------------------- */

void output_csv_path(const char *base, const run_record *r, int count, char *out, size_t out_len)
{
    if (count == 1) {
        snprintf(out, out_len, "%s", base);
        return;
    }
    const char *slash = strrchr(base, '/');
    const char *dot = strrchr(base, '.');
    /* figure = accel-feedback flies each run twice: the second is "-without" */
    const char *without =
        (r->sc->figure == FIGURE_ACCEL_FEEDBACK && r->sc->fsw.accel_fb_gain_per_s == 0.0) ? "-without" : "";
    if (dot == NULL || (slash != NULL && dot < slash)) {
        snprintf(out, out_len, "%s-%s-%s%s", base, sim_variant_names[r->variant], r->backend, without);
    } else {
        snprintf(out, out_len, "%.*s-%s-%s%s%s", (int)(dot - base), base, sim_variant_names[r->variant], r->backend,
                 without, dot);
    }
}

static bool write_table(const char *path, const sim_trace *t, char sep, bool comment_header, char *err,
                        size_t err_len)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        snprintf(err, err_len, "%s: cannot write: %s", path, strerror(errno));
        return false;
    }
    if (comment_header) {
        fputs("# ", f);
    }
    for (int c = 0; c < SIM_TRACE_COLUMN_COUNT; c++) {
        fprintf(f, "%s%c", sim_trace_column_names[c], c + 1 < SIM_TRACE_COLUMN_COUNT ? sep : '\n');
    }
    for (size_t r = 0; r < t->rows; r++) {
        const double *row = t->data + r * SIM_TRACE_COLUMN_COUNT;
        for (int c = 0; c < SIM_TRACE_COLUMN_COUNT; c++) {
            fprintf(f, "%.9g%c", row[c], c + 1 < SIM_TRACE_COLUMN_COUNT ? sep : '\n');
        }
    }
    if (fclose(f) != 0) {
        snprintf(err, err_len, "%s: write failed", path);
        return false;
    }
    return true;
}

bool output_csv(const char *path, const run_record *r, char *err, size_t err_len)
{
    if (r->trace.data == NULL) {
        snprintf(err, err_len, "%s: no trace to write (Monte-Carlo runs keep none)", path);
        return false;
    }
    return write_table(path, &r->trace, ',', false, err, err_len);
}

/* ---------------------------------------------------------------------- */
/* figures                                                                 */
/* ---------------------------------------------------------------------- */

static bool gnuplot_available(void)
{
    const char *path = getenv("PATH");
    if (path == NULL) {
        return false;
    }
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", path);
    char *save = NULL;
    for (char *dir = strtok_r(buf, ":", &save); dir != NULL; dir = strtok_r(NULL, ":", &save)) {
        char exe[4200];
        snprintf(exe, sizeof exe, "%s/gnuplot", dir);
        if (access(exe, X_OK) == 0) {
            return true;
        }
    }
    return false;
}

/* gnuplot's 1-based column of a trace column. */
#define COL(name) (SIM_COL_##name + 1)

static void data_name(const run_record *r, char *out, size_t len)
{
    snprintf(out, len, "%s-%s-%s.dat", r->sc->name, sim_variant_names[r->variant], r->backend);
}

/* The largest |value| of a trace column (to keep flat plots from collapsing). */
static double column_peak(const sim_trace *t, int column)
{
    double peak = 0.0;
    for (size_t i = 0; i < t->rows; i++) {
        const double v = fabs(t->data[i * SIM_TRACE_COLUMN_COUNT + (size_t)column]);
        peak = v > peak ? v : peak;
    }
    return peak;
}

static void summary_figure(FILE *gp, const run_record *r)
{
    char dat[256];
    data_name(r, dat, sizeof dat);
    const char *v = sim_variant_names[r->variant];
    fprintf(gp, "\n# ---- summary of %s, %s, %s\n", r->sc->name, v, r->backend);
    fprintf(gp, "set output 'summary-%s-%s-%s.png'\n", r->sc->name, v, r->backend);
    fprintf(gp, "set multiplot layout 3,2 title '%s: %s (%s backend)' font ',14'\n", r->sc->name, v, r->backend);
    fprintf(gp, "set xlabel 't [s]'\n");
    fprintf(gp, "set ylabel 'height [m]'\nset title 'pad, reference and altitude'\n");
    fprintf(gp,
            "plot '%s' u %d:%d w l lw 2 lc rgb '#2ca02c' t 'pad z_d', '' u %d:%d w l lw 1.5 lc rgb '#d62728' t "
            "'reference z_r', '' u %d:%d w l lw 1.5 lc rgb '#1f77b4' t 'altitude z'\n",
            dat, COL(t_s), COL(pad_z_m), COL(t_s), COL(z_r_m), COL(t_s), COL(z_m));
    fprintf(gp, "set ylabel 'e [mm]'\nset title 'tracking error e = z - z_r'\n");
    fprintf(gp, "plot '%s' u %d:($%d*1000) w l lc rgb '#1f77b4' t 'e'\n", dat, COL(t_s), COL(error_m));
    fprintf(gp, "set ylabel 'force [N]'\nset title 'thrust: command and delivered'\n");
    fprintf(gp,
            "plot '%s' u %d:%d w l lc rgb '#d62728' t 'command F_z', '' u %d:%d w l lc rgb '#1f77b4' t "
            "'rotors (with k_g)'\n",
            dat, COL(t_s), COL(thrust_cmd_n), COL(t_s), COL(rotor_thrust_n));
    fprintf(gp, "set ylabel '[kg]'\nset title 'Theta* = m/(k_h k_g) and Theta'\n");
    fprintf(gp,
            "plot '%s' u %d:%d w l lw 1.5 lc rgb '#1f77b4' t 'Theta*', '' u %d:%d w l lw 1.5 lc rgb '#2ca02c' t "
            "'Theta'\n",
            dat, COL(t_s), COL(theta_star_kg), COL(t_s), COL(theta_kg));
    fprintf(gp, "set ylabel 'tilt [deg]'\nset y2label 'x, y [m]'\nset y2tics\nset title 'attitude and position'\n");
    /* a level, centred flight plots flat lines: give those a range of their own */
    if (column_peak(&r->trace, SIM_COL_tilt_deg) < 1e-6) {
        fprintf(gp, "set yrange [0:1]\n");
    }
    if (column_peak(&r->trace, SIM_COL_x_m) < 1e-6 && column_peak(&r->trace, SIM_COL_y_m) < 1e-6) {
        fprintf(gp, "set y2range [-0.01:0.01]\n");
    }
    fprintf(gp,
            "plot '%s' u %d:%d w l lc rgb '#9467bd' t 'tilt', '' u %d:%d axes x1y2 w l lc rgb '#ff7f0e' t 'x', '' "
            "u %d:%d axes x1y2 w l lc rgb '#17becf' t 'y'\n",
            dat, COL(t_s), COL(tilt_deg), COL(t_s), COL(x_m), COL(t_s), COL(y_m));
    fprintf(gp, "unset y2tics\nset y2label ''\nset autoscale y\nset autoscale y2\n");
    if (column_peak(&r->trace, SIM_COL_contact_force_n) < 1e-9) {
        fprintf(gp, "set y2range [0:1]\n");
    }
    fprintf(gp, "set ylabel 'clearance [m]'\nset y2label 'contact force [N]'\nset y2tics\n"
                "set title 'landing gear above the pad'\n");
    fprintf(gp,
            "plot '%s' u %d:%d w l lc rgb '#1f77b4' t 'gear clearance', '' u %d:%d axes x1y2 w l lc rgb '#d62728' "
            "t 'contact force'\n",
            dat, COL(t_s), COL(gear_clearance_m), COL(t_s), COL(contact_force_n));
    fprintf(gp, "unset y2tics\nset y2label ''\nset autoscale y2\nunset multiplot\n");
}

/* Figures 4.2 and 4.3 of the dissertation from a pair ssc / ssc-adaptive. */
static void dissertation_figures(FILE *gp, const run_record *plain, const run_record *adaptive)
{
    char dp[256], da[256];
    data_name(plain, dp, sizeof dp);
    data_name(adaptive, da, sizeof da);
    const char *b = plain->backend;
    fprintf(gp, "\n# ---- the dissertation's Figure 4.2 (%s backend)\n", b);
    fprintf(gp, "set output 'fig4.2-%s.png'\n", b);
    fprintf(gp, "set multiplot layout 2,1 title 'Figure 4.2: tracking (%s, %s backend)' font ',14'\n",
            plain->sc->name, b);
    fprintf(gp, "set xlabel 't [s]'\nset ylabel 'altitude [m]'\nset title '(a) pad z_d, reference z_r, altitude z'\n");
    fprintf(gp,
            "plot '%s' u %d:%d w l lw 2 lc rgb '#2ca02c' t 'pad z_d', '' u %d:%d w l lw 2 lc rgb '#d62728' t "
            "'reference z_r', '%s' u %d:%d w l lw 1.5 lc rgb '#e377c2' t 'z, SSC with adaptation', '%s' u %d:%d w l "
            "lw 1.5 dt 2 lc rgb '#1f77b4' t 'z, SSC without adaptation'\n",
            da, COL(t_s), COL(pad_z_m), COL(t_s), COL(z_r_m), da, COL(t_s), COL(z_m), dp, COL(t_s), COL(z_m));
    fprintf(gp, "set ylabel 'u = F_z [N]'\nset title '(b) control signal'\n");
    fprintf(gp,
            "plot '%s' u %d:%d w l lc rgb '#d62728' t 'with adaptation', '%s' u %d:%d w l lc rgb '#1f77b4' t "
            "'without adaptation'\n",
            da, COL(t_s), COL(thrust_cmd_n), dp, COL(t_s), COL(thrust_cmd_n));
    fprintf(gp, "unset multiplot\n");

    fprintf(gp, "\n# ---- the dissertation's Figure 4.3 (%s backend)\n", b);
    fprintf(gp, "set output 'fig4.3-%s.png'\n", b);
    fprintf(gp, "set multiplot layout 2,1 title 'Figure 4.3: adaptation (%s, %s backend)' font ',14'\n",
            plain->sc->name, b);
    fprintf(gp, "set xlabel 't [s]'\nset ylabel '[kg]'\nset title '(a) ideal Theta*(t) and adapted Theta(t)'\n");
    fprintf(gp,
            "plot '%s' u %d:%d w l lw 2 lc rgb '#1f77b4' t 'Theta*', '' u %d:%d w l lw 2 lc rgb '#2ca02c' t "
            "'Theta'\n",
            da, COL(t_s), COL(theta_star_kg), COL(t_s), COL(theta_kg));
    /* the first second's transient reaches tens of m/s^2: the axis shows the rest */
    double peak = 0.0;
    const run_record *pair[2] = {plain, adaptive};
    for (int k = 0; k < 2; k++) {
        const sim_trace *t = &pair[k]->trace;
        for (size_t i = 0; i < t->rows; i++) {
            const double *row = t->data + i * SIM_TRACE_COLUMN_COUNT;
            if (row[SIM_COL_t_s] >= 2.0 && fabs(row[SIM_COL_adaptation_term_mps2]) > peak) {
                peak = fabs(row[SIM_COL_adaptation_term_mps2]);
            }
        }
    }
    if (peak > 0.0) {
        fprintf(gp, "set yrange [%g:%g]\n", -1.5 * peak, 1.5 * peak);
    }
    fprintf(gp, "set ylabel '[m/s^2]'\nset title '(b) (Theta - Theta*)/Theta* phi (axis clipped to t >= 2 s)'\n");
    fprintf(gp,
            "plot '%s' u %d:%d w l lc rgb '#d62728' t 'with adaptation', '%s' u %d:%d w l lc rgb '#1f77b4' t "
            "'without adaptation'\n",
            da, COL(t_s), COL(adaptation_term_mps2), dp, COL(t_s), COL(adaptation_term_mps2));
    fprintf(gp, "set autoscale y\nunset multiplot\n");
}

/* ---- section 4.5's experiments (Figures 4.4-4.7): the PD run beside the SSC ones */

/* The pid law with both integral gains 0 is the dissertation's PD (fsw_adapter.h). */
static const char *law_label(const run_record *r)
{
    const fsw_config *f = &r->sc->fsw;
    if (strcmp(sim_variant_names[r->variant], "pid") == 0) {
        return (f->pid_ki_z_per_s2 == 0.0 && f->pid_ki_v_n_per_m == 0.0) ? "PD" : "PID";
    }
    return sim_variant_names[r->variant];
}

#define EXPERIMENT_COLUMNS_MAX 4

/* The runs of one backend drawn side by side: the pid (PD) run first, then
 * every SSC variant in the order given. Returns how many; 0 without a PD and
 * an SSC run. */
static int experiment_columns(const run_record *records, int count, const char *backend,
                              const run_record *cols[EXPERIMENT_COLUMNS_MAX])
{
    int n = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < count && n < EXPERIMENT_COLUMNS_MAX; i++) {
            const run_record *r = &records[i];
            const char *v = sim_variant_names[r->variant];
            const bool wanted = pass == 0 ? strcmp(v, "pid") == 0 : strncmp(v, "ssc", 3) == 0;
            if (r->trace.data != NULL && wanted && strcmp(r->backend, backend) == 0) {
                cols[n++] = r;
            }
        }
        if (pass == 0 && n == 0) {
            return 0;
        }
    }
    return n >= 2 ? n : 0;
}

/* One of Figures 4.4-4.7 in a backend: the dissertation's panels as rows, one
 * column per law. Heights in m for the F450, in cm for the Crazyflie (as the
 * dissertation's figures). */
static void experiment_figure(FILE *gp, const run_record *const *cols, int ncols)
{
    const scenario *sc = cols[0]->sc;
    const char *b = cols[0]->backend;
    static const char *const what[] = {"", "F450: heading tracking and ground effect",
                                       "Crazyflie: ground effect", "Crazyflie: tracking",
                                       "Crazyflie: landing on an oscillating platform"};
    static const char *const number[] = {"", "4.4", "4.5", "4.6", "4.7"};
    const int f = (int)sc->figure;
    const int rows = (sc->figure == FIGURE_4_4 || sc->figure == FIGURE_4_5) ? 3 : 2;
    const double len = sc->figure == FIGURE_4_4 ? 1.0 : 100.0; /* m -> the figure's unit */
    const char *unit = sc->figure == FIGURE_4_4 ? "m" : "cm";
    fprintf(gp, "\n# ---- the dissertation's Figure %s (%s backend)\n", number[f], b);
    fprintf(gp, "set output 'fig%s-%s.png'\n", number[f], b);
    fprintf(gp, "set terminal pngcairo size %d,%d enhanced font 'DejaVu Sans,10'\n", 600 * ncols + 200, 330 * rows);
    fprintf(gp,
            "set multiplot layout %d,%d columnsfirst title 'Figure %s: %s (%s, %s backend; SIL, not the "
            "experiment)' font ',14'\n",
            rows, ncols, number[f], what[f], sc->name, b);
    fprintf(gp, "set xlabel 't [s]'\n");
    for (int c = 0; c < ncols; c++) {
        char dat[256];
        data_name(cols[c], dat, sizeof dat);
        const char *law = law_label(cols[c]);
        switch (sc->figure) {
        case FIGURE_4_4:
            fprintf(gp, "set ylabel 'heading [deg]'\nset title '(a) heading {/Symbol y} and {/Symbol y}_r, %s'\n",
                    law);
            fprintf(gp,
                    "plot '%s' u %d:%d w l lw 1.5 lc rgb '#d62728' t '{/Symbol y}_r', '' u %d:%d w l lw 1.5 lc rgb "
                    "'#1f77b4' t '{/Symbol y}'\n",
                    dat, COL(t_s), COL(yaw_r_deg), COL(t_s), COL(yaw_deg));
            fprintf(gp, "set ylabel 'height [m]'\nset title '(b) altitude z and ground level, %s'\n", law);
            fprintf(gp,
                    "plot '%s' u %d:%d w l lw 1.5 lc rgb '#1f77b4' t 'z', '' u %d:%d w l lw 2 lc rgb '#d62728' t "
                    "'ground'\n",
                    dat, COL(t_s), COL(z_m), COL(t_s), COL(pad_z_m));
            fprintf(gp, "set ylabel 'F_z k_h [N]'\nset title '(c) k_h u = F_z k_h (3.4), %s'\n", law);
            fprintf(gp, "plot '%s' u %d:($%d*$%d) w l lc rgb '#1f77b4' t 'F_z k_h', '' u %d:($%d*$%d) smooth bezier "
                        "lw 2 lc rgb '#d62728' t 'trend'\n",
                    dat, COL(t_s), COL(thrust_cmd_n), COL(k_h), COL(t_s), COL(thrust_cmd_n), COL(k_h));
            break;
        case FIGURE_4_5:
            fprintf(gp, "set ylabel 'z_r [%s]'\nset title '(a) desired altitude, %s'\n", unit, law);
            fprintf(gp, "plot '%s' u %d:($%d*%g) w l lw 1.5 lc rgb '#d62728' t 'z_r'\n", dat, COL(t_s), COL(z_r_m),
                    len);
            fprintf(gp, "set ylabel 'F_z [N]'\nset title '(b) control effort, %s'\n", law);
            fprintf(gp, "plot '%s' u %d:%d w l lc rgb '#1f77b4' t 'F_z', '' u %d:%d smooth bezier lw 2 lc rgb "
                        "'#d62728' t 'average (trend)'\n",
                    dat, COL(t_s), COL(thrust_cmd_n), COL(t_s), COL(thrust_cmd_n));
            fprintf(gp, "set ylabel 'e [%s]'\nset title '(c) tracking error e = z - z_r, %s'\n", unit, law);
            fprintf(gp, "plot '%s' u %d:($%d*%g) w l lc rgb '#1f77b4' t 'e'\n", dat, COL(t_s), COL(error_m), len);
            break;
        case FIGURE_4_6:
        case FIGURE_4_7:
            fprintf(gp, "set ylabel 'altitude [%s]'\nset title '(a) z_r%s and z, %s'\n", unit,
                    sc->figure == FIGURE_4_7 ? ", pad z_d" : "", law);
            fprintf(gp, "plot '%s' u %d:($%d*%g) w l lw 1.5 lc rgb '#d62728' t 'z_r', '' u %d:($%d*%g) w l lw 1.5 "
                        "lc rgb '#1f77b4' t 'z'",
                    dat, COL(t_s), COL(z_r_m), len, COL(t_s), COL(z_m), len);
            if (sc->figure == FIGURE_4_7) {
                fprintf(gp, ", '' u %d:($%d*%g) w l lw 2 lc rgb '#2ca02c' t 'pad z_d'", COL(t_s), COL(pad_z_m), len);
            }
            fprintf(gp, "\nset ylabel 'F_z [N]'\nset title '(b) control effort, %s'\n", law);
            fprintf(gp, "plot '%s' u %d:%d w l lc rgb '#1f77b4' t 'F_z'\n", dat, COL(t_s), COL(thrust_cmd_n));
            break;
        default:
            break;
        }
    }
    fprintf(gp, "unset multiplot\nset terminal pngcairo size 1400,1000 enhanced font 'DejaVu Sans,10'\n");
}

/* ---- figure = accel-feedback: a run with the acceleration feedback beside the same run without it */

/* The largest |value| of a column over both runs, for one axis range across the columns. */
static double pair_peak(const run_record *const pair[2], int column)
{
    const double a = column_peak(&pair[0]->trace, column), b = column_peak(&pair[1]->trace, column);
    const double peak = a > b ? a : b;
    return peak > 1e-9 ? 1.1 * peak : 1e-3;
}

static void accel_feedback_figure(FILE *gp, const run_record *with, const run_record *without)
{
    const run_record *const pair[2] = {with, without};
    const char *v = sim_variant_names[with->variant];
    const char *b = with->backend;
    const double xy = 100.0 * (pair_peak(pair, SIM_COL_x_m) > pair_peak(pair, SIM_COL_y_m)
                                   ? pair_peak(pair, SIM_COL_x_m)
                                   : pair_peak(pair, SIM_COL_y_m));
    const double e = 100.0 * pair_peak(pair, SIM_COL_error_m);
    const double fb_x = pair_peak(pair, SIM_COL_accel_fb_x_mps2), fb_y = pair_peak(pair, SIM_COL_accel_fb_y_mps2);
    const double ix = pair_peak(pair, SIM_COL_pos_int_x_mps2), iy = pair_peak(pair, SIM_COL_pos_int_y_mps2);
    double fb = fb_x > fb_y ? fb_x : fb_y;
    fb = fb > ix ? fb : ix;
    fb = fb > iy ? fb : iy;
    /* the mass on its own axis, its steps inside the panel */
    const double mass_max = pair_peak(pair, SIM_COL_mass_kg) / 1.1;
    double mass_min = mass_max;
    for (int k = 0; k < 2; k++) {
        for (size_t i = 0; i < pair[k]->trace.rows; i++) {
            const double m = pair[k]->trace.data[i * SIM_TRACE_COLUMN_COUNT + (size_t)SIM_COL_mass_kg];
            mass_min = m < mass_min ? m : mass_min;
        }
    }
    const double mass_pad = 0.5 * (mass_max - mass_min) + 0.05 * mass_max;
    fprintf(gp, "\n# ---- acceleration feedback: %s with and without (%s, %s backend)\n", with->sc->name, v, b);
    fprintf(gp, "set output 'accel-feedback-%s-%s.png'\n", v, b);
    fprintf(gp, "set terminal pngcairo size 1400,1000 enhanced font 'DejaVu Sans,10'\n");
    fprintf(gp,
            "set multiplot layout 3,2 columnsfirst title 'Acceleration feedback (2.10)-(2.11) through mass steps (%s, "
            "%s, %s backend)' font ',14'\n",
            with->sc->name, v, b);
    fprintf(gp, "set xlabel 't [s]'\n");
    for (int c = 0; c < 2; c++) {
        char dat[256];
        data_name(pair[c], dat, sizeof dat);
        char label[64];
        snprintf(label, sizeof label, "k_a = %g /s", pair[c]->result.info.accel_fb_gain_per_s);
        fprintf(gp, "set yrange [%g:%g]\nset ylabel 'position [cm]'\nset y2label 'mass [kg]'\nset y2tics\n", -xy,
                xy);
        fprintf(gp, "set y2range [%g:%g]\n", mass_min - mass_pad, mass_max + mass_pad);
        fprintf(gp, "set title '(a) horizontal position x, y (setpoint 0), %s'\n", label);
        fprintf(gp,
                "plot '%s' u %d:($%d*100) w l lc rgb '#1f77b4' t 'x', '' u %d:($%d*100) w l lc rgb '#ff7f0e' t 'y', "
                "'' u %d:%d axes x1y2 w l lw 2 lc rgb '#7f7f7f' t 'mass'\n",
                dat, COL(t_s), COL(x_m), COL(t_s), COL(y_m), COL(t_s), COL(mass_kg));
        fprintf(gp, "unset y2tics\nset y2label ''\nset autoscale y2\n");
        fprintf(gp, "set yrange [%g:%g]\nset ylabel 'e [cm]'\nset title '(b) altitude error e = z - z_r, %s'\n", -e,
                e, label);
        fprintf(gp, "plot '%s' u %d:($%d*100) w l lc rgb '#1f77b4' t 'e'\n", dat, COL(t_s), COL(error_m));
        fprintf(gp,
                "set yrange [%g:%g]\nset ylabel '[m/s^2]'\nset title '(c) feedback term I_a and position integral "
                "I, %s'\n",
                -fb, fb, label);
        fprintf(gp,
                "plot '%s' u %d:%d w l lw 1.5 lc rgb '#d62728' t 'I_{a,x}', '' u %d:%d w l lw 1.5 lc rgb '#9467bd' t "
                "'I_{a,y}', '' u %d:%d w l dt 2 lc rgb '#2ca02c' t 'I_x', '' u %d:%d w l dt 2 lc rgb '#17becf' t "
                "'I_y'\n",
                dat, COL(t_s), COL(accel_fb_x_mps2), COL(t_s), COL(accel_fb_y_mps2), COL(t_s), COL(pos_int_x_mps2),
                COL(t_s), COL(pos_int_y_mps2));
    }
    fprintf(gp, "unset multiplot\nset autoscale y\n");
}

/* Each run of an accel-feedback scenario paired with its run without the feedback. */
static int accel_feedback_figures(FILE *gp, const run_record *records, int count)
{
    int n = 0;
    for (int i = 0; i < count; i++) {
        const run_record *p = &records[i];
        if (p->sc->figure != FIGURE_ACCEL_FEEDBACK || p->trace.data == NULL ||
            !(p->result.info.accel_fb_gain_per_s > 0.0)) {
            continue;
        }
        for (int j = 0; j < count; j++) {
            const run_record *q = &records[j];
            if (q->sc->figure == FIGURE_ACCEL_FEEDBACK && q->trace.data != NULL &&
                q->result.info.accel_fb_gain_per_s == 0.0 && q->variant == p->variant &&
                strcmp(q->backend, p->backend) == 0) {
                accel_feedback_figure(gp, p, q);
                n++;
                break;
            }
        }
    }
    return n;
}

static bool ensure_dir(const char *dir, char *err, size_t err_len)
{
    struct stat st;
    if (stat(dir, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            return true;
        }
        snprintf(err, err_len, "%s: not a directory", dir);
        return false;
    }
    /* mkdir -p */
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", dir);
    for (char *p = buf + 1; *p != '\0'; p++) {
        if (*p == '/') {
            *p = '\0';
            (void)mkdir(buf, 0777);
            *p = '/';
        }
    }
    if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
        snprintf(err, err_len, "%s: cannot create: %s", dir, strerror(errno));
        return false;
    }
    return true;
}

bool output_plots(const char *dir, const run_record *records, int count, bool quiet, char *err, size_t err_len)
{
    if (!ensure_dir(dir, err, err_len)) {
        return false;
    }
    char path[1400];
    int with_trace = 0;
    for (int i = 0; i < count; i++) {
        if (records[i].trace.data == NULL) {
            continue;
        }
        char dat[256];
        data_name(&records[i], dat, sizeof dat);
        snprintf(path, sizeof path, "%s/%s", dir, dat);
        if (!write_table(path, &records[i].trace, ' ', true, err, err_len)) {
            return false;
        }
        with_trace++;
    }
    if (with_trace == 0) {
        if (!quiet) {
            fprintf(stderr, "fc-sil: no traces to plot (Monte-Carlo runs keep none)\n");
        }
        return true;
    }
    snprintf(path, sizeof path, "%s/plots.gp", dir);
    FILE *gp = fopen(path, "w");
    if (gp == NULL) {
        snprintf(err, err_len, "%s: cannot write: %s", path, strerror(errno));
        return false;
    }
    fprintf(gp, "# gnuplot script written by fc-sil; run it in this directory: gnuplot plots.gp\n");
    fprintf(gp, "set terminal pngcairo size 1400,1000 enhanced font 'DejaVu Sans,10'\n");
    fprintf(gp, "set grid\nset key top right box opaque\nset datafile commentschars '#'\n");
    for (int i = 0; i < count; i++) {
        if (records[i].trace.data != NULL) {
            summary_figure(gp, &records[i]);
        }
    }
    int figures = 0;
    for (int i = 0; i < count; i++) {
        const run_record *p = &records[i];
        /* a scenario of section 4.5 draws its own figure instead */
        if (p->trace.data == NULL || p->sc->figure != FIGURE_NONE ||
            strcmp(sim_variant_names[p->variant], "ssc") != 0) {
            continue;
        }
        for (int j = 0; j < count; j++) {
            const run_record *q = &records[j];
            if (q->trace.data != NULL && strcmp(sim_variant_names[q->variant], "ssc-adaptive") == 0 &&
                strcmp(q->backend, p->backend) == 0) {
                dissertation_figures(gp, p, q);
                figures++;
                break;
            }
        }
    }
    /* section 4.5's figure, once per backend that has a PD and an SSC run */
    int experiments = 0;
    for (int i = 0; i < count; i++) {
        if (records[i].sc->figure == FIGURE_NONE || records[i].sc->figure == FIGURE_ACCEL_FEEDBACK ||
            records[i].trace.data == NULL) {
            continue;
        }
        bool seen = false;
        for (int j = 0; j < i; j++) {
            seen = seen || strcmp(records[j].backend, records[i].backend) == 0;
        }
        const run_record *cols[EXPERIMENT_COLUMNS_MAX];
        const int ncols = seen ? 0 : experiment_columns(records, count, records[i].backend, cols);
        if (ncols > 0) {
            experiment_figure(gp, cols, ncols);
            experiments++;
        }
    }
    const int accel_figures = accel_feedback_figures(gp, records, count);
    if (fclose(gp) != 0) {
        snprintf(err, err_len, "%s: write failed", path);
        return false;
    }
    if (!gnuplot_available()) {
        fprintf(stderr, "fc-sil: gnuplot not found; plots skipped (data and plots.gp are in %s)\n", dir);
        return true;
    }
    fflush(stdout);
    fflush(stderr);
    const pid_t pid = fork();
    if (pid < 0) {
        snprintf(err, err_len, "cannot start gnuplot: %s", strerror(errno));
        return false;
    }
    if (pid == 0) {
        if (chdir(dir) != 0) {
            _exit(127);
        }
        execlp("gnuplot", "gnuplot", "plots.gp", (char *)NULL);
        _exit(127);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        snprintf(err, err_len, "gnuplot failed on %s/plots.gp", dir);
        return false;
    }
    if (!quiet) {
        fprintf(stderr, "fc-sil: figures in %s (%d summar%s%s%s%s)\n", dir, with_trace,
                with_trace == 1 ? "y" : "ies", figures > 0 ? ", Figures 4.2 and 4.3" : "",
                experiments > 0 ? ", the dissertation's section 4.5 figure" : "",
                accel_figures > 0 ? ", accel-feedback-*.png" : "");
    }
    return true;
}

/* ---------------------------------------------------------------------- */
/* printed tables                                                          */
/* ---------------------------------------------------------------------- */

/* Column headings and scales of the printed tables. */
static const char *const short_names[SIM_METRIC_COUNT] = {
    "rms[mm]", "max[mm]", "step[mm]", "tv[N/s]", "theta_err", "clr[mm]", "td_v[m/s]", "td_t[s]", "bounces",
    "tilt[deg]", "nan", "td_tilt[deg]", "early", "sat[s]", "entered", "air_stops", "fs_v[m/s]", "fs_v_err", "fs_td[m/s]", "off[s]"};
static const double scales[SIM_METRIC_COUNT] = {1000.0, 1000.0, 1000.0, 1.0, 1.0, 1000.0, 1.0, 1.0, 1.0, 1.0,
                                                1.0,    1.0,    1.0,    1.0, 1.0, 1.0,    1.0, 1.0, 1.0, 1.0};

static void print_value(double v, double scale)
{
    if (isfinite(v)) {
        printf(" %10.4g", v * scale);
    } else {
        printf(" %10s", "-");
    }
}

/* Whether a record's failsafe metrics apply (to its single run, or to any of its runs). */
static bool has_failsafe(const run_record *r)
{
    const int k = SIM_METRIC_FAILSAFE_FIRST; /* failsafe_entered */
    return !r->failed && (r->runs > 1 ? r->stats[k].count > 0 : isfinite(sim_metric_value(&r->result.metrics, k)));
}

/* The robustness lines of a Monte-Carlo record: diverged runs by reason, the
 * NaN outputs, and the first diverged seeds. */
static void print_divergence(const run_record *r)
{
    const montecarlo_params *mc = &r->sc->montecarlo;
    printf("diverged: %d of %d runs (after the transient |error| > %g m or position > %g m; tilt > %g deg, "
           "non-finite state or output):",
           r->diverged_runs, r->runs, mc->diverged_error_m, mc->diverged_position_m, mc->diverged_tilt_deg);
    for (int b = 0; b < SIM_DIVERGED_REASON_COUNT; b++) {
        printf(" %s %d", sim_divergence_reason_name(b), r->diverged_by_reason[b]);
    }
    printf("\nNaN outputs: %d runs, %.0f steps\n", r->nan_output_runs, r->nan_outputs_total);
    if (has_failsafe(r)) {
        printf("failsafe: entered in %d of %d runs; motors stopped in the air in %d runs\n", r->failsafe_entered_runs,
               r->runs, r->airborne_motor_stop_runs);
    }
    if (r->diverged_runs == 0) {
        return;
    }
    printf("diverged seeds:");
    int shown = 0;
    for (int i = 0; i < r->runs && shown < 20; i++) {
        const unsigned reasons = sim_divergence(run_metrics(r, i), mc);
        if (reasons != 0u) {
            char why[96];
            sim_divergence_text(reasons, why, sizeof why);
            printf(" %llu (%s)", (unsigned long long)(r->runs > 1 ? r->per_run_seed[i] : r->seed), why);
            shown++;
        }
    }
    printf("%s\n", r->diverged_runs > shown ? " ..." : "");
}

/* One table of the metrics first..last - 1: a line per record, a single run's
 * values or the Monte-Carlo medians. */
static void print_metric_table(const run_record *records, int count, bool compare, int first, int last)
{
    const bool mc = records[0].runs > 1;
    printf("%-18s %-6s", compare ? "variant" : "controller", "numeric");
    for (int k = first; k < last; k++) {
        printf(" %10s", short_names[k]);
    }
    printf("\n");
    for (int i = 0; i < count; i++) {
        const run_record *r = &records[i];
        if (r->sc->figure == FIGURE_ACCEL_FEEDBACK) {
            /* the runs with and without the acceleration feedback */
            char label[64];
            snprintf(label, sizeof label, "%s k_a=%g", sim_variant_names[r->variant],
                     r->result.info.accel_fb_gain_per_s);
            printf("%-18s %-6s", label, r->backend);
        } else {
            printf("%-18s %-6s", sim_variant_names[r->variant], r->backend);
        }
        if (r->failed) {
            printf(" not run: %s\n", r->error);
            continue;
        }
        for (int k = first; k < last; k++) {
            print_value(mc ? r->stats[k].median : sim_metric_value(&r->result.metrics, k), scales[k]);
        }
        printf("\n");
    }
}

/* --compare --runs N: the figures the variants are compared by (rms error,
 * control total variation, Theta error), each as median and p95 over the
 * runs: the spread the median table above leaves out. */
static void print_compare_spread(const run_record *records, int count)
{
    static const int compared[] = {0, 3, 4}; /* rms_error_m, control_tv_per_s, theta_rel_error */
    printf("\nmedian and p95 over the runs\n%-18s %-6s", "variant", "numeric");
    for (unsigned c = 0u; c < sizeof compared / sizeof compared[0]; c++) {
        printf(" %10s %10s", short_names[compared[c]], "p95");
    }
    printf("\n");
    for (int i = 0; i < count; i++) {
        const run_record *r = &records[i];
        if (r->failed) {
            continue;
        }
        printf("%-18s %-6s", sim_variant_names[r->variant], r->backend);
        for (unsigned c = 0u; c < sizeof compared / sizeof compared[0]; c++) {
            const int k = compared[c];
            print_value(r->stats[k].median, scales[k]);
            print_value(r->stats[k].p95, scales[k]);
        }
        printf("\n");
    }
}

void output_print(const run_record *records, int count, bool compare)
{
    if (count == 0) {
        return;
    }
    const bool mc = records[0].runs > 1;
    printf("scenario %s (%s)%s\n", records[0].sc->name, records[0].sc->path,
           mc ? ": Monte-Carlo, median over the runs" : "");
    print_metric_table(records, count, compare, 0, SIM_METRIC_FAILSAFE_FIRST);
    bool failsafe = false;
    for (int i = 0; i < count; i++) {
        failsafe = failsafe || has_failsafe(&records[i]);
    }
    if (failsafe) {
        printf("failsafe:\n");
        print_metric_table(records, count, compare, SIM_METRIC_FAILSAFE_FIRST, SIM_METRIC_COUNT);
    }
    for (int i = 0; i < count && !mc; i++) {
        const sim_result *res = &records[i].result;
        if (records[i].failed || (records[i].sc->mission.command != MISSION_LAND && !has_failsafe(&records[i]))) {
            continue;
        }
        printf("landing (%s, %s): final %s, %d abort(s), touchdown window from %.3f s\n",
               sim_variant_names[records[i].variant], records[i].backend,
               sim_landing_state_names[res->final_landing_state], res->aborts, res->touchdown_planned_s);
        for (int e = 0; e < res->event_count; e++) {
            printf("  %8.3f s  %-10s %s\n", res->events[e].t_s, sim_landing_state_names[res->events[e].state],
                   sim_landing_reason_names[res->events[e].reason]);
        }
    }
    if (mc && compare) {
        print_compare_spread(records, count);
    }
    if (!mc || compare) {
        return;
    }
    for (int i = 0; i < count; i++) {
        const run_record *r = &records[i];
        if (r->failed) {
            continue;
        }
        printf("\n%s, %s: %d runs, seeds %llu..%llu\n", sim_variant_names[r->variant], r->backend, r->runs,
               (unsigned long long)r->seed, (unsigned long long)(r->seed + (uint64_t)r->runs - 1u));
        printf("%-32s %10s %10s %10s %10s %10s %10s %12s\n", "metric", "min", "median", "p90", "p95", "p99", "max",
               "worst seed");
        for (int k = 0; k < SIM_METRIC_COUNT; k++) {
            const metric_stats *s = &r->stats[k];
            printf("%-32s", sim_metric_names[k]);
            print_value(s->min, 1.0);
            print_value(s->median, 1.0);
            print_value(s->p90, 1.0);
            print_value(s->p95, 1.0);
            print_value(s->p99, 1.0);
            print_value(s->max, 1.0);
            if (s->count > 0) {
                printf(" %12llu\n", (unsigned long long)s->worst_seed);
            } else {
                printf(" %12s\n", "-");
            }
        }
        print_divergence(r);
    }
}

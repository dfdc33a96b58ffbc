/* sim.c - one flight: plant, sensors, flight software, metrics, trace (sim.h). */
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "plant.h"
#include "rng.h"
#include "sensors.h"

#define RAD2DEG (180.0 / 3.14159265358979323846)

const char *const sim_metric_names[SIM_METRIC_COUNT] = {
    "rms_error_m",      "max_abs_error_m",         "mass_step_peak_error_m", "control_tv_per_s",
    "theta_rel_error",  "min_clearance_m",         "touchdown_rel_speed_mps", "touchdown_time_s",
    "bounces",          "max_tilt_deg",            "nan_outputs",            "touchdown_rel_tilt_deg",
    "early_contact",    "thrust_saturated_s",
    "failsafe_entered", "failsafe_motor_stops_airborne", "failsafe_descent_rate_mps",
    "failsafe_descent_rate_rel_error", "failsafe_touchdown_speed_mps", "failsafe_time_to_motors_off_s",
};

double sim_metric_value(const sim_metrics *m, int index)
{
    switch (index) {
    case 0: return m->rms_error_m;
    case 1: return m->max_abs_error_m;
    case 2: return m->mass_step_peak_error_m;
    case 3: return m->control_tv_per_s;
    case 4: return m->theta_rel_error;
    case 5: return m->min_clearance_m;
    case 6: return m->touchdown_rel_speed_mps;
    case 7: return m->touchdown_time_s;
    case 8: return m->bounces;
    case 9: return m->max_tilt_deg;
    case 10: return m->nan_outputs;
    case 11: return m->touchdown_rel_tilt_deg;
    case 12: return m->early_contact;
    case 13: return m->thrust_saturated_s;
    case 14: return m->failsafe_entered;
    case 15: return m->failsafe_motor_stops_airborne;
    case 16: return m->failsafe_descent_rate_mps;
    case 17: return m->failsafe_descent_rate_rel_error;
    case 18: return m->failsafe_touchdown_speed_mps;
    case 19: return m->failsafe_time_to_motors_off_s;
    default: return (double)NAN;
    }
}

const char *const sim_trace_column_names[SIM_TRACE_COLUMN_COUNT] = {
#define SIM_TRACE_NAME(name) #name,
    SIM_TRACE_COLUMNS(SIM_TRACE_NAME)
#undef SIM_TRACE_NAME
};

const char *const sim_landing_state_names[FSW_LANDING_STATE_COUNT] = {
    "idle", "hold", "observe", "descend", "touchdown", "disarm", "landed", "abort", "failsafe",
};

const char *const sim_landing_reason_names[FSW_LANDING_REASON_COUNT] = {
    "none",         "commanded",        "hold-settled",      "pad-learnt",         "contact",
    "contact-lost", "contact-confirmed", "ramp-done",        "abort-commanded",    "abort-horizontal",
    "abort-tilt",   "abort-confidence", "abort-pad-accel",   "abort-range-lost",   "abort-climb-done",
    "retries-exhausted", "inputs-lost", "inputs-back",       "failsafe-landed",
};

double sim_reference(const fsw_info *info, double pad_z_m, double t_since_start_s)
{
    const double decay = t_since_start_s >= 0.0 ? exp(-t_since_start_s / info->ref_tau_s) : 1.0;
    return pad_z_m + info->ref_bias_m + info->ref_offset_init_m * decay;
}

void sim_trace_free(sim_trace *t)
{
    free(t->data);
    t->data = NULL;
    t->rows = t->capacity = 0;
}

static double clock_s(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double now_s(void)
{
    return clock_s(CLOCK_MONOTONIC);
}

static bool all_finite(const fsw_outputs *o)
{
    for (int i = 0; i < FSW_MAX_ROTORS; i++) {
        if (!isfinite(o->rotor_speed[i])) {
            return false;
        }
    }
    return isfinite(o->thrust_n) && isfinite(o->moment_nm[0]) && isfinite(o->moment_nm[1]) &&
           isfinite(o->moment_nm[2]) && isfinite(o->velocity_cmd_mps[0]) && isfinite(o->velocity_cmd_mps[1]) &&
           isfinite(o->velocity_cmd_mps[2]) && isfinite(o->yaw_rate_cmd_radps);
}

/* ---------------------------------------------------------------------- */
/* the failsafe's metrics                                                  */
/* ---------------------------------------------------------------------- */

/* A motor stop with the gear higher than this above the pad is in the air (SPEC's safety contract). */
#define AIRBORNE_GEAR_HEIGHT_M 0.05
/* The descent window: from this long after FAILSAFE began (the transition to the descent) ... */
#define DESCENT_WINDOW_START_S 1.0
/* ... until the gear first falls below the lower of this height and this share of its height at the start */
#define DESCENT_WINDOW_FLOOR_M 0.3
#define DESCENT_WINDOW_FLOOR_SHARE 0.2

typedef struct failsafe_acc {
    long airborne_stops;       /* the whole run's */
    bool motors_were_on;
    bool entered;
    double start_s;            /* when landing_state first became FAILSAFE */
    double floor_m;            /* the descent window's floor */
    bool window_closed;
    double *descent_mps;       /* -vz relative to the pad in the window, one per controller step (grown) */
    size_t descent_count, descent_capacity;
    double touchdown_speed_mps, motors_off_s;
} failsafe_acc;

static void failsafe_acc_init(failsafe_acc *f)
{
    memset(f, 0, sizeof *f);
    f->descent_mps = NULL;
    f->touchdown_speed_mps = f->motors_off_s = (double)NAN;
}

/* One sample of the descent window. Out of memory, the window closes early:
 * the median is then over its first samples. */
static void failsafe_acc_record(failsafe_acc *f, double descent_mps)
{
    if (f->descent_count == f->descent_capacity) {
        const size_t capacity = f->descent_capacity > 0 ? 2 * f->descent_capacity : 1024;
        double *grown = realloc(f->descent_mps, capacity * sizeof *grown);
        if (grown == NULL) {
            f->window_closed = true;
            return;
        }
        f->descent_mps = grown;
        f->descent_capacity = capacity;
    }
    f->descent_mps[f->descent_count++] = descent_mps;
}

/* Power-on: before the run's first step the firmware runs disarmed for
 * POWER_ON_S, or as long as its attitude filter needs to align if that is
 * longer, the vehicle held still in its attitude of t = 0: the IMU reads
 * gravity (not the thrust of a start in the air) and its biases, the
 * velocity 0, each with fresh white noise of the sensors' levels (a stream
 * of its own, so the flight's noise is the same with or without it); no
 * range sample, the heading once; the rest is the first samples. A vehicle powered on before its flight: a run
 * that starts armed (and in the air) is not refused, and the estimators
 * start from what a vehicle resting on its pad would have learnt (the
 * accelerometer's bias). */
#define POWER_ON_S 2.0

static void add_noise(rng *r, double *v, double std)
{
    for (int i = 0; i < 3; i++) {
        v[i] += std * rng_normal(r);
    }
}

static void set_v3(double *out, v3 v)
{
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}

static void power_on(const fsw_backend *backend, void *fsw, const scenario *sc, const plant *pl, const sensors *sens,
                     const fsw_inputs *first, int alignment_steps, double dt_s, fsw_outputs *out)
{
    const double scale = sc->sensors.noise_scale;
    double r[3][3];
    quat_to_matrix(pl->s.q, r);
    const v3 gravity_b = mat_apply_t(r, v3_make(0.0, 0.0, pl->p.gravity_mps2)); /* at rest: R^T (0, 0, g) */
    rng noise;
    rng_seed(&noise, sc->seed, 300);
    const int steps = (int)fmax((double)alignment_steps, ceil(POWER_ON_S / dt_s));
    for (int i = 0; i < steps; i++) {
        fsw_inputs idle = *first;
        idle.command = FSW_COMMAND_DISARM;
        set_v3(idle.gyro_radps, sens->gyro_bias);
        set_v3(idle.accel_mps2, v3_add(gravity_b, sens->accel_bias));
        set_v3(idle.velocity_mps, v3_make(0.0, 0.0, 0.0));
        idle.range_fresh = 0;   /* one frozen range sample would teach the pad model a still pad */
        idle.heading_fresh = i == 0 ? first->heading_fresh : 0;
        add_noise(&noise, idle.gyro_radps, scale * sc->sensors.imu.gyro_noise_radps);
        add_noise(&noise, idle.accel_mps2, scale * sc->sensors.imu.accel_noise_mps2);
        add_noise(&noise, idle.velocity_mps, scale * sc->sensors.position.velocity_noise_mps);
        backend->step(fsw, &idle, out);
    }
}

/* One controller step: the firmware's command and outputs, the plant's true
 * gear height and vertical speed against the pad, and whether it touches it. */
static void failsafe_acc_step(failsafe_acc *f, double t, int command, const fsw_outputs *out, double gear_m,
                              double rel_vz_mps, bool contact)
{
    if (f->motors_were_on && !out->motors_on && command != FSW_COMMAND_DISARM && gear_m > AIRBORNE_GEAR_HEIGHT_M) {
        f->airborne_stops++;
    }
    f->motors_were_on = out->motors_on != 0;
    if (!f->entered && out->landing_state == FSW_LANDING_FAILSAFE) {
        f->entered = true;
        f->start_s = t;
        f->floor_m = fmin(DESCENT_WINDOW_FLOOR_M, DESCENT_WINDOW_FLOOR_SHARE * gear_m);
    }
    if (!f->entered) {
        return;
    }
    if (isnan(f->motors_off_s) && !out->motors_on) {
        f->motors_off_s = t - f->start_s;
    }
    /* the window closes for good when the failsafe ends, the motors stop, or the gear reaches its floor */
    f->window_closed = f->window_closed || out->landing_state != FSW_LANDING_FAILSAFE || !out->motors_on ||
                       contact || gear_m < f->floor_m;
    if (!f->window_closed && t - f->start_s >= DESCENT_WINDOW_START_S) {
        failsafe_acc_record(f, -rel_vz_mps);
    }
}

/* After each plant step: the first contact once the failsafe began, at the
 * plant's rate (a controller step may see only the rebound of a hard impact). */
static void failsafe_acc_plant_step(failsafe_acc *f, const plant *pl)
{
    if (!f->entered || !isnan(f->touchdown_speed_mps) || !pl->p.contact) {
        return;
    }
    pad_state pad;
    if (plant_gear_clearance(pl, &pad) < 0.0) {
        f->touchdown_speed_mps = fabs(pl->s.v.z - pad.vz_mps);
    }
}

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The failsafe's metrics into m (NaN where they do not apply); frees the window's samples. */
static void failsafe_acc_finish(failsafe_acc *f, bool input_loss_injected, double descent_mps, sim_metrics *m)
{
    m->failsafe_entered = m->failsafe_motor_stops_airborne = m->failsafe_descent_rate_mps = (double)NAN;
    m->failsafe_descent_rate_rel_error = m->failsafe_touchdown_speed_mps = (double)NAN;
    m->failsafe_time_to_motors_off_s = (double)NAN;
    if (f->entered || input_loss_injected) {
        m->failsafe_entered = f->entered ? 1.0 : 0.0;
        m->failsafe_motor_stops_airborne = (double)f->airborne_stops;
        m->failsafe_touchdown_speed_mps = f->touchdown_speed_mps;
        m->failsafe_time_to_motors_off_s = f->motors_off_s;
    }
    if (f->descent_count > 0) {
        const size_t n = f->descent_count;
        qsort(f->descent_mps, n, sizeof *f->descent_mps, compare_double);
        const double median = n % 2 == 1 ? f->descent_mps[n / 2]
                                         : 0.5 * (f->descent_mps[n / 2 - 1] + f->descent_mps[n / 2]);
        m->failsafe_descent_rate_mps = median;
        m->failsafe_descent_rate_rel_error = fabs(median - descent_mps) / descent_mps;
    }
    free(f->descent_mps);
    f->descent_mps = NULL;
}

/* ---------------------------------------------------------------------- */
/* faults and inputs                                                       */
/* ---------------------------------------------------------------------- */

/* The fault starts at t_s: the pad's faults are set up in the plant (the
 * others act on the inputs while t_s <= t < t_s + duration_s). */
static void fault_arm(const fault_params *fault, plant *pl, double t_s)
{
    if (fault->kind == FAULT_PAD_PERIOD) {
        pl->p.pad.warp_start_s = t_s;
        pl->p.pad.warp_factor = fault->scale;
    }
    if (fault->kind == FAULT_PAD_AMPLITUDE) {
        pl->p.pad.growth_start_s = t_s;
        pl->p.pad.growth_duration_s = fault->duration_s;
        pl->p.pad.growth_scale = fault->scale;
    }
}

/* An input loss while its fault is active: the inputs become NaN. */
static void apply_input_loss(fault_kind kind, fsw_inputs *in)
{
    for (int i = 0; i < 3; i++) {
        if (kind == FAULT_POSITION_LOST) {
            in->position_m[i] = in->velocity_mps[i] = (double)NAN;
        } else if (kind == FAULT_IMU_LOST) {
            in->gyro_radps[i] = in->accel_mps2[i] = (double)NAN;
        }
    }
}

/* ---------------------------------------------------------------------- */
/* one flight                                                              */
/* ---------------------------------------------------------------------- */

/* abs(Theta - Theta*)/Theta* over the last THETA_WINDOW_S of flight, for
 * theta_rel_error (SPEC.md): a ring of samples, their 95th percentile at the
 * end (nearest rank). */
#define THETA_WINDOW_S 10.0

typedef struct theta_window {
    double *samples;
    long capacity, count, next;
} theta_window;

static bool theta_window_init(theta_window *w, double dt_s)
{
    w->capacity = (long)ceil(THETA_WINDOW_S / dt_s);
    w->count = w->next = 0;
    w->samples = malloc((size_t)w->capacity * sizeof(double));
    return w->samples != NULL;
}

static void theta_window_push(theta_window *w, double rel_error)
{
    w->samples[w->next] = rel_error;
    w->next = (w->next + 1) % w->capacity;
    w->count = w->count < w->capacity ? w->count + 1 : w->capacity;
}

static int compare_doubles(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The 95th percentile of the samples (sorts them); NaN without any. */
static double theta_window_p95(theta_window *w)
{
    if (w->count == 0) {
        return (double)NAN;
    }
    qsort(w->samples, (size_t)w->count, sizeof(double), compare_doubles);
    long rank = (long)ceil(0.95 * (double)w->count);
    rank = rank < 1 ? 1 : rank;
    return w->samples[rank - 1];
}

/* Metric accumulators. */
typedef struct acc {
    double sum_sq;
    long window;
    double max_abs;
    double mass_peak;
    bool mass_step_seen;
    double tv, last_u;
    bool have_last_u;
    double max_tilt;
    long nan_outputs;
    long saturated_steps; /* in the error window */
    double min_clearance;
    bool contact_ever, airborne_since_contact;
    double touchdown_time, touchdown_speed;
    /* the first contact at the plant's rate: a stiff contact is over within a
     * controller step, which then sees only its rebound */
    bool plant_contact_seen;
    double plant_touchdown_time, plant_touchdown_speed;
    double plant_touchdown_rel_tilt; /* deg */
    bool plant_touchdown_early;      /* before the touchdown window opened */
    long bounces;
    double max_position_error;
    double settled_position_error; /* after the transient */
    long nonfinite_state;
} acc;

bool sim_run(const scenario *sc, const sim_options *opt, sim_result *res, sim_trace *trace, char *err,
             size_t err_len)
{
    memset(res, 0, sizeof *res);
    const double t_start_wall = now_s();
    const double t_start_cpu = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    fsw_config cfg = sc->fsw;
    cfg.variant = opt->variant;
    fsw_info info;
    memset(&info, 0, sizeof info);
    void *fsw = opt->backend->create(&cfg, &info, err, err_len);
    if (fsw == NULL) {
        return false;
    }
    if (info.rotor_count != sc->plant.rotor_count) {
        snprintf(err, err_len, "the firmware airframe has %d rotors, the plant %d", info.rotor_count,
                 sc->plant.rotor_count);
        opt->backend->destroy(fsw);
        return false;
    }
    if (info.velocity_output != (sc->plant.velocity_input ? 1 : 0)) {
        snprintf(err, err_len, "the firmware outputs %s, the vehicle takes %s",
                 info.velocity_output ? "velocity commands" : "rotor speeds",
                 sc->plant.velocity_input ? "velocity commands ([vehicle] input)" : "rotor speeds");
        opt->backend->destroy(fsw);
        return false;
    }
    res->info = info;
    res->seed = sc->seed;

    const double dt = cfg.dt_s;
    const int substeps = (int)lround(sc->plant_rate_hz * dt);
    const double h = dt / substeps;
    const long steps = lround(sc->duration_s / dt);
    const mission_params *mission = &sc->mission;

    /* initial state: level (or as given) at the reference z_r(0) over the pad, at rest */
    pad_state pad0;
    pad_eval(&sc->plant.pad, 0.0, &pad0);
    const double z0 = isnan(sc->initial.height_m) ? sim_reference(&info, pad0.z_m, 0.0)
                                                   : pad0.z_m + sc->initial.height_m;
    plant_state s0;
    memset(&s0, 0, sizeof s0);
    s0.p = v3_make(sc->initial.x_m, sc->initial.y_m, z0);
    s0.v = sc->initial.velocity_mps;
    s0.q = quat_from_rpy(sc->initial.roll_rad, sc->initial.pitch_rad, sc->initial.yaw_rad);
    s0.m = sc->plant.mass_kg;
    plant pl;
    plant_init(&pl, &sc->plant, &s0);
    if (sc->initial.motors_hover) {
        const double u = plant_hover_speed(&pl);
        for (int i = 0; i < pl.p.rotor_count; i++) {
            pl.s.u[i] = u > 0.0 ? u : 1.0;
            pl.u_cmd[i] = pl.s.u[i];
        }
    }
    sensors sens;
    sensors_init(&sens, &sc->sensors, dt, sc->seed);

    if (trace != NULL && opt->want_trace) {
        trace->decimation = opt->trace_decimation > 0 ? opt->trace_decimation : 1;
        trace->capacity = (size_t)(steps / trace->decimation + 2);
        trace->rows = 0;
        trace->data = malloc(trace->capacity * SIM_TRACE_COLUMN_COUNT * sizeof(double));
        if (trace->data == NULL) {
            snprintf(err, err_len, "out of memory for the trace");
            opt->backend->destroy(fsw);
            return false;
        }
    }

    acc a;
    memset(&a, 0, sizeof a);
    a.min_clearance = (double)INFINITY;
    a.touchdown_time = a.touchdown_speed = (double)NAN;
    const double transient = isnan(sc->metrics.transient_s) ? 5.0 * info.ref_tau_s + 5.0 : sc->metrics.transient_s;
    const double window_after_step = sc->metrics.mass_step_window_s;
    const double planned = isnan(mission->touchdown_planned_s) ? (double)INFINITY : mission->touchdown_planned_s;
    double disarm_at = (double)INFINITY;
    double last_tilt_cos = 1.0;
    fsw_outputs out;
    memset(&out, 0, sizeof out);
    double last_theta = (double)NAN, last_theta_star = (double)NAN;
    theta_window theta_errors;
    if (!theta_window_init(&theta_errors, dt)) {
        snprintf(err, err_len, "out of memory for the Theta window");
        opt->backend->destroy(fsw);
        return false;
    }
    /* range freshness, wind, the fault (at start_s, or in a landing run from the first DESCEND) */
    const bool land = mission->command == MISSION_LAND;
    double last_range_t = (double)NAN;
    double last_heading_t = (double)NAN;
    double fault_at = (double)INFINITY;
    if (!isnan(sc->fault.start_s)) {
        fault_at = sc->fault.start_s;
        fault_arm(&sc->fault, &pl, fault_at);
    }
    const bool range_finder = sc->range_finder == RANGE_FINDER_ON || (sc->range_finder == RANGE_FINDER_AUTO && land);
    const bool input_loss = sc->fault.kind == FAULT_POSITION_LOST || sc->fault.kind == FAULT_IMU_LOST;
    failsafe_acc fs;
    failsafe_acc_init(&fs);
    double motors_off_at = (double)INFINITY;
    bool motors_ran = false;
    rng wind_rng;
    rng_seed(&wind_rng, sc->seed, 200);
    v3 gust = v3_make(0.0, 0.0, 0.0);
    const double gust_pole = exp(-dt / sc->wind.gust_tau_s);
    const double gust_drive = sc->wind.gust_std_mps * sqrt(1.0 - gust_pole * gust_pole);
    res->touchdown_planned_s = (double)NAN;
    double landed_at = (double)INFINITY;
    long steps_run = 0;

    for (long k = 0; k < steps; k++) {
        const double t = (double)k * dt;
        /* sensors due at t (the plant is at t) */
        sensors_sample(&sens, &pl, t);
        sensor_readout sr;
        sensors_read(&sens, t, &sr);
        pad_state pad;
        pad_eval(&pl.p.pad, t, &pad);

        fsw_inputs in;
        memset(&in, 0, sizeof in);
        in.gyro_radps[0] = sr.gyro_radps.x;
        in.gyro_radps[1] = sr.gyro_radps.y;
        in.gyro_radps[2] = sr.gyro_radps.z;
        in.accel_mps2[0] = sr.accel_mps2.x;
        in.accel_mps2[1] = sr.accel_mps2.y;
        in.accel_mps2[2] = sr.accel_mps2.z;
        in.attitude_q[0] = sr.attitude.w;
        in.attitude_q[1] = sr.attitude.x;
        in.attitude_q[2] = sr.attitude.y;
        in.attitude_q[3] = sr.attitude.z;
        in.heading_rad = sr.heading_rad;
        in.heading_fresh = sr.has_heading && sr.heading_sample_t != last_heading_t;
        last_heading_t = sr.has_heading ? sr.heading_sample_t : last_heading_t;
        in.position_m[0] = sr.position_m.x;
        in.position_m[1] = sr.position_m.y;
        in.position_m[2] = sr.position_m.z;
        const bool fault_active = t >= fault_at && t < fault_at + sc->fault.duration_s;
        if (range_finder) {
            /* the range finder to the pad (a landing mission's z comes from the position sensor) */
            in.range_m = sr.altitude_m;
            in.range_fresh = sr.altitude_sample_t != last_range_t;
            last_range_t = sr.altitude_sample_t;
            if (fault_active && sc->fault.kind == FAULT_RANGE_DROPOUT) {
                in.range_fresh = 0;
            }
        } else if (sc->range_finder == RANGE_FINDER_OFF) {
            in.range_m = (double)NAN; /* no range finder: never fresh */
        }
        if (!land && sr.has_altitude) {
            /* the platform's altitude: absolute, or the pad's height plus the
             * range projected on the vertical with the firmware's own k_h */
            in.position_m[2] = sr.altitude_is_range ? pad.z_m + sr.altitude_m * last_tilt_cos : sr.altitude_m;
        }
        /* wind: mean + Gauss-Markov gusts (horizontal) + a gust fault */
        gust.x = gust_pole * gust.x + gust_drive * rng_normal(&wind_rng);
        gust.y = gust_pole * gust.y + gust_drive * rng_normal(&wind_rng);
        pl.wind_mps = v3_add(sc->wind.mean_mps, gust);
        if (fault_active && sc->fault.kind == FAULT_GUST) {
            pl.wind_mps = v3_add(pl.wind_mps, sc->fault.vector);
        }
        pl.disturbance_moment_b =
            (fault_active && sc->fault.kind == FAULT_TORQUE) ? sc->fault.vector : v3_make(0.0, 0.0, 0.0);
        in.velocity_mps[0] = sr.velocity_mps.x;
        in.velocity_mps[1] = sr.velocity_mps.y;
        in.velocity_mps[2] = sr.velocity_mps.z;
        in.pad_z_m = pad.z_m;
        in.pad_vz_mps = pad.vz_mps;
        in.pad_az_mps2 = pad.az_mps2;
        in.position_setpoint_m[0] = mission->setpoint_x_m;
        in.position_setpoint_m[1] = mission->setpoint_y_m;
        const quat q_pad = pad_attitude(&pad);
        in.pad_attitude_q[0] = q_pad.w;
        in.pad_attitude_q[1] = q_pad.x;
        in.pad_attitude_q[2] = q_pad.y;
        in.pad_attitude_q[3] = q_pad.z;
        in.yaw_setpoint_rad = scenario_yaw_setpoint_rad(mission, t);
        in.yaw_rate_setpoint_radps = scenario_yaw_rate_setpoint_radps(mission, t);
        const int armed_command = !land ? FSW_COMMAND_TRACK_PAD
                                  : (sc->fault.kind == FAULT_HOLD_COMMAND && fault_active) ? FSW_COMMAND_HOLD
                                                                                           : FSW_COMMAND_LAND;
        in.command = (t + 1e-9 >= mission->track_start_s && t < disarm_at) ? armed_command : FSW_COMMAND_DISARM;
        if (fault_active) {
            apply_input_loss(sc->fault.kind, &in);
        }

        if (k == 0) {
            power_on(opt->backend, fsw, sc, &pl, &sens, &in, info.alignment_steps, dt, &out);
        }
        opt->backend->step(fsw, &in, &out);
        steps_run = k + 1;
        /* the firmware stopped its motors while armed: the run ends end_after_motors_off_s later */
        motors_ran = motors_ran || out.motors_on;
        const bool stopped_armed = motors_ran && !out.motors_on && in.command != FSW_COMMAND_DISARM;
        motors_off_at = stopped_armed ? fmin(motors_off_at, t) : (double)INFINITY;
        if (t >= motors_off_at + mission->end_after_motors_off_s) {
            break;
        }
        if (land && out.landing_state == FSW_LANDING_LANDED) {
            landed_at = fmin(landed_at, t);
            if (t >= landed_at + mission->end_after_landed_s) {
                break; /* motors off on the pad for long enough: nothing is left to measure */
            }
        } else {
            landed_at = (double)INFINITY;
        }
        if (out.landing_changed && res->event_count < SIM_MAX_EVENTS) {
            sim_event *ev = &res->events[res->event_count++];
            ev->t_s = t;
            ev->state = out.landing_state;
            ev->reason = out.landing_reason;
        }
        if (land && out.landing_state == FSW_LANDING_DESCEND && isinf(fault_at) && sc->fault.kind != FAULT_NONE) {
            fault_at = t + sc->fault.delay_s;
            fault_arm(&sc->fault, &pl, fault_at);
        }
        if (land && out.touchdown_window && !a.contact_ever && isnan(res->touchdown_planned_s)) {
            res->touchdown_planned_s = t;
        }
        res->final_landing_state = out.landing_state;
        res->aborts = out.aborts;
        res->descent_blocked_by = out.descent_blocked_by;
        last_tilt_cos = out.tilt_cos;
        if (!all_finite(&out)) {
            a.nan_outputs++;
        }
        if (pl.p.velocity_input) {
            plant_set_velocity_command(&pl,
                                       v3_make(out.velocity_cmd_mps[0], out.velocity_cmd_mps[1],
                                               out.velocity_cmd_mps[2]),
                                       out.yaw_rate_cmd_radps, out.motors_on && out.output_velocity);
        } else {
            plant_set_command(&pl, out.rotor_speed, out.rotor_count);
        }

        /* metrics at t_k */
        plant_diag d;
        plant_diagnose(&pl, &d);
        /* the reference flown: (3.6) on the true pad when tracking it, the firmware's own in a landing */
        const double z_r = land ? out.z_r_m : sim_reference(&info, pad.z_m, t - mission->track_start_s);
        const double e = pl.s.p.z - z_r;
        if (t >= transient && !(sc->metrics.error_until_contact && a.contact_ever)) {
            a.sum_sq += e * e;
            a.window++;
            const bool thrust_at_limit =
                out.clamped || (out.allocation_saturation & (FSW_SAT_THRUST_HIGH | FSW_SAT_THRUST_LOW)) != 0u;
            a.saturated_steps += thrust_at_limit;
            if (fabs(e) > a.max_abs) {
                a.max_abs = fabs(e);
            }
        }
        for (int j = 0; j < sc->plant.mass_step_count; j++) {
            const double ts = sc->plant.mass_step_time_s[j];
            if (t >= ts && t < ts + window_after_step) {
                a.mass_step_seen = true;
                if (fabs(e) > a.mass_peak) {
                    a.mass_peak = fabs(e);
                }
            }
        }
        const double u = out.thrust_n;
        if (a.have_last_u) {
            a.tv += fabs(u - a.last_u);
        }
        a.last_u = u;
        a.have_last_u = true;
        const double r33 = 1.0 - 2.0 * (pl.s.q.x * pl.s.q.x + pl.s.q.y * pl.s.q.y);
        const double tilt = acos(r33 > 1.0 ? 1.0 : (r33 < -1.0 ? -1.0 : r33)) * RAD2DEG;
        if (tilt > a.max_tilt) {
            a.max_tilt = tilt;
        }
        /* for the divergence test of Monte-Carlo runs (sim_divergence) */
        const double position_error = hypot(pl.s.p.x - mission->setpoint_x_m, pl.s.p.y - mission->setpoint_y_m);
        a.max_position_error = position_error > a.max_position_error ? position_error : a.max_position_error;
        if (t >= transient && position_error > a.settled_position_error) {
            a.settled_position_error = position_error;
        }
        if (!isfinite(position_error + pl.s.p.z + pl.s.v.x + pl.s.v.y + pl.s.v.z + r33)) {
            a.nonfinite_state++;
        }
        /* before the planned touchdown (a contact earlier shows as its depth, a
         * collision); with no plan, before the first contact */
        const bool before_plan = land ? (!a.contact_ever && !out.touchdown_window)
                                      : (t < planned && (isfinite(planned) || !a.contact_ever));
        if (before_plan && d.gear_clearance_m < a.min_clearance) {
            a.min_clearance = d.gear_clearance_m;
        }
        const bool contact = sc->plant.contact && d.feet_in_contact > 0;
        if (contact && !a.contact_ever) {
            a.contact_ever = true;
            a.touchdown_time = t;
            a.touchdown_speed = fabs(pl.s.v.z - pad.vz_mps);
            if (mission->disarm_on_contact) {
                disarm_at = t + mission->disarm_delay_s;
            }
        } else if (contact && a.airborne_since_contact) {
            a.bounces++;
            a.airborne_since_contact = false;
        } else if (!contact && a.contact_ever && d.gear_clearance_m > sc->metrics.bounce_height_m) {
            a.airborne_since_contact = true;
        }
        failsafe_acc_step(&fs, t, in.command, &out, d.gear_clearance_m, pl.s.v.z - pad.vz_mps, contact);
        const double k_h = r33;
        const double theta_star = pl.s.m / (k_h * d.ground_gain);
        if (out.motors_on) {
            /* Theta against Theta* at the end of the flight (a landing run: the last armed step) */
            last_theta = out.theta_kg;
            last_theta_star = theta_star;
            /* theta_rel_error: in flight only; on the pad Theta* is the ground's, not the airframe's */
            if (!a.contact_ever) {
                theta_window_push(&theta_errors, fabs(out.theta_kg - theta_star) / theta_star);
            }
        }

        if (trace != NULL && opt->want_trace && k % trace->decimation == 0 && trace->rows < trace->capacity) {
            double *row = trace->data + trace->rows * SIM_TRACE_COLUMN_COUNT;
            double roll, pitch, yaw;
            quat_to_rpy(pl.s.q, &roll, &pitch, &yaw);
            double umin = 1.0, umax = 0.0, usum = 0.0, thrust_sum = 0.0;
            for (int i = 0; i < pl.p.rotor_count; i++) {
                usum += pl.s.u[i];
                umin = pl.s.u[i] < umin ? pl.s.u[i] : umin;
                umax = pl.s.u[i] > umax ? pl.s.u[i] : umax;
                thrust_sum += d.rotor_thrust_n[i];
            }
            /* Figure 4.3(b): (Theta - Theta*)/Theta* phi, phi = u_nom / Theta as the law used it */
            const double phi = fabs(out.theta_kg) > 1e-9 ? out.u_nom_n / out.theta_kg : 0.0;
            row[SIM_COL_t_s] = t;
            row[SIM_COL_pad_z_m] = pad.z_m;
            row[SIM_COL_pad_vz_mps] = pad.vz_mps;
            row[SIM_COL_z_r_m] = z_r;
            row[SIM_COL_z_m] = pl.s.p.z;
            row[SIM_COL_vz_mps] = pl.s.v.z;
            row[SIM_COL_error_m] = e;
            row[SIM_COL_x_m] = pl.s.p.x;
            row[SIM_COL_y_m] = pl.s.p.y;
            row[SIM_COL_roll_deg] = roll * RAD2DEG;
            row[SIM_COL_pitch_deg] = pitch * RAD2DEG;
            row[SIM_COL_yaw_deg] = yaw * RAD2DEG;
            row[SIM_COL_tilt_deg] = tilt;
            row[SIM_COL_thrust_cmd_n] = out.thrust_n;
            row[SIM_COL_vertical_force_n] = out.vertical_force_n;
            row[SIM_COL_u_nom_n] = out.u_nom_n;
            row[SIM_COL_u0_av_n] = out.u0_av_n;
            row[SIM_COL_rho_n] = out.rho_n;
            row[SIM_COL_sigma_mps] = out.sigma_mps;
            row[SIM_COL_sigma_tilde_mps] = out.sigma_tilde_mps;
            row[SIM_COL_theta_kg] = out.theta_kg;
            row[SIM_COL_theta_star_kg] = theta_star;
            row[SIM_COL_adaptation_term_mps2] = (out.theta_kg - theta_star) / theta_star * phi;
            row[SIM_COL_ground_gain] = d.ground_gain;
            row[SIM_COL_mass_kg] = pl.s.m;
            row[SIM_COL_gear_clearance_m] = d.gear_clearance_m;
            row[SIM_COL_contact_force_n] = d.contact_force_w.z;
            row[SIM_COL_rotor_thrust_n] = thrust_sum;
            row[SIM_COL_fsw_z_r_m] = out.z_r_m;
            row[SIM_COL_u_mean] = usum / pl.p.rotor_count;
            row[SIM_COL_u_min] = umin;
            row[SIM_COL_u_max] = umax;
            row[SIM_COL_motors_on] = out.motors_on;
            row[SIM_COL_status] = out.status;
            row[SIM_COL_landing_state] = out.landing_state;
            row[SIM_COL_fsw_gear_height_m] = out.gear_height_m;
            row[SIM_COL_fsw_pad_z_m] = out.pad_est_z_m;
            row[SIM_COL_fsw_pad_vz_mps] = out.pad_est_vz_mps;
            row[SIM_COL_pad_confidence] = out.pad_confidence;
            row[SIM_COL_fsw_pad_period_s] = out.pad_period_s;
            row[SIM_COL_fsw_vz_est_mps] = out.vz_est_mps;
            row[SIM_COL_fsw_hover_thrust_n] = out.hover_thrust_n;
            row[SIM_COL_fsw_accel_bias_mps2] = out.accel_bias_mps2;
            row[SIM_COL_land_state] = out.land_state;
            row[SIM_COL_failsafe_cause] = out.failsafe_cause;
            row[SIM_COL_moment_x_nm] = out.moment_nm[0];
            row[SIM_COL_moment_y_nm] = out.moment_nm[1];
            row[SIM_COL_moment_z_nm] = out.moment_nm[2];
            row[SIM_COL_saturation] = out.allocation_saturation;
            row[SIM_COL_att_err_x_rad] = out.attitude_error_rad[0];
            row[SIM_COL_att_err_y_rad] = out.attitude_error_rad[1];
            row[SIM_COL_att_err_z_rad] = out.attitude_error_rad[2];
            row[SIM_COL_att_int_x_rad_s] = out.attitude_integral_rad_s[0];
            row[SIM_COL_att_int_y_rad_s] = out.attitude_integral_rad_s[1];
            row[SIM_COL_att_int_z_rad_s] = out.attitude_integral_rad_s[2];
            row[SIM_COL_pos_int_x_mps2] = out.position_integral_mps2[0];
            row[SIM_COL_pos_int_y_mps2] = out.position_integral_mps2[1];
            row[SIM_COL_accel_fb_x_mps2] = out.accel_feedback_mps2[0];
            row[SIM_COL_accel_fb_y_mps2] = out.accel_feedback_mps2[1];
            row[SIM_COL_yaw_r_deg] = scenario_yaw_setpoint_rad(mission, t) * RAD2DEG;
            row[SIM_COL_k_h] = k_h;
            row[SIM_COL_velocity_cmd_x_mps] = out.velocity_cmd_mps[0];
            row[SIM_COL_velocity_cmd_y_mps] = out.velocity_cmd_mps[1];
            row[SIM_COL_velocity_cmd_z_mps] = out.velocity_cmd_mps[2];
            row[SIM_COL_yaw_rate_cmd_radps] = out.yaw_rate_cmd_radps;
            row[SIM_COL_pad_roll_deg] = pad.roll_rad * RAD2DEG;
            row[SIM_COL_pad_pitch_deg] = pad.pitch_rad * RAD2DEG;
            row[SIM_COL_descent_shaping_mps] = out.descent_shaping_mps;
            trace->rows++;
        }

        /* the plant over one controller step */
        for (int j = 0; j < substeps; j++) {
            if (j > 0) {
                sensors_sample(&sens, &pl, t + j * h);
            }
            plant_step(&pl, h);
            failsafe_acc_plant_step(&fs, &pl);
            if (sc->plant.contact && !a.plant_contact_seen) {
                pad_state pad_now;
                if (plant_gear_clearance(&pl, &pad_now) < 0.0) {
                    a.plant_contact_seen = true;
                    a.plant_touchdown_time = pl.t;
                    a.plant_touchdown_speed = fabs(pl.s.v.z - pad_now.vz_mps);
                    double rm[3][3];
                    quat_to_matrix(pl.s.q, rm);
                    const double c = v3_dot(v3_make(rm[0][2], rm[1][2], rm[2][2]), pad_normal(&pad_now));
                    a.plant_touchdown_rel_tilt = acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c)) * RAD2DEG;
                    a.plant_touchdown_early = land && isnan(res->touchdown_planned_s);
                }
            }
        }
        /* no drift of the plant's clock (the pad cached at the step's end moves with it) */
        const double t_next = (double)(k + 1) * dt;
        if (pl.pad_cache_t == pl.t) {
            pl.pad_cache_t = t_next;
        }
        pl.t = t_next;
        if (opt->progress != NULL && (k & 1023) == 0) {
            opt->progress((double)k / (double)steps, opt->progress_user);
        }
    }
    opt->backend->destroy(fsw);

    sim_metrics *m = &res->metrics;
    m->rms_error_m = a.window > 0 ? sqrt(a.sum_sq / (double)a.window) : (double)NAN;
    m->max_abs_error_m = a.window > 0 ? a.max_abs : (double)NAN;
    m->mass_step_peak_error_m = a.mass_step_seen ? a.mass_peak : (double)NAN;
    m->control_tv_per_s = a.tv / ((double)steps_run * dt);
    m->thrust_saturated_s = a.window > 0 ? (double)a.saturated_steps * dt : (double)NAN;
    m->theta_end_kg = last_theta;
    m->theta_star_end_kg = last_theta_star;
    m->theta_rel_error = sim_variant_is_adaptive(opt->variant) ? theta_window_p95(&theta_errors) : (double)NAN;
    free(theta_errors.samples);
    const bool landing = mission->landing;
    m->min_clearance_m = landing ? a.min_clearance : (double)NAN;
    m->touchdown_rel_speed_mps =
        landing ? (a.plant_contact_seen ? a.plant_touchdown_speed : a.touchdown_speed) : (double)NAN;
    m->touchdown_time_s = landing ? (a.plant_contact_seen ? a.plant_touchdown_time : a.touchdown_time) : (double)NAN;
    m->bounces = landing && a.contact_ever ? (double)a.bounces : (landing ? 0.0 : (double)NAN);
    m->max_tilt_deg = a.max_tilt;
    m->nan_outputs = (double)a.nan_outputs;
    m->touchdown_rel_tilt_deg = landing && a.plant_contact_seen ? a.plant_touchdown_rel_tilt : (double)NAN;
    m->early_contact = landing ? (a.plant_contact_seen && a.plant_touchdown_early ? 1.0 : 0.0) : (double)NAN;
    plant_diag d;
    plant_diagnose(&pl, &d);
    m->final_height_m = d.gear_clearance_m;
    m->max_position_error_m = a.max_position_error;
    m->settled_position_error_m = a.settled_position_error;
    m->nonfinite_state_steps = (double)a.nonfinite_state;
    failsafe_acc_finish(&fs, input_loss, info.failsafe_descent_mps, m);
    res->controller_steps = steps_run;
    res->plant_steps = steps_run * substeps;
    res->wall_s = now_s() - t_start_wall;
    res->cpu_s = clock_s(CLOCK_PROCESS_CPUTIME_ID) - t_start_cpu;
    if (opt->progress != NULL) {
        opt->progress(1.0, opt->progress_user);
    }
    return true;
}

/*
 * fsw_adapter.c - plain doubles <-> fc_controller_inputs / fc_controller_outputs.
 *
 * Compiled once per numeric backend (FC_NUMERIC_FIXED = 0 or 1) and partially
 * linked with that backend's firmware objects; the only global symbol left is
 * the table fsw_<FSW_BACKEND>_backend (sim_host/CMakeLists.txt). It calls the
 * firmware's entry point and nothing deeper: fc_controller_default_params,
 * fc_controller_init, fc_controller_step, and the conversions of fc/scalar.h.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fc/controller.h"
#include "fsw_adapter.h"
#include "pil_wire.h" /* tools/pil: the PIL wire, shared with the ATmega image */

#ifndef FSW_BACKEND
#error "FSW_BACKEND (float or fixed) must be defined"
#endif
#define FSW_CAT3(a, b, c) a##b##c
#define FSW_NAME(a, b, c) FSW_CAT3(a, b, c)
#define FSW_STR2(x) #x
#define FSW_STR(x) FSW_STR2(x)
#define FSW_TABLE FSW_NAME(fsw_, FSW_BACKEND, _backend)

_Static_assert(FSW_MAX_ROTORS == FC_MAX_ROTORS, "rotor count bound differs from the firmware's");
_Static_assert(FSW_VARIANT_COUNT == (int)FC_ALT_VARIANT_COUNT, "variant list differs from the firmware's");
_Static_assert(FSW_AIRFRAME_COUNT == (int)FC_AIRFRAME_COUNT, "airframe list differs from the firmware's");
_Static_assert(FSW_AIRFRAME_HEXA_4KG == (int)FC_AIRFRAME_HEXA_4KG, "airframe numbering differs");
_Static_assert(FSW_COMMAND_TRACK_PAD == (int)FC_COMMAND_TRACK_PAD, "command numbering differs");
_Static_assert(FSW_COMMAND_LAND == (int)FC_COMMAND_LAND && FSW_COMMAND_HOLD == (int)FC_COMMAND_HOLD,
               "command numbering differs");
_Static_assert(FSW_SAT_THRUST_HIGH == FC_SAT_THRUST_HIGH && FSW_SAT_THRUST_LOW == FC_SAT_THRUST_LOW,
               "saturation bits differ");
_Static_assert(FSW_LANDING_STATE_COUNT == (int)FC_LANDING_STATE_COUNT, "landing states differ");
_Static_assert(FSW_LANDING_REASON_COUNT == (int)FC_REASON_COUNT, "landing reasons differ");
_Static_assert(FSW_LANDING_DESCEND == (int)FC_LANDING_DESCEND && FSW_LANDING_ABORT == (int)FC_LANDING_ABORT &&
                   FSW_LANDING_FAILSAFE == (int)FC_LANDING_FAILSAFE,
               "landing state numbering differs");

/* A double in the firmware's number type. The fixed backend holds no NaN
 * (fc_from_float makes it 0, a plausible value): a NaN input, a lost one,
 * arrives as the format's largest value, outside every physical range. */
static fc_real real_of(double x, int frac)
{
#if FC_NUMERIC_FIXED
    if (isnan(x)) {
        return FC_REAL_MAX;
    }
#endif
    return fc_from_float((float)x, frac);
}

#define TO_FC(x, KIND) real_of((x), FC_##KIND##_FRAC)
#define FROM_FC(x, KIND) ((double)fc_to_float((x), FC_##KIND##_FRAC))

static void override(fc_real *field, double value, int frac)
{
    if (!isnan(value)) {
        *field = fc_from_float((float)value, frac);
    }
}

static void scale(fc_real *field, double factor, int frac)
{
    if (!isnan(factor)) {
        *field = fc_from_float((float)((double)fc_to_float(*field, frac) * factor), frac);
    }
}

static fc_vec3 vec_to_fc(const double v[3], int frac);

/* The tuning knobs (sim_host/README.md, "Tuning the variants"), one pair for
 * every law: bandwidth multiplies the gains that set how fast the error
 * decays (l0 of the sliding surface; the pid's position loop), authority those
 * that set the force spent on it (a constant rho; the design margins delta and
 * k0 that a norm-observer or extra modulation adds to its computed bound; the
 * super-twisting's k1 sqrt(s) and k2 s, a Lipschitz bound scaled by s; the
 * pid's velocity loop). NaN: 1. */
static void scale_law_gains(fc_altitude_control_params *a, double bandwidth, double authority)
{
    if (a->law == FC_ALT_LAW_PID) {
        scale(&a->pid_kp_z_per_s, bandwidth, FC_GAIN_FRAC);
        scale(&a->pid_ki_z_per_s2, bandwidth, FC_GAIN_FRAC);
        scale(&a->pid_kp_v_n_per_mps, authority, FC_GAIN_FRAC);
        scale(&a->pid_ki_v_n_per_m, authority, FC_GAIN_FRAC);
        return;
    }
    scale(&a->l0_per_s, bandwidth, FC_GAIN_FRAC);
    if (a->law == FC_ALT_LAW_SUPER_TWISTING) {
        scale(&a->stw_k1, sqrt(authority), FC_GAIN_FRAC);
        scale(&a->stw_k2_nps, authority, FC_GAIN_FRAC);
    } else if (a->law == FC_ALT_LAW_SSC && a->modulation != FC_SSC_MODULATION_CONSTANT) {
        scale(&a->delta_n, authority, FC_FORCE_FRAC);
        scale(&a->k0_ns_per_m, authority, FC_GAIN_FRAC);
    } else {
        scale(&a->rho_n, authority, FC_FORCE_FRAC);
    }
}

/* The firmware's parameters for cfg: its defaults, then the overrides. A
 * field overridden here must also be in the PIL wire's listing
 * (tools/pil/pil_wire.c), which carries it to the ATmega image. */
static bool params_of_config(const fsw_config *cfg, fc_controller_params *out, char *err, size_t err_len)
{
    if (cfg->airframe < 0 || cfg->airframe >= (int)FC_AIRFRAME_COUNT || cfg->variant < 0 ||
        cfg->variant >= (int)FC_ALT_VARIANT_COUNT || !(cfg->dt_s > 0.0)) {
        snprintf(err, err_len, "bad airframe, variant or step");
        return false;
    }
    fc_controller_params p;
    fc_controller_default_params(&p, (fc_airframe)cfg->airframe, (fc_altitude_variant)cfg->variant,
                                 TO_FC(cfg->dt_s, DT));
    if (cfg->use_external_attitude >= 0) {
        p.use_external_attitude = cfg->use_external_attitude != 0;
    }
    if (!isnan(cfg->mass_kg)) {
        /* nominal mass: what follows it follows it (fc_controller_set_mass) */
        fc_controller_set_mass(&p, TO_FC(cfg->mass_kg, MASS));
    }
    override(&p.reference.tau_s, cfg->ref_tau_s, FC_TIME_FRAC);
    override(&p.reference.offset_init_m, cfg->ref_offset_init_m, FC_LENGTH_FRAC);
    override(&p.reference.bias_m, cfg->ref_bias_m, FC_LENGTH_FRAC);
    override(&p.altitude.thrust_min_n, cfg->thrust_min_n, FC_FORCE_FRAC);
    override(&p.altitude.thrust_max_n, cfg->thrust_max_n, FC_FORCE_FRAC);
    override(&p.altitude.ground_gain_max, cfg->ground_gain_max, FC_RATIO_FRAC);
    scale(&p.altitude.rho_n, cfg->rho_scale, FC_FORCE_FRAC);
    scale(&p.altitude.gamma, cfg->gamma_scale, FC_GAIN_FRAC);
    scale(&p.altitude.kappa_m_per_kg, cfg->kappa_m_scale, FC_GAIN_FRAC);
    scale_law_gains(&p.altitude, cfg->bandwidth_scale, cfg->authority_scale);
    override(&p.altitude.rho_n, cfg->rho_n, FC_FORCE_FRAC);
    override(&p.altitude.gamma, cfg->gamma, FC_GAIN_FRAC);
    override(&p.altitude.actuator_lag_s, cfg->actuator_lag_s, FC_DT_FRAC);
    override(&p.altitude.tau_av_s, cfg->tau_av_s, FC_DT_FRAC);
    override(&p.altitude.l0_per_s, cfg->l0_per_s, FC_GAIN_FRAC);
    override(&p.altitude.a_m_per_s, cfg->a_m_per_s, FC_GAIN_FRAC);
    override(&p.altitude.kappa_m_per_kg, cfg->kappa_m_per_kg, FC_GAIN_FRAC);
    override(&p.horizontal.kp_per_s2, cfg->horizontal_kp_per_s2, FC_RATIO_FRAC);
    override(&p.horizontal.kd_per_s, cfg->horizontal_kd_per_s, FC_RATIO_FRAC);
    override(&p.horizontal.tilt_max_rad, cfg->tilt_max_rad, FC_ANGLE_FRAC);
    override(&p.horizontal.accel_fb_gain_per_s, cfg->accel_fb_gain_per_s, FC_RATIO_FRAC);
    override(&p.altitude.pid_kp_z_per_s, cfg->pid_kp_z_per_s, FC_GAIN_FRAC);
    override(&p.altitude.pid_ki_z_per_s2, cfg->pid_ki_z_per_s2, FC_GAIN_FRAC);
    override(&p.altitude.pid_kp_v_n_per_mps, cfg->pid_kp_v_n_per_mps, FC_GAIN_FRAC);
    override(&p.altitude.pid_ki_v_n_per_m, cfg->pid_ki_v_n_per_m, FC_GAIN_FRAC);
    override(&p.landing.gear_height_m, cfg->landing_gear_height_m, FC_LENGTH_FRAC);
    override(&p.landing.touchdown_dip_m, cfg->landing_touchdown_dip_m, FC_LENGTH_FRAC);
    override(&p.landing.hold_height_m, cfg->landing_hold_height_m, FC_LENGTH_FRAC);
    override(&p.landing.descent_tau_s, cfg->landing_descent_tau_s, FC_TIME_FRAC);
    override(&p.landing.pad_accel_max_mps2, cfg->landing_pad_accel_max_mps2, FC_ACCEL_FRAC);
    override(&p.landing.confidence_start, cfg->landing_confidence_start, FC_UNIT_FRAC);
    if (cfg->descent_shaping >= 0) {
        p.landing.descent_shaping = cfg->descent_shaping == 1;
    }
    override(&p.landing.shaping.k_r_m2ps, cfg->shaping_k_r_m2ps, FC_GAIN_FRAC);
    override(&p.landing.shaping.delta_h_m, cfg->shaping_delta_h_m, FC_LENGTH_FRAC);
    override(&p.landing.shaping.k_c_per_s, cfg->shaping_k_c_per_s, FC_GAIN_FRAC);
    override(&p.landing.shaping.u_zbias_mps, cfg->shaping_u_zbias_mps, FC_VEL_FRAC);
    override(&p.landing.shaping.k_a_mps, cfg->shaping_k_a_mps, FC_GAIN_FRAC);
    override(&p.landing.shaping.delta_a_m, cfg->shaping_delta_a_m, FC_LENGTH_FRAC);
    override(&p.landing.shaping.max_climb_mps, cfg->shaping_max_climb_mps, FC_VEL_FRAC);
    override(&p.landing.shaping_commit_m, cfg->shaping_commit_m, FC_LENGTH_FRAC);
    if (cfg->velocity_output == 1) {
        fc_velocity_output_params v;
        fc_controller_velocity_defaults(&v, vec_to_fc(cfg->velocity_k_p_per_s, FC_RATIO_FRAC),
                                        vec_to_fc(cfg->velocity_a_p_per_s, FC_RATIO_FRAC));
        fc_controller_set_velocity_output(&p, &v);
    }
    *out = p;
    return true;
}

static bool init_succeeded(fc_init_result r, char *err, size_t err_len)
{
    static const char *const why[] = {"", "a parameter out of range", "rank-deficient rotor geometry",
                                      "the modules' g differ", "the modules' nominal masses differ",
                                      "maximum thrust under 1.5 x the weight",
                                      "maximum thrust above what the rotors give"};
    if (r != FC_INIT_OK) {
        const unsigned i = (unsigned)r < sizeof why / sizeof why[0] ? (unsigned)r : 1u;
        snprintf(err, err_len, "fc_controller_init failed (%s)", why[i]);
    }
    return r == FC_INIT_OK;
}

/* What the simulator is told of the configuration. */
static void info_of(const fc_controller_params *params, fsw_info *info)
{
    if (info != NULL) {
        info->mass_kg = FROM_FC(params->mass_kg, MASS);
        info->theta0_kg = FROM_FC(params->altitude.theta0_kg, MASS);
        /* the projection bounds of Theta (4.15): [m_min / k_g_max, m_max] */
        info->theta_min_kg =
            FROM_FC(params->altitude.mass_min_kg, MASS) / FROM_FC(params->altitude.ground_gain_max, RATIO);
        info->theta_max_kg = FROM_FC(params->altitude.mass_max_kg, MASS);
        info->thrust_min_n = FROM_FC(params->altitude.thrust_min_n, FORCE);
        info->thrust_max_n = FROM_FC(params->altitude.thrust_max_n, FORCE);
        info->ground_gain_max = FROM_FC(params->altitude.ground_gain_max, RATIO);
        info->ref_tau_s = FROM_FC(params->reference.tau_s, TIME);
        info->ref_offset_init_m = FROM_FC(params->reference.offset_init_m, LENGTH);
        info->ref_bias_m = FROM_FC(params->reference.bias_m, LENGTH);
        info->rho_n = FROM_FC(params->altitude.rho_n, FORCE);
        info->gamma = FROM_FC(params->altitude.gamma, GAIN);
        info->accel_fb_gain_per_s = FROM_FC(params->horizontal.accel_fb_gain_per_s, RATIO);
        info->failsafe_descent_mps = FROM_FC(params->failsafe.descent_mps, VEL);
        info->alignment_steps = (int)params->estimator.alignment_samples;
        info->rotor_count = params->allocation.rotor_count;
        info->velocity_output = params->output == FC_OUTPUT_VELOCITY ? 1 : 0;
        info->state_bytes = sizeof(fc_controller);
    }
}

static void *adapter_create(const fsw_config *cfg, fsw_info *info, char *err, size_t err_len)
{
    fc_controller_params p;
    if (!params_of_config(cfg, &p, err, err_len)) {
        return NULL;
    }
    fc_controller *ctl = malloc(sizeof *ctl);
    if (ctl == NULL) {
        snprintf(err, err_len, "out of memory");
        return NULL;
    }
    if (!init_succeeded(fc_controller_init(ctl, &p), err, err_len)) {
        free(ctl);
        return NULL;
    }
    info_of(&p, info);
    return ctl;
}

static void adapter_destroy(void *ctl)
{
    free(ctl);
}

static fc_vec3 vec_to_fc(const double v[3], int frac)
{
    return fc_vec3_make(real_of(v[0], frac), real_of(v[1], frac), real_of(v[2], frac));
}

static void vec_from_fc(fc_vec3 v, int frac, double out[3])
{
    out[0] = (double)fc_to_float(v.x, frac);
    out[1] = (double)fc_to_float(v.y, frac);
    out[2] = (double)fc_to_float(v.z, frac);
}

static void quat_from_fc(fc_quat q, double out[4])
{
    out[0] = FROM_FC(q.w, UNIT);
    out[1] = FROM_FC(q.x, UNIT);
    out[2] = FROM_FC(q.y, UNIT);
    out[3] = FROM_FC(q.z, UNIT);
}

static fc_controller_inputs inputs_of(const fsw_inputs *in)
{
    fc_controller_inputs fin;
    fin.imu.gyro_radps = vec_to_fc(in->gyro_radps, FC_RATE_FRAC);
    fin.imu.accel_mps2 = vec_to_fc(in->accel_mps2, FC_ACCEL_FRAC);
    fin.attitude_external.w = TO_FC(in->attitude_q[0], UNIT);
    fin.attitude_external.x = TO_FC(in->attitude_q[1], UNIT);
    fin.attitude_external.y = TO_FC(in->attitude_q[2], UNIT);
    fin.attitude_external.z = TO_FC(in->attitude_q[3], UNIT);
    fin.heading_rad = TO_FC(in->heading_rad, ANGLE);
    fin.heading_fresh = in->heading_fresh != 0;
    fin.position_m = vec_to_fc(in->position_m, FC_LENGTH_FRAC);
    fin.velocity_mps = vec_to_fc(in->velocity_mps, FC_VEL_FRAC);
    fin.pad.z_m = TO_FC(in->pad_z_m, LENGTH);
    fin.pad.vz_mps = TO_FC(in->pad_vz_mps, VEL);
    fin.pad.az_mps2 = TO_FC(in->pad_az_mps2, ACCEL);
    fin.range_m = TO_FC(in->range_m, LENGTH);
    fin.range_fresh = in->range_fresh != 0;
    fin.position_setpoint_m = vec_to_fc(in->position_setpoint_m, FC_LENGTH_FRAC);
    fin.pad_attitude.w = TO_FC(in->pad_attitude_q[0], UNIT);
    fin.pad_attitude.x = TO_FC(in->pad_attitude_q[1], UNIT);
    fin.pad_attitude.y = TO_FC(in->pad_attitude_q[2], UNIT);
    fin.pad_attitude.z = TO_FC(in->pad_attitude_q[3], UNIT);
    fin.yaw_setpoint_rad = TO_FC(in->yaw_setpoint_rad, ANGLE);
    fin.yaw_rate_setpoint_radps = TO_FC(in->yaw_rate_setpoint_radps, RATE);
    fin.command = (in->command >= 0 && in->command < (int)FC_COMMAND_COUNT) ? (fc_controller_command)in->command
                                                                           : FC_COMMAND_DISARM;
    return fin;
}

/* The step's outputs and telemetry, and the loop internals the trace shows, as doubles. */
static void outputs_of(fc_step_status status, const fc_controller_outputs *fo, const pil_internals *internals,
                       fsw_outputs *out)
{
    out->status = status;
    for (int i = 0; i < FSW_MAX_ROTORS; i++) {
        out->rotor_speed[i] = FROM_FC(fo->rotor_speed[i], UNIT);
    }
    out->rotor_count = fo->rotor_count;
    out->motors_on = fo->motors_on ? 1 : 0;
    out->thrust_n = FROM_FC(fo->thrust_n, FORCE);
    vec_from_fc(fo->moment_nm, FC_MOMENT_FRAC, out->moment_nm);
    out->output_velocity = fo->output == FC_OUTPUT_VELOCITY ? 1 : 0;
    vec_from_fc(fo->velocity_cmd_mps, FC_VEL_FRAC, out->velocity_cmd_mps);
    out->yaw_rate_cmd_radps = FROM_FC(fo->yaw_rate_cmd_radps, RATE);
    const fc_controller_telemetry *tm = &fo->telemetry;
    quat_from_fc(tm->attitude, out->attitude_q);
    quat_from_fc(tm->attitude_setpoint, out->attitude_setpoint_q);
    vec_from_fc(tm->rate_radps, FC_RATE_FRAC, out->rate_radps);
    out->z_r_m = FROM_FC(tm->reference.z_m, LENGTH);
    out->vz_r_mps = FROM_FC(tm->reference.vz_mps, VEL);
    out->az_r_mps2 = FROM_FC(tm->reference.az_mps2, ACCEL);
    out->tilt_cos = FROM_FC(tm->tilt_cos, RATIO);
    const fc_altitude_control_output *a = &tm->altitude;
    out->alt_thrust_n = FROM_FC(a->thrust_n, FORCE);
    out->vertical_force_n = FROM_FC(a->vertical_force_n, FORCE);
    out->error_m = FROM_FC(a->error_m, LENGTH);
    out->sigma_mps = FROM_FC(a->sigma_mps, VEL);
    out->sigma_tilde_mps = FROM_FC(a->sigma_tilde_mps, VEL);
    out->rho_n = FROM_FC(a->rho_n, FORCE);
    out->u0_av_n = FROM_FC(a->u0_av_n, FORCE);
    out->u_nom_n = FROM_FC(a->u_nom_n, FORCE);
    out->theta_kg = FROM_FC(a->theta_kg, MASS);
    out->observer_bound_n = FROM_FC(a->observer_bound_n, FORCE);
    out->clamped = a->clamped ? 1 : 0;
    out->allocation_saturation = tm->allocation_saturation;
    out->estimator_status = tm->estimator_status;
    out->altitude_status = tm->altitude_status;
    out->attitude_status = tm->attitude_status;
    out->allocation_status = tm->allocation_status;
    out->landing_state = (int)tm->landing_state;
    out->landing_reason = (int)tm->landing_reason;
    out->landing_changed = tm->landing_changed ? 1 : 0;
    out->touchdown_window = tm->touchdown_window ? 1 : 0;
    out->aborts = tm->aborts;
    out->descent_blocked_by = (int)tm->descent_blocked_by;
    out->descent_shaping_mps = FROM_FC(tm->descent_shaping_mps, VEL);
    out->pad_est_z_m = FROM_FC(tm->pad.now.z_m, LENGTH);
    out->pad_est_vz_mps = FROM_FC(tm->pad.now.vz_mps, VEL);
    out->pad_confidence = FROM_FC(tm->pad.confidence, UNIT);
    out->pad_accel_bound_mps2 = FROM_FC(tm->pad.accel_bound_mps2, ACCEL);
    out->pad_period_s = FROM_FC(tm->pad.dominant_period_s, TIME);
    out->gear_height_m = FROM_FC(tm->gear_height_m, LENGTH);
    out->vz_est_mps = FROM_FC(tm->vertical.vz_mps, VEL);
    out->hover_thrust_n = FROM_FC(tm->vertical.hover_thrust_n, FORCE);
    out->accel_bias_mps2 = FROM_FC(tm->vertical.accel_bias_mps2, ACCEL);
    out->land_state = (int)tm->land_state;
    out->failsafe_cause = (int)tm->failsafe_cause;
    out->arming_blocked_by = (int)tm->arming_blocked_by;
    vec_from_fc(internals->attitude_error_rad, FC_ANGLE_FRAC, out->attitude_error_rad);
    vec_from_fc(internals->attitude_integral_rad_s, FC_ANGLE_FRAC, out->attitude_integral_rad_s);
    out->position_integral_mps2[0] = FROM_FC(internals->position_integral_mps2.x, ACCEL);
    out->position_integral_mps2[1] = FROM_FC(internals->position_integral_mps2.y, ACCEL);
    out->accel_feedback_mps2[0] = FROM_FC(internals->accel_feedback_mps2.x, ACCEL);
    out->accel_feedback_mps2[1] = FROM_FC(internals->accel_feedback_mps2.y, ACCEL);
}

static void adapter_step(void *handle, const fsw_inputs *in, fsw_outputs *out)
{
    fc_controller *ctl = handle;
    const fc_controller_inputs fin = inputs_of(in);
    fc_controller_outputs fout;
    const fc_step_status status = fc_controller_step(ctl, &fin, &fout);
    const pil_internals internals = pil_internals_of(ctl);
    outputs_of(status, &fout, &internals, out);
}

const fsw_backend FSW_TABLE = {FSW_STR(FSW_BACKEND), adapter_create, adapter_destroy, adapter_step};

#if defined(FSW_PIL) && FSW_PIL
/*
 * Processor in the loop (compiled into the fixed copy only): the same
 * parameters, inputs and outputs as above, but the step runs in the ATmega
 * image named by cfg->target_image, in simavr (pil_avr.c), and what crosses is
 * the PIL wire's words (pil_wire.h). The host computes nothing of the
 * controller: it converts, packs and unpacks.
 */
#include "pil_avr.h"

static void *pil_create(const fsw_config *cfg, fsw_info *info, char *err, size_t err_len)
{
    fc_controller_params p;
    if (!params_of_config(cfg, &p, err, err_len)) {
        return NULL;
    }
    if (cfg->target_image == NULL) {
        snprintf(err, err_len, "a PIL run needs the ATmega image (fc-sil --pil-image FILE)");
        return NULL;
    }
    if (cfg->descent_shaping == 1) {
        snprintf(err, err_len, "the PIL wire does not carry descent shaping ([landing] descent_shaping)");
        return NULL;
    }
    if (cfg->velocity_output == 1 || !isnan(cfg->landing_gear_height_m) || !isnan(cfg->landing_touchdown_dip_m)) {
        snprintf(err, err_len,
                 "the PIL wire does not carry the velocity output, the gear height nor the dip ([controller] "
                 "output, landing_gear_height_m, landing_touchdown_dip_m)");
        return NULL;
    }
    uint32_t airframe = (uint32_t)cfg->airframe, variant = (uint32_t)cfg->variant;
    uint32_t params[PIL_PARAM_WORDS], out[PIL_OUTPUT_WORDS];
    pil_wire wire = {params, PIL_PARAM_WORDS, 0u, true};
    if (!pil_wire_params(&wire, &airframe, &variant, &p)) {
        snprintf(err, err_len, "the PIL parameter listing does not fill PIL_PARAM_WORDS");
        return NULL;
    }
    pil_avr *target = pil_avr_open(cfg->target_image, params, PIL_PARAM_WORDS, PIL_INPUT_WORDS, out,
                                   PIL_OUTPUT_WORDS, err, err_len);
    if (target == NULL) {
        return NULL;
    }
    if (out[0] == UINT32_MAX || !init_succeeded((fc_init_result)out[0], err, err_len)) {
        if (out[0] == UINT32_MAX) {
            snprintf(err, err_len, "the ATmega image rejected the PIL parameters");
        }
        pil_avr_close(target);
        return NULL;
    }
    info_of(&p, info);
    return target;
}

static void pil_destroy(void *handle)
{
    const pil_avr_cycles c = pil_avr_step_cycles(handle);
    fprintf(stderr, "pil: fc_controller_step on the ATmega2560 (simavr): %lu calls, cycles min %lu mean %.0f max %lu; "
                    "stack peak %u B\n",
            c.calls, (unsigned long)c.min, c.mean, (unsigned long)c.max, (unsigned)c.stack_peak_bytes);
    pil_avr_close(handle);
}

static void pil_step(void *handle, const fsw_inputs *in, fsw_outputs *out)
{
    fc_controller_inputs fin = inputs_of(in);
    uint32_t in_words[PIL_INPUT_WORDS], out_words[PIL_OUTPUT_WORDS];
    pil_wire wire = {in_words, PIL_INPUT_WORDS, 0u, true};
    char err[160] = "";
    if (!pil_wire_inputs(&wire, &fin) || !pil_avr_step(handle, in_words, out_words, err, sizeof err)) {
        /* the simulated core is gone: nothing sensible to fly on */
        fprintf(stderr, "pil: %s\n", err[0] != '\0' ? err : "the input listing does not fill PIL_INPUT_WORDS");
        exit(2);
    }
    fc_controller_outputs fout = {0};
    pil_internals internals = {0};
    uint32_t status = 0u;
    wire = (pil_wire){out_words, PIL_OUTPUT_WORDS, 0u, false};
    (void)pil_wire_outputs(&wire, &status, &fout, &internals);
    outputs_of((fc_step_status)status, &fout, &internals, out);
}

const fsw_backend fsw_pil_backend = {"pil", pil_create, pil_destroy, pil_step};
#endif

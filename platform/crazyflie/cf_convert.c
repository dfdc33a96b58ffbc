/* cf_convert.c - conversions and decisions of the Crazyflie app (cf_convert.h). */
#include "cf_convert.h"

#include <math.h>

#define F(x, KIND) fc_from_float((x), FC_##KIND##_FRAC)
#define R(x, KIND) fc_to_float((x), FC_##KIND##_FRAC)

/* ---- units ------------------------------------------------------------------- */

float cf_rad_from_deg(float deg)
{
    return deg * (CF_PI_F / 180.0f);
}

float cf_mps2_from_g(float g)
{
    return g * CF_GRAVITY_MPS2;
}

float cf_wrap_pi(float angle_rad)
{
    if (angle_rad >= -CF_PI_F && angle_rad <= CF_PI_F) {
        return angle_rad;
    }
    /* NaN and infinities stay not finite: the controller reports them */
    return remainderf(angle_rad, 2.0f * CF_PI_F);
}

/* ---- quaternions ------------------------------------------------------------- */

fc_quat cf_quat_from_xyzw(float x, float y, float z, float w)
{
    return fc_quat_make(F(w, UNIT), F(x, UNIT), F(y, UNIT), F(z, UNIT));
}

void cf_quat_to_xyzw(fc_quat q, float xyzw[4])
{
    xyzw[0] = R(q.x, UNIT);
    xyzw[1] = R(q.y, UNIT);
    xyzw[2] = R(q.z, UNIT);
    xyzw[3] = R(q.w, UNIT);
}

fc_quat cf_quat_from_legacy_rpy_deg(float roll_deg, float pitch_legacy_deg, float yaw_deg)
{
    /* ZYX: q = q_z(yaw) (x) q_y(pitch) (x) q_x(roll), pitch = -legacy pitch */
    const float hr = 0.5f * cf_rad_from_deg(roll_deg);
    const float hp = -0.5f * cf_rad_from_deg(pitch_legacy_deg);
    const float hy = 0.5f * cf_rad_from_deg(yaw_deg);
    const float cr = cosf(hr), sr = sinf(hr);
    const float cp = cosf(hp), sp = sinf(hp);
    const float cy = cosf(hy), sy = sinf(hy);
    return cf_quat_from_xyzw(sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                             cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy);
}

/* ---- tuning -------------------------------------------------------------------- */

static void default_params(fc_controller_params *p, uint8_t variant)
{
    fc_controller_default_params(p, FC_AIRFRAME_CRAZYFLIE2, (fc_altitude_variant)variant,
                                 FC_C(CF_STEP_DT_S, DT));
}

bool cf_tuning_prepare(cf_tuning *t)
{
    if (t->variant >= (uint8_t)FC_ALT_VARIANT_COUNT) {
        t->variant = t->loaded_variant < (uint8_t)FC_ALT_VARIANT_COUNT ? t->loaded_variant : CF_DEFAULT_VARIANT;
    }
    if (t->variant == t->loaded_variant) {
        return false;
    }
    fc_controller_params p;
    default_params(&p, t->variant);
    const fc_altitude_control_params *a = &p.altitude;
    t->l0 = R(a->l0_per_s, GAIN);
    t->rho = R(a->rho_n, FORCE);
    t->gamma = R(a->gamma, GAIN);
    t->tau_av = R(a->tau_av_s, DT);
    t->a_m = R(a->a_m_per_s, GAIN);
    t->kappa_m = R(a->kappa_m_per_kg, GAIN);
    t->k0 = R(a->k0_ns_per_m, GAIN);
    t->delta = R(a->delta_n, FORCE);
    t->theta0 = R(a->theta0_kg, MASS);
    if (t->loaded_variant == CF_TUNING_NONE) {
        /* what does not depend on the variant: loaded once */
        t->tau_zr = CF_DEFAULT_TAU_ZR_S;
        t->z_init = R(p.reference.offset_init_m, LENGTH);
        t->z_bias = R(p.reference.bias_m, LENGTH);
        t->h_kp = R(p.horizontal.kp_per_s2, RATIO);
        t->h_kd = R(p.horizontal.kd_per_s, RATIO);
    }
    t->loaded_variant = t->variant;
    return true;
}

/* The tuned value over the default: an untouched value (it reads back as the
 * default) keeps the default's exact number, which the float of a 30-bit fixed
 * value could not give back. */
static fc_real tuned(fc_real default_value, float value, int frac, bool *finite)
{
    if (!isfinite(value)) {
        *finite = false;
        return default_value;
    }
    return fc_to_float(default_value, frac) == value ? default_value : fc_from_float(value, frac);
}

bool cf_params_from_tuning(const cf_tuning *t, float offset_m, fc_controller_params *p)
{
    const uint8_t variant = t->variant < (uint8_t)FC_ALT_VARIANT_COUNT ? t->variant : CF_DEFAULT_VARIANT;
    default_params(p, variant);
    p->use_external_attitude = true;
    bool finite = true;
    fc_altitude_control_params *a = &p->altitude;
    a->l0_per_s = tuned(a->l0_per_s, t->l0, FC_GAIN_FRAC, &finite);
    a->rho_n = tuned(a->rho_n, t->rho, FC_FORCE_FRAC, &finite);
    a->gamma = tuned(a->gamma, t->gamma, FC_GAIN_FRAC, &finite);
    a->tau_av_s = tuned(a->tau_av_s, t->tau_av, FC_DT_FRAC, &finite);
    a->a_m_per_s = tuned(a->a_m_per_s, t->a_m, FC_GAIN_FRAC, &finite);
    a->kappa_m_per_kg = tuned(a->kappa_m_per_kg, t->kappa_m, FC_GAIN_FRAC, &finite);
    a->k0_ns_per_m = tuned(a->k0_ns_per_m, t->k0, FC_GAIN_FRAC, &finite);
    a->delta_n = tuned(a->delta_n, t->delta, FC_FORCE_FRAC, &finite);
    a->theta0_kg = tuned(a->theta0_kg, t->theta0, FC_MASS_FRAC, &finite);
    p->reference.tau_s = tuned(p->reference.tau_s, t->tau_zr, FC_TIME_FRAC, &finite);
    p->reference.offset_init_m = tuned(p->reference.offset_init_m, offset_m, FC_LENGTH_FRAC, &finite);
    p->reference.bias_m = tuned(p->reference.bias_m, t->z_bias, FC_LENGTH_FRAC, &finite);
    p->horizontal.kp_per_s2 = tuned(p->horizontal.kp_per_s2, t->h_kp, FC_RATIO_FRAC, &finite);
    p->horizontal.kd_per_s = tuned(p->horizontal.kd_per_s, t->h_kd, FC_RATIO_FRAC, &finite);
    return finite;
}

float cf_approach_offset_m(const cf_tuning *t, float z_m, float pad_z_m)
{
    if (t->offset_auto == 0u) {
        return t->z_init;
    }
    const float above = z_m - pad_z_m - t->z_bias;
    if (!(above > 0.0f)) {
        return 0.0f; /* below the hold point, or no position yet */
    }
    return above < CF_APPROACH_OFFSET_MAX_M ? above : CF_APPROACH_OFFSET_MAX_M;
}

/* ---- decisions ------------------------------------------------------------------ */

void cf_session_reset(cf_session *s)
{
    s->last_command = FC_COMMAND_DISARM;
    s->hold_x_m = 0.0f;
    s->hold_y_m = 0.0f;
    s->hold_yaw_rad = 0.0f;
    s->pad_phase_rad = 0.0f;
    s->range_last_mm = 0.0f;
    s->range_m = 0.0f;
    s->range_fresh = false;
}

bool cf_setpoint_live(const cf_sample *s)
{
    return s->sp_thrust > 0.0f || s->sp_mode_x != CF_MODE_DISABLE || s->sp_mode_y != CF_MODE_DISABLE ||
           s->sp_mode_z != CF_MODE_DISABLE;
}

fc_controller_command cf_command(uint8_t mission, uint8_t track, const cf_sample *s)
{
    if (!cf_setpoint_live(s)) {
        return FC_COMMAND_DISARM;
    }
    switch (mission) {
    case CF_MISSION_FOLLOW:
        return track < (uint8_t)FC_COMMAND_COUNT ? (fc_controller_command)track : FC_COMMAND_DISARM;
    case CF_MISSION_LAND:
        return FC_COMMAND_LAND;
    case CF_MISSION_HOLD:
    default:
        return FC_COMMAND_HOLD;
    }
}

bool cf_session_begin(cf_session *ss, fc_controller_command command, const cf_sample *s)
{
    const bool begins = ss->last_command == FC_COMMAND_DISARM && command != FC_COMMAND_DISARM;
    if (begins) {
        ss->hold_x_m = s->pos_m[0];
        ss->hold_y_m = s->pos_m[1];
        ss->hold_yaw_rad = cf_wrap_pi(cf_rad_from_deg(s->yaw_deg));
        ss->pad_phase_rad = 0.0f;
    }
    ss->last_command = command;
    return begins;
}

float cf_pad_height_m(const cf_session *ss, const cf_tuning *t)
{
    return t->pad_z + t->pad_amp * sinf(ss->pad_phase_rad);
}

fc_vertical_trajectory cf_pad_trajectory(const cf_session *ss, const cf_tuning *t)
{
    const float w = 2.0f * CF_PI_F * t->pad_freq;
    const float s = sinf(ss->pad_phase_rad), c = cosf(ss->pad_phase_rad);
    fc_vertical_trajectory pad;
    pad.z_m = F(t->pad_z + t->pad_amp * s, LENGTH);
    pad.vz_mps = F(t->pad_amp * w * c, VEL);
    pad.az_mps2 = F(-t->pad_amp * w * w * s, ACCEL);
    return pad;
}

void cf_pad_advance(cf_session *ss, const cf_tuning *t, float dt_s)
{
    const float next = cf_wrap_pi(ss->pad_phase_rad + 2.0f * CF_PI_F * t->pad_freq * dt_s);
    ss->pad_phase_rad = isfinite(next) ? next : 0.0f;
}

void cf_range_step(cf_session *ss, float range_mm, const cf_tuning *t)
{
    const bool changed = range_mm != ss->range_last_mm;
    ss->range_last_mm = range_mm;
    ss->range_fresh = false;
    if (!(changed && range_mm >= 0.0f && range_mm < CF_RANGE_MAX_MM)) {
        return; /* the same reading (or none), or one the deck driver calls an outlier */
    }
    const float range_m = range_mm * 0.001f + t->range_offset_m;
    if (!isfinite(range_m)) {
        return; /* a non-finite offset: no sample */
    }
    ss->range_m = range_m > 0.0f ? range_m : 0.0f;
    ss->range_fresh = true;
}

void cf_inputs_from_sample(const cf_sample *s, const cf_session *ss, const cf_tuning *t,
                           fc_controller_command command, fc_controller_inputs *in)
{
    in->imu.gyro_radps = fc_vec3_make(F(cf_rad_from_deg(s->gyro_dps[0]), RATE), F(cf_rad_from_deg(s->gyro_dps[1]), RATE),
                                      F(cf_rad_from_deg(s->gyro_dps[2]), RATE));
    in->imu.accel_mps2 = fc_vec3_make(F(cf_mps2_from_g(s->acc_g[0]), ACCEL), F(cf_mps2_from_g(s->acc_g[1]), ACCEL),
                                      F(cf_mps2_from_g(s->acc_g[2]), ACCEL));
    in->attitude_external = cf_quat_from_xyzw(s->quat_xyzw[0], s->quat_xyzw[1], s->quat_xyzw[2], s->quat_xyzw[3]);
    /* the app flies on the firmware's attitude (use_external_attitude): no heading for the library's filter */
    in->heading_rad = FC_INT(0, ANGLE);
    in->heading_fresh = false;
    in->position_m = fc_vec3_make(F(s->pos_m[0], LENGTH), F(s->pos_m[1], LENGTH), F(s->pos_m[2], LENGTH));
    in->velocity_mps = fc_vec3_make(F(s->vel_mps[0], VEL), F(s->vel_mps[1], VEL), F(s->vel_mps[2], VEL));
    in->pad = cf_pad_trajectory(ss, t);
    const float x = s->sp_mode_x == CF_MODE_ABS ? s->sp_pos_m[0] : ss->hold_x_m;
    const float y = s->sp_mode_y == CF_MODE_ABS ? s->sp_pos_m[1] : ss->hold_y_m;
    in->position_setpoint_m = fc_vec3_make(F(x, LENGTH), F(y, LENGTH), FC_INT(0, LENGTH));
    const float yaw = s->sp_mode_yaw == CF_MODE_ABS ? cf_wrap_pi(cf_rad_from_deg(s->sp_yaw_deg)) : ss->hold_yaw_rad;
    in->yaw_setpoint_rad = F(yaw, ANGLE);
    in->range_m = F(ss->range_m, LENGTH);
    in->range_fresh = ss->range_fresh;
    in->command = command;
}

/* ---- outputs ------------------------------------------------------------------------ */

void cf_force_torque_from_outputs(const fc_controller_outputs *out, cf_force_torque *ft)
{
    ft->thrust_n = 0.0f;
    ft->torque_nm[0] = ft->torque_nm[1] = ft->torque_nm[2] = 0.0f;
    if (!out->motors_on) {
        return;
    }
    const float thrust = R(out->thrust_n, FORCE);
    const float mx = R(out->moment_nm.x, MOMENT), my = R(out->moment_nm.y, MOMENT), mz = R(out->moment_nm.z, MOMENT);
    if (!(isfinite(thrust) && isfinite(mx) && isfinite(my) && isfinite(mz))) {
        return; /* the library promises finite outputs; this is the last guard */
    }
    ft->thrust_n = thrust > 0.0f ? thrust : 0.0f;
    ft->torque_nm[0] = mx;
    ft->torque_nm[1] = my;
    ft->torque_nm[2] = mz;
}

void cf_telemetry_from_outputs(const fc_controller_outputs *out, fc_step_status status,
                               fc_controller_command command, float pad_z_m, float range_m, cf_telemetry *tm)
{
    const fc_controller_telemetry *ct = &out->telemetry;
    const fc_altitude_control_output *a = &ct->altitude;
    tm->sigma = R(a->sigma_mps, VEL);
    tm->sigma_tilde = R(a->sigma_tilde_mps, VEL);
    tm->rho = R(a->rho_n, FORCE);
    tm->theta = R(a->theta_kg, MASS);
    tm->u0_av = R(a->u0_av_n, FORCE);
    tm->u_nom = R(a->u_nom_n, FORCE);
    tm->error = R(a->error_m, LENGTH);
    tm->z_ref = R(ct->reference.z_m, LENGTH);
    tm->vz_ref = R(ct->reference.vz_mps, VEL);
    tm->pad_z = pad_z_m;
    cf_force_torque ft;
    cf_force_torque_from_outputs(out, &ft);
    tm->thrust = ft.thrust_n;
    tm->torque[0] = ft.torque_nm[0];
    tm->torque[1] = ft.torque_nm[1];
    tm->torque[2] = ft.torque_nm[2];
    tm->status = status;
    tm->command = (uint8_t)command;
    tm->saturation = ct->allocation_saturation;
    tm->landing_state = (uint8_t)ct->landing_state;
    tm->landing_reason = (uint8_t)ct->landing_reason;
    tm->aborts = ct->aborts;
    tm->touchdown_window = ct->touchdown_window ? 1u : 0u;
    tm->pad_confidence = R(ct->pad.confidence, UNIT);
    tm->pad_est_z = R(ct->pad.now.z_m, LENGTH);
    tm->pad_est_vz = R(ct->pad.now.vz_mps, VEL);
    tm->pad_period = R(ct->pad.dominant_period_s, TIME);
    tm->gear_height = R(ct->gear_height_m, LENGTH);
    tm->range = range_m;
}

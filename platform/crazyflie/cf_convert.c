/* cf_convert.c - conversions and decisions of the Crazyflie app (cf_convert.h). */
#include "cf_convert.h"

#include <math.h>
#include <stddef.h>

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

/* ---- airframe ------------------------------------------------------------------ */

/* mass 0: the library's preset as it is */
static cf_airframe airframe;

static bool within(float value, float low, float high)
{
    return value >= low && value <= high;
}

bool cf_airframe_use(const cf_airframe *af)
{
    if (af == NULL) {
        airframe = (cf_airframe){0};
        return true;
    }
    const bool plausible = within(af->mass_kg, 0.005f, 1.0f) && within(af->arm_m, 0.01f, 0.5f) &&
                           within(af->thrust_max_n, 0.01f, 10.0f) &&
                           within(af->thrust_min_n, 0.0f, 0.9f * af->thrust_max_n) &&
                           within(af->torque_per_thrust_m, 0.0005f, 0.05f);
    if (!plausible) {
        return false;
    }
    airframe = *af;
    return true;
}

/* The preset's quad-X (rotor order and spin) with the platform's arm,
 * thrust range and torque per thrust; the idle speed sqrt(THRUST_MIN /
 * THRUST_MAX) of a thrust that goes with the speed squared. */
static void airframe_rotors(fc_allocation_params *a)
{
    fc_allocation_preset_crazyflie2(a);
    const float arm_ratio = airframe.arm_m / CF_AIRFRAME_PRESET_ARM_M;
    const float speed_min = sqrtf(airframe.thrust_min_n / airframe.thrust_max_n);
    for (int i = 0; i < a->rotor_count && i < FC_MAX_ROTORS; i++) {
        fc_rotor_params *r = &a->rotor[i];
        const float spin = R(r->torque_max_nm, MOMENT) < 0.0f ? -1.0f : 1.0f;
        r->position_m.x = F(R(r->position_m.x, LENGTH) * arm_ratio, LENGTH);
        r->position_m.y = F(R(r->position_m.y, LENGTH) * arm_ratio, LENGTH);
        r->thrust_max_n = F(airframe.thrust_max_n, FORCE);
        r->torque_max_nm = F(spin * airframe.thrust_max_n * airframe.torque_per_thrust_m, MOMENT);
        r->speed_min = F(speed_min, UNIT);
    }
}

/* ---- tuning -------------------------------------------------------------------- */

static void default_params(fc_controller_params *p, uint8_t variant)
{
    if (!(airframe.mass_kg > 0.0f)) {
        fc_controller_default_params(p, FC_AIRFRAME_CRAZYFLIE2, (fc_altitude_variant)variant,
                                     FC_C(CF_STEP_DT_S, DT));
        return;
    }
    /* the platform's airframe; the preset's inertia scaled by mass and arm^2 */
    fc_allocation_params rotors;
    airframe_rotors(&rotors);
    const float arm_ratio = airframe.arm_m / CF_AIRFRAME_PRESET_ARM_M;
    const float scale = airframe.mass_kg / CF_AIRFRAME_PRESET_MASS_KG * arm_ratio * arm_ratio;
    const fc_vec3 inertia = fc_vec3_make(F(CF_AIRFRAME_PRESET_JXY_KGM2 * scale, INERTIA),
                                         F(CF_AIRFRAME_PRESET_JXY_KGM2 * scale, INERTIA),
                                         F(CF_AIRFRAME_PRESET_JZ_KGM2 * scale, INERTIA));
    fc_controller_default_params_for(p, FC_AIRFRAME_CRAZYFLIE2, &rotors, F(airframe.mass_kg, MASS), inertia,
                                     (fc_altitude_variant)variant, FC_C(CF_STEP_DT_S, DT));
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
    if (!isfinite(above)) {
        return 0.0f; /* no position yet */
    }
    return fminf(fmaxf(above, -CF_APPROACH_OFFSET_MAX_M), CF_APPROACH_OFFSET_MAX_M);
}

/* ---- decisions ------------------------------------------------------------------ */

void cf_session_reset(cf_session *s)
{
    s->last_command = FC_COMMAND_DISARM;
    s->sp_x_m = 0.0f;
    s->sp_y_m = 0.0f;
    s->sp_yaw_rad = 0.0f;
    s->cmd_z_m = 0.0f;
    s->cmd_vz_mps = 0.0f;
    s->cmd_az_mps2 = 0.0f;
    s->have_cmd_z = false;
    s->approach_offset_m = 0.0f;
    s->approach_decay = 0.0f;
    s->approach_pending = false;
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

/* A finite value, or the fallback. */
static float finite_or(float value, float fallback)
{
    return isfinite(value) ? value : fallback;
}

bool cf_session_begin(cf_session *ss, fc_controller_command command, const cf_sample *s, const cf_tuning *t)
{
    (void)t;
    const bool begins = ss->last_command == FC_COMMAND_DISARM && command != FC_COMMAND_DISARM;
    if (begins) {
        ss->sp_x_m = finite_or(s->pos_m[0], 0.0f);
        ss->sp_y_m = finite_or(s->pos_m[1], 0.0f);
        ss->sp_yaw_rad = finite_or(cf_wrap_pi(cf_rad_from_deg(s->yaw_deg)), 0.0f);
        ss->cmd_z_m = finite_or(s->pos_m[2], 0.0f);
        ss->cmd_vz_mps = 0.0f;
        ss->cmd_az_mps2 = 0.0f;
        ss->have_cmd_z = false;
        ss->pad_phase_rad = 0.0f;
    }
    /* every switch into tracking: the approach starts at the next setpoint step */
    ss->approach_pending = command == FC_COMMAND_TRACK_PAD && ss->last_command != FC_COMMAND_TRACK_PAD;
    ss->last_command = command;
    return begins;
}

/* value kept within lead of centre */
static float within_lead(float value, float centre, float lead)
{
    return fminf(fmaxf(value, centre - lead), centre + lead);
}

/* x, y: a point, a velocity, or none (level). */
static void horizontal_setpoint_step(cf_session *ss, const cf_sample *s, const cf_tuning *t, float dt_s)
{
    if (s->sp_mode_x == CF_MODE_ABS && s->sp_mode_y == CF_MODE_ABS) {
        ss->sp_x_m = finite_or(s->sp_pos_m[0], ss->sp_x_m);
        ss->sp_y_m = finite_or(s->sp_pos_m[1], ss->sp_y_m);
    } else if (s->sp_mode_x == CF_MODE_VELOCITY && s->sp_mode_y == CF_MODE_VELOCITY) {
        float vx_mps = finite_or(s->sp_vel_mps[0], 0.0f), vy_mps = finite_or(s->sp_vel_mps[1], 0.0f);
        if (s->sp_velocity_body) {
            /* the body's heading frame, turned to the world by the vehicle's yaw */
            const float yaw_rad = finite_or(cf_rad_from_deg(s->yaw_deg), 0.0f);
            const float c = cosf(yaw_rad), sn = sinf(yaw_rad);
            const float forward_mps = vx_mps;
            vx_mps = c * forward_mps - sn * vy_mps;
            vy_mps = sn * forward_mps + c * vy_mps;
        }
        const float x = within_lead(ss->sp_x_m + vx_mps * dt_s, s->pos_m[0], CF_VELOCITY_LEAD_MAX_M);
        const float y = within_lead(ss->sp_y_m + vy_mps * dt_s, s->pos_m[1], CF_VELOCITY_LEAD_MAX_M);
        ss->sp_x_m = finite_or(x, ss->sp_x_m);
        ss->sp_y_m = finite_or(y, ss->sp_y_m);
    } else {
        /* level out: the PD's kp (sp - p) - kd v is zero at sp = p + v kd / kp */
        const float lead_s = t->h_kp > 0.0f ? t->h_kd / t->h_kp : 0.0f;
        ss->sp_x_m = finite_or(s->pos_m[0] + s->vel_mps[0] * lead_s, ss->sp_x_m);
        ss->sp_y_m = finite_or(s->pos_m[1] + s->vel_mps[1] * lead_s, ss->sp_y_m);
    }
}

static void yaw_setpoint_step(cf_session *ss, const cf_sample *s, float dt_s)
{
    if (s->sp_mode_yaw == CF_MODE_ABS) {
        ss->sp_yaw_rad = finite_or(cf_wrap_pi(cf_rad_from_deg(s->sp_yaw_deg)), ss->sp_yaw_rad);
    } else if (s->sp_mode_yaw == CF_MODE_VELOCITY) {
        const float turned = cf_wrap_pi(ss->sp_yaw_rad + cf_rad_from_deg(s->sp_yaw_rate_dps) * dt_s);
        ss->sp_yaw_rad = finite_or(turned, ss->sp_yaw_rad);
    } else {
        /* held */
    }
}

/* z: toward the commanded height at most CF_COMMAND_Z_SPEED_MAX_MPS, with its feed-forward. */
static void vertical_setpoint_step(cf_session *ss, const cf_sample *s, float dt_s)
{
    float target_m;
    float vz_mps = 0.0f, az_mps2 = 0.0f;
    if (s->sp_mode_z == CF_MODE_ABS) {
        target_m = finite_or(s->sp_pos_m[2], ss->cmd_z_m);
        vz_mps = finite_or(s->sp_vel_mps[2], 0.0f);
        az_mps2 = finite_or(s->sp_acc_mps2[2], 0.0f);
    } else if (s->sp_mode_z == CF_MODE_VELOCITY) {
        vz_mps = finite_or(s->sp_vel_mps[2], 0.0f);
        target_m = finite_or(within_lead(ss->cmd_z_m + vz_mps * dt_s, s->pos_m[2], CF_VELOCITY_LEAD_MAX_M),
                             ss->cmd_z_m);
    } else {
        return; /* held: the level-out keeps z, and so does a setpoint without one */
    }
    /* the first height after a start is taken as it is (the approach joins it to the
     * vehicle's); later ones move at most CF_COMMAND_Z_SPEED_MAX_MPS */
    const float step_max_m = ss->have_cmd_z ? CF_COMMAND_Z_SPEED_MAX_MPS * dt_s : CF_APPROACH_OFFSET_MAX_M;
    const float moved_m = within_lead(target_m, ss->cmd_z_m, step_max_m);
    const bool limited = moved_m != target_m;
    ss->cmd_z_m = moved_m;
    /* a ramp the limit makes has its own speed and no acceleration */
    const float ramp_mps = target_m > moved_m ? CF_COMMAND_Z_SPEED_MAX_MPS : -CF_COMMAND_Z_SPEED_MAX_MPS;
    ss->cmd_vz_mps = limited ? ramp_mps : within_lead(vz_mps, 0.0f, CF_COMMAND_Z_SPEED_MAX_MPS);
    ss->cmd_az_mps2 = limited ? 0.0f : az_mps2;
    ss->have_cmd_z = true;
}

void cf_setpoint_step(cf_session *ss, const cf_sample *s, const cf_tuning *t, float dt_s)
{
    horizontal_setpoint_step(ss, s, t, dt_s);
    yaw_setpoint_step(ss, s, dt_s);
    vertical_setpoint_step(ss, s, dt_s);
    if (ss->approach_pending) {
        /* z_r starts at the vehicle's height, over the height this step tracks */
        ss->approach_offset_m = cf_approach_offset_m(t, s->pos_m[2], cf_pad_height_m(ss, t));
        ss->approach_decay = 1.0f;
        ss->approach_pending = false;
    }
}

/* Tracking rides on the commander's height (less the bias) once it gave one. */
static bool follows_command(const cf_session *ss, const cf_tuning *t)
{
    return t->command_z != 0u && ss->have_cmd_z;
}

/* The pad in float: m, m/s, m/s^2. */
static void pad_float(const cf_session *ss, const cf_tuning *t, float *z_m, float *vz_mps, float *az_mps2)
{
    const float w = 2.0f * CF_PI_F * t->pad_freq;
    const float sn = sinf(ss->pad_phase_rad), c = cosf(ss->pad_phase_rad);
    const bool command = follows_command(ss, t);
    *z_m = (command ? ss->cmd_z_m - t->z_bias : t->pad_z) + t->pad_amp * sn;
    *vz_mps = (command ? ss->cmd_vz_mps : 0.0f) + t->pad_amp * w * c;
    *az_mps2 = (command ? ss->cmd_az_mps2 : 0.0f) - t->pad_amp * w * w * sn;
}

float cf_pad_height_m(const cf_session *ss, const cf_tuning *t)
{
    float z_m, vz_mps, az_mps2;
    pad_float(ss, t, &z_m, &vz_mps, &az_mps2);
    return z_m;
}

fc_vertical_trajectory cf_pad_trajectory(const cf_session *ss, const cf_tuning *t)
{
    float z_m, vz_mps, az_mps2;
    pad_float(ss, t, &z_m, &vz_mps, &az_mps2);
    fc_vertical_trajectory pad;
    pad.z_m = F(z_m, LENGTH);
    pad.vz_mps = F(vz_mps, VEL);
    pad.az_mps2 = F(az_mps2, ACCEL);
    return pad;
}

fc_vertical_trajectory cf_track_trajectory(const cf_session *ss, const cf_tuning *t)
{
    float z_m, vz_mps, az_mps2;
    pad_float(ss, t, &z_m, &vz_mps, &az_mps2);
    /* (3.6)'s decaying offset and its derivatives: -offset / tau, offset / tau^2 */
    const float inv_tau_per_s = t->tau_zr > 0.0f ? 1.0f / t->tau_zr : 0.0f;
    const float offset_m = ss->approach_offset_m * ss->approach_decay;
    fc_vertical_trajectory track;
    track.z_m = F(z_m + offset_m, LENGTH);
    track.vz_mps = F(vz_mps - offset_m * inv_tau_per_s, VEL);
    track.az_mps2 = F(az_mps2 + offset_m * inv_tau_per_s * inv_tau_per_s, ACCEL);
    return track;
}

void cf_pad_advance(cf_session *ss, const cf_tuning *t, float dt_s)
{
    const float next = cf_wrap_pi(ss->pad_phase_rad + 2.0f * CF_PI_F * t->pad_freq * dt_s);
    ss->pad_phase_rad = isfinite(next) ? next : 0.0f;
    const float decay = t->tau_zr > 0.0f ? ss->approach_decay * expf(-dt_s / t->tau_zr) : 0.0f;
    ss->approach_decay = isfinite(decay) ? decay : 0.0f;
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

/* The heading setpoint's rate, fed forward by the library (yaw in velocity
 * mode only): a rate that is no number is none, and one beyond what the
 * library's input gate lets through (100 rad/s) is cut to it, so that the
 * sample is not refused for it. */
static float yaw_rate_feedforward_radps(const cf_sample *s)
{
    if (s->sp_mode_yaw != CF_MODE_VELOCITY) {
        return 0.0f;
    }
    const float rate = finite_or(cf_rad_from_deg(s->sp_yaw_rate_dps), 0.0f);
    const float limit = 100.0f;
    return rate > limit ? limit : (rate < -limit ? -limit : rate);
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
    in->pad = cf_track_trajectory(ss, t);
    in->position_setpoint_m = fc_vec3_make(F(ss->sp_x_m, LENGTH), F(ss->sp_y_m, LENGTH), FC_INT(0, LENGTH));
    in->pad_attitude = fc_quat_identity(); /* no deck attitude on this path: a level pad */
    in->yaw_setpoint_rad = F(ss->sp_yaw_rad, ANGLE);
    in->yaw_rate_setpoint_radps = F(yaw_rate_feedforward_radps(s), RATE);
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

/* pil_wire.c - the PIL mailboxes' contents, one listing per message (pil_wire.h). */
#include "pil_wire.h"

#include <string.h>

/* One word: written from *value, or read into it. */
static void word(pil_wire *w, uint32_t *value)
{
    if (w->at < w->size) {
        if (w->writing) {
            w->word[w->at] = *value;
        } else {
            *value = w->word[w->at];
        }
    }
    w->at++;
}

/* An fc_real as its 32 bits (int32_t in fixed, IEEE single in float). */
static void real(pil_wire *w, fc_real *value)
{
    uint32_t bits;
    _Static_assert(sizeof bits == sizeof *value, "fc_real is 32 bits");
    memcpy(&bits, value, sizeof bits);
    word(w, &bits);
    memcpy(value, &bits, sizeof bits);
}

static void vec3(pil_wire *w, fc_vec3 *v)
{
    real(w, &v->x);
    real(w, &v->y);
    real(w, &v->z);
}

static void quat(pil_wire *w, fc_quat *q)
{
    real(w, &q->w);
    real(w, &q->x);
    real(w, &q->y);
    real(w, &q->z);
}

static void trajectory(pil_wire *w, fc_vertical_trajectory *t)
{
    real(w, &t->z_m);
    real(w, &t->vz_mps);
    real(w, &t->az_mps2);
}

static void flag(pil_wire *w, bool *value)
{
    uint32_t v = *value ? 1u : 0u;
    word(w, &v);
    *value = v != 0u;
}

static void byte(pil_wire *w, uint8_t *value)
{
    uint32_t v = *value;
    word(w, &v);
    *value = (uint8_t)v;
}

static void status(pil_wire *w, fc_step_status *value)
{
    uint32_t v = *value;
    word(w, &v);
    *value = (fc_step_status)v;
}

/* An enum's value through one word: written from it, or read (returned). */
static uint32_t enum_word(pil_wire *w, uint32_t value)
{
    uint32_t v = value;
    word(w, &v);
    return v;
}

static bool complete(const pil_wire *w)
{
    return w->at == w->size;
}

bool pil_wire_params(pil_wire *w, uint32_t *airframe, uint32_t *variant, fc_controller_params *p)
{
    w->at = 0u;
    word(w, airframe);
    word(w, variant);
    real(w, &p->dt_s);
    if (!w->writing) {
        /* the image's own defaults for everything the wire does not carry */
        fc_controller_default_params(p, (fc_airframe)*airframe, (fc_altitude_variant)*variant, p->dt_s);
    }
    flag(w, &p->use_external_attitude);
    /* what sim_host/fsw_adapter.c may override */
    real(w, &p->mass_kg);
    if (!w->writing) {
        fc_controller_set_mass(p, p->mass_kg);
    }
    real(w, &p->altitude.theta0_kg);
    real(w, &p->altitude.mass_min_kg);
    real(w, &p->altitude.mass_max_kg);
    real(w, &p->reference.tau_s);
    real(w, &p->reference.offset_init_m);
    real(w, &p->reference.bias_m);
    real(w, &p->altitude.thrust_min_n);
    real(w, &p->altitude.thrust_max_n);
    real(w, &p->altitude.ground_gain_max);
    real(w, &p->altitude.rho_n);
    real(w, &p->altitude.gamma);
    real(w, &p->altitude.actuator_lag_s);
    real(w, &p->altitude.kappa_m_per_kg);
    real(w, &p->altitude.tau_av_s);
    real(w, &p->altitude.l0_per_s);
    real(w, &p->altitude.a_m_per_s);
    real(w, &p->altitude.delta_n);
    real(w, &p->altitude.k0_ns_per_m);
    real(w, &p->altitude.stw_k1);
    real(w, &p->altitude.stw_k2_nps);
    real(w, &p->altitude.pid_kp_z_per_s);
    real(w, &p->altitude.pid_ki_z_per_s2);
    real(w, &p->altitude.pid_kp_v_n_per_mps);
    real(w, &p->altitude.pid_ki_v_n_per_m);
    real(w, &p->horizontal.kp_per_s2);
    real(w, &p->horizontal.kd_per_s);
    real(w, &p->horizontal.tilt_max_rad);
    real(w, &p->horizontal.accel_fb_gain_per_s);
    real(w, &p->landing.hold_height_m);
    real(w, &p->landing.descent_tau_s);
    real(w, &p->landing.pad_accel_max_mps2);
    real(w, &p->landing.confidence_start);
    return complete(w);
}

bool pil_wire_inputs(pil_wire *w, fc_controller_inputs *in)
{
    w->at = 0u;
    vec3(w, &in->imu.gyro_radps);
    vec3(w, &in->imu.accel_mps2);
    quat(w, &in->attitude_external);
    real(w, &in->heading_rad);
    flag(w, &in->heading_fresh);
    vec3(w, &in->position_m);
    vec3(w, &in->velocity_mps);
    trajectory(w, &in->pad);
    real(w, &in->range_m);
    flag(w, &in->range_fresh);
    vec3(w, &in->position_setpoint_m);
    real(w, &in->yaw_setpoint_rad);
    in->command = (fc_controller_command)enum_word(w, (uint32_t)in->command);
    real(w, &in->yaw_rate_setpoint_radps);
    return complete(w);
}

static void altitude_output(pil_wire *w, fc_altitude_control_output *a)
{
    real(w, &a->thrust_n);
    real(w, &a->vertical_force_n);
    real(w, &a->error_m);
    real(w, &a->sigma_mps);
    real(w, &a->sigma_tilde_mps);
    real(w, &a->rho_n);
    real(w, &a->u0_av_n);
    real(w, &a->u_nom_n);
    real(w, &a->theta_kg);
    real(w, &a->observer_bound_n);
    flag(w, &a->clamped);
}

static void landing_telemetry(pil_wire *w, fc_controller_telemetry *tm)
{
    tm->landing_state = (fc_landing_state)enum_word(w, (uint32_t)tm->landing_state);
    tm->landing_reason = (fc_landing_reason)enum_word(w, (uint32_t)tm->landing_reason);
    tm->descent_blocked_by = (fc_landing_reason)enum_word(w, (uint32_t)tm->descent_blocked_by);
    flag(w, &tm->landing_changed);
    flag(w, &tm->touchdown_window);
    byte(w, &tm->aborts);
}

static void safety_telemetry(pil_wire *w, fc_controller_telemetry *tm)
{
    real(w, &tm->vertical.vz_mps);
    real(w, &tm->vertical.hover_thrust_n);
    real(w, &tm->vertical.accel_bias_mps2);
    tm->land_state = (fc_land_state)enum_word(w, (uint32_t)tm->land_state);
    tm->failsafe_cause = (fc_failsafe_cause)enum_word(w, (uint32_t)tm->failsafe_cause);
    tm->arming_blocked_by = (fc_arming_check)enum_word(w, (uint32_t)tm->arming_blocked_by);
}

/* The telemetry fields the SIL reads (sim_host/fsw_adapter.c). */
static void telemetry(pil_wire *w, fc_controller_telemetry *tm)
{
    quat(w, &tm->attitude);
    quat(w, &tm->attitude_setpoint);
    vec3(w, &tm->rate_radps);
    trajectory(w, &tm->reference);
    real(w, &tm->tilt_cos);
    altitude_output(w, &tm->altitude);
    byte(w, &tm->allocation_saturation);
    status(w, &tm->estimator_status);
    status(w, &tm->altitude_status);
    status(w, &tm->attitude_status);
    status(w, &tm->allocation_status);
    trajectory(w, &tm->pad.now);
    real(w, &tm->pad.confidence);
    real(w, &tm->pad.accel_bound_mps2);
    real(w, &tm->pad.dominant_period_s);
    real(w, &tm->gear_height_m);
    landing_telemetry(w, tm);
    safety_telemetry(w, tm);
}

bool pil_wire_outputs(pil_wire *w, uint32_t *step_status, fc_controller_outputs *out, pil_internals *internals)
{
    w->at = 0u;
    word(w, step_status);
    for (unsigned i = 0u; i < FC_MAX_ROTORS; i++) {
        real(w, &out->rotor_speed[i]);
    }
    byte(w, &out->rotor_count);
    flag(w, &out->motors_on);
    real(w, &out->thrust_n);
    vec3(w, &out->moment_nm);
    telemetry(w, &out->telemetry);
    vec3(w, &internals->attitude_error_rad);
    vec3(w, &internals->attitude_integral_rad_s);
    vec3(w, &internals->position_integral_mps2);
    vec3(w, &internals->accel_feedback_mps2);
    return complete(w);
}

pil_internals pil_internals_of(const fc_controller *ctl)
{
    const pil_internals internals = {ctl->attitude.last_error_rad, ctl->attitude.integral_rad_s,
                                     ctl->position.integral_mps2, ctl->position.accel_fb_mps2};
    return internals;
}

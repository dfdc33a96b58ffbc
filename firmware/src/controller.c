/* controller.c - the flight controller's one entry point (fc/controller.h). */
#include "fc/controller.h"

/* ---------------------------------------------------------------------- */
/* parameters                                                              */
/* ---------------------------------------------------------------------- */

/* Collective thrust range of a planar vehicle from its rotors: all at full
 * speed, and all at idle (T_max u_min^r). */
static void thrust_range_n(const fc_allocation_params *a, fc_real *min_n, fc_real *max_n)
{
    fc_arith ar = {0u};
    *min_n = FC_INT(0, FORCE);
    *max_n = FC_INT(0, FORCE);
    for (int i = 0; i < a->rotor_count && i < FC_MAX_ROTORS; i++) {
        const fc_rotor_params *r = &a->rotor[i];
        const fc_real idle = fc_pow_unit(&ar, r->speed_min, r->thrust_exponent);
        *max_n = fc_add(&ar, *max_n, r->thrust_max_n);
        *min_n = fc_add(&ar, *min_n, fc_mul(&ar, r->thrust_max_n, idle, FC_SHIFT(FORCE, UNIT, FORCE)));
    }
}

/* Half of what the rotors together can give about each axis: the budget the
 * attitude loop may ask for while the collective thrust keeps the other half. */
static fc_vec3 moment_budget_nm(const fc_allocation_params *a)
{
    fc_arith ar = {0u};
    fc_vec3 sum = fc_vec3_zero();
    for (int i = 0; i < a->rotor_count && i < FC_MAX_ROTORS; i++) {
        const fc_rotor_params *r = &a->rotor[i];
        /* l x d in LENGTH, times T_max: MOMENT */
        const fc_vec3 lever = fc_vec3_cross(&ar, r->position_m, r->axis_unit, FC_SHIFT(LENGTH, UNIT, LENGTH));
        const fc_vec3 moment = fc_vec3_scale(&ar, lever, r->thrust_max_n, FC_SHIFT(LENGTH, FORCE, MOMENT));
        sum.x = fc_add(&ar, sum.x, fc_abs(&ar, moment.x));
        sum.y = fc_add(&ar, sum.y, fc_abs(&ar, moment.y));
        sum.z = fc_add(&ar, sum.z, fc_abs(&ar, r->torque_max_nm));
    }
    return fc_vec3_scale(&ar, sum, FC_C(0.5f, UNIT), FC_SHIFT(MOMENT, UNIT, MOMENT));
}

void fc_controller_default_params(fc_controller_params *p, fc_airframe airframe, fc_altitude_variant variant,
                                  fc_real dt_s)
{
    fc_vec3 inertia;
    switch (airframe) {
    case FC_AIRFRAME_CRAZYFLIE2:
        p->mass_kg = FC_C(0.027f, MASS);
        inertia = fc_vec3_make(FC_C(1.66e-5f, INERTIA), FC_C(1.66e-5f, INERTIA), FC_C(2.93e-5f, INERTIA));
        fc_allocation_preset_crazyflie2(&p->allocation);
        break;
    case FC_AIRFRAME_F450:
        p->mass_kg = FC_C(1.2f, MASS);
        inertia = fc_vec3_make(FC_C(0.011f, INERTIA), FC_C(0.011f, INERTIA), FC_C(0.021f, INERTIA));
        fc_allocation_preset_f450(&p->allocation);
        break;
    case FC_AIRFRAME_HEXA_4KG:
    case FC_AIRFRAME_COUNT:
    default:
        /* the dissertation's 4.4 vehicle */
        p->mass_kg = FC_C(4.0f, MASS);
        inertia = fc_vec3_make(FC_C(0.082f, INERTIA), FC_C(0.082f, INERTIA), FC_C(0.149f, INERTIA));
        fc_allocation_preset_hexa_x_4kg(&p->allocation);
        break;
    }
    p->dt_s = dt_s;
    p->gravity_mps2 = FC_C(9.81f, ACCEL);
    p->use_external_attitude = false;
    fc_attitude_estimator_default_params(&p->estimator, dt_s);
    fc_attitude_control_default_params(&p->attitude, dt_s, inertia);
    p->attitude.moment_limit_nm = moment_budget_nm(&p->allocation);
    /* the 4.4 reference: tau_zr = 0.1 s, z_r_init = 1 m, z_r_bias = 0.18 m */
    p->reference.dt_s = dt_s;
    p->reference.tau_s = FC_C(0.1f, TIME);
    p->reference.offset_init_m = FC_C(1.0f, LENGTH);
    p->reference.bias_m = FC_C(0.18f, LENGTH);
    fc_altitude_control_variant_params(&p->altitude, variant, dt_s, p->mass_kg);
    thrust_range_n(&p->allocation, &p->altitude.thrust_min_n, &p->altitude.thrust_max_n);
    /* horizontal PD: wn = 1.5 rad/s, zeta = 0.9, tilt at most 30 deg */
    p->horizontal.kp_per_s2 = FC_C(2.25f, GAIN);
    p->horizontal.kd_per_s = FC_C(2.7f, GAIN);
    p->horizontal.tilt_max_rad = FC_C(0.5236f, ANGLE);
}

static bool horizontal_params_valid(const fc_horizontal_params *h)
{
    return fc_is_finite(h->kp_per_s2) && fc_is_finite(h->kd_per_s) && fc_is_finite(h->tilt_max_rad) &&
           h->kp_per_s2 >= FC_INT(0, GAIN) && h->kd_per_s >= FC_INT(0, GAIN) &&
           h->tilt_max_rad > FC_INT(0, ANGLE) && h->tilt_max_rad <= FC_C(1.2f, ANGLE);
}

/* ---------------------------------------------------------------------- */
/* init                                                                    */
/* ---------------------------------------------------------------------- */

static void motors_off(const fc_controller *ctl, fc_controller_outputs *out)
{
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        out->rotor_speed[i] = FC_INT(0, UNIT);
    }
    out->rotor_count = ctl->ready ? ctl->allocation.rotor_count : 0u;
    out->motors_on = false;
    out->thrust_n = FC_INT(0, FORCE);
    out->moment_nm = fc_vec3_zero();
}

static void reset_loops(fc_controller *ctl)
{
    fc_altitude_control_reset(&ctl->altitude);
    fc_attitude_control_reset(&ctl->attitude);
    fc_allocation_reset(&ctl->allocation);
    ctl->last_saturation = 0u;
}

fc_init_result fc_controller_init(fc_controller *ctl, const fc_controller_params *p)
{
    ctl->ready = false;
    ctl->p = *p;
    ctl->ar.saturated = 0u;
    ctl->last_command = FC_COMMAND_DISARM;
    ctl->last_saturation = 0u;
    ctl->last_attitude = fc_quat_identity();
    /* every module validates its own parameters; the first failure is the answer */
    fc_init_result result = FC_INIT_OK;
    const fc_init_result parts[] = {
        fc_attitude_estimator_init(&ctl->estimator, &p->estimator),
        fc_attitude_control_init(&ctl->attitude, &p->attitude),
        fc_allocation_init(&ctl->allocation, &p->allocation),
        fc_altitude_reference_init(&ctl->reference, &p->reference),
        fc_altitude_control_init(&ctl->altitude, &p->altitude),
    };
    for (unsigned i = 0u; i < sizeof parts / sizeof parts[0]; i++) {
        if (parts[i] != FC_INIT_OK && result == FC_INIT_OK) {
            result = parts[i];
        }
    }
    const bool same_step = p->estimator.dt_s == p->dt_s && p->attitude.dt_s == p->dt_s &&
                           p->reference.dt_s == p->dt_s && p->altitude.dt_s == p->dt_s;
    if (result == FC_INIT_OK &&
        (!same_step || !horizontal_params_valid(&p->horizontal) || !fc_is_finite(p->mass_kg) ||
         !(p->mass_kg > FC_INT(0, MASS)) || !fc_is_finite(p->gravity_mps2) ||
         !(p->gravity_mps2 > FC_INT(0, ACCEL)))) {
        result = FC_INIT_BAD_PARAM;
    }
    if (result == FC_INIT_OK) {
        /* |a| <= g tan(tilt_max): the tilt limit as a horizontal acceleration */
        const fc_real tan_tilt = fc_div(&ctl->ar, fc_sin(&ctl->ar, p->horizontal.tilt_max_rad),
                                        fc_cos(&ctl->ar, p->horizontal.tilt_max_rad), FC_DIV_SHIFT(UNIT, UNIT, RATIO));
        ctl->horizontal_accel_max_mps2 = fc_mul(&ctl->ar, p->gravity_mps2, tan_tilt, FC_SHIFT(ACCEL, RATIO, ACCEL));
    }
    ctl->ready = result == FC_INIT_OK;
    return result;
}

/* ---------------------------------------------------------------------- */
/* one step                                                                */
/* ---------------------------------------------------------------------- */

/* The attitude in use: the filter's, or the platform's if it is a usable quaternion. */
static fc_quat attitude_in_use(fc_controller *ctl, const fc_controller_inputs *in, const fc_attitude_estimate *est,
                               fc_step_status *status)
{
    if (!ctl->p.use_external_attitude) {
        return est->attitude;
    }
    bool ok = false;
    const fc_quat q = fc_quat_normalize(&ctl->ar, in->attitude_external, &ok);
    if (!ok) {
        *status |= FC_STEP_BAD_INPUT;
        return ctl->last_attitude;
    }
    return q;
}

/* k_h = cos(roll) cos(pitch): the world-z component of the body z axis, 1 - 2(x^2 + y^2). */
static fc_real tilt_cos_of(fc_arith *ar, fc_quat q)
{
    const fc_real xx_yy = fc_dot2(ar, q.x, q.x, q.y, q.y, FC_SHIFT(UNIT, UNIT, RATIO));
    return fc_sub(ar, FC_INT(1, RATIO), fc_add(ar, xx_yy, xx_yy));
}

/* Horizontal PD -> wanted acceleration -> attitude setpoint. The acceleration
 * is saturated as a vector (direction kept, 2.6.4) to the tilt limit, turned
 * into the heading frame, and the thrust axis (a_x, a_y, g) gives pitch and roll
 * (ZYX): pitch = atan2(a_f.x, g), roll = atan2(-a_f.y, sqrt(a_f.x^2 + g^2)). */
static fc_quat attitude_setpoint(fc_controller *ctl, const fc_controller_inputs *in)
{
    fc_arith *ar = &ctl->ar;
    const fc_controller_params *p = &ctl->p;
    const fc_vec3 position_error = fc_vec3_sub(ar, in->position_m, in->position_setpoint_m);
    const fc_real ax = fc_neg(ar, fc_add(ar, fc_mul(ar, p->horizontal.kp_per_s2, position_error.x,
                                                     FC_SHIFT(GAIN, LENGTH, ACCEL)),
                                         fc_mul(ar, p->horizontal.kd_per_s, in->velocity_mps.x,
                                                FC_SHIFT(GAIN, VEL, ACCEL))));
    const fc_real ay = fc_neg(ar, fc_add(ar, fc_mul(ar, p->horizontal.kp_per_s2, position_error.y,
                                                     FC_SHIFT(GAIN, LENGTH, ACCEL)),
                                         fc_mul(ar, p->horizontal.kd_per_s, in->velocity_mps.y,
                                                FC_SHIFT(GAIN, VEL, ACCEL))));
    const fc_vec3 accel =
        fc_vec3_clamp_norm(ar, fc_vec3_make(ax, ay, FC_INT(0, ACCEL)), ctl->horizontal_accel_max_mps2, FC_ACCEL_FRAC);
    /* into the heading frame: R_z(-yaw) a */
    const fc_real c = fc_cos(ar, in->yaw_setpoint_rad), s = fc_sin(ar, in->yaw_setpoint_rad);
    const fc_real forward = fc_dot2(ar, c, accel.x, s, accel.y, FC_SHIFT(UNIT, ACCEL, ACCEL));
    const fc_real left = fc_dot2(ar, fc_neg(ar, s), accel.x, c, accel.y, FC_SHIFT(UNIT, ACCEL, ACCEL));
    const fc_real pitch = fc_atan2(ar, forward, p->gravity_mps2);
    const fc_real roll = fc_atan2(ar, fc_neg(ar, left), fc_hypot3(ar, forward, p->gravity_mps2, FC_INT(0, ACCEL)));
    return fc_quat_from_rpy(ar, roll, pitch, in->yaw_setpoint_rad);
}

static bool vec3_within(fc_vec3 v, fc_real limit)
{
    return fc_within(v.x, limit) && fc_within(v.y, limit) && fc_within(v.z, limit);
}

/* The inputs are numbers inside the physical range (fc/status.h): beyond it
 * a finite value is as bad as a NaN. */
static bool controller_inputs_usable(const fc_controller_inputs *in)
{
    const fc_real length = FC_C(FC_INPUT_MAX_LENGTH_M, LENGTH);
    const fc_real speed = FC_C(FC_INPUT_MAX_SPEED_MPS, VEL);
    const fc_real accel = FC_C(FC_INPUT_MAX_ACCEL_MPS2, ACCEL);
    return vec3_within(in->position_m, length) && vec3_within(in->velocity_mps, speed) &&
           vec3_within(in->position_setpoint_m, length) && fc_within(in->yaw_setpoint_rad, FC_C(7.0f, ANGLE)) &&
           fc_within(in->pad.z_m, length) && fc_within(in->pad.vz_mps, speed) && fc_within(in->pad.az_mps2, accel);
}

/* The bits of a module's status that the controller passes on. */
static fc_step_status passed_on(fc_step_status module_status)
{
    return module_status & (FC_STEP_BAD_INPUT | FC_STEP_OUTPUT_LIMITED | FC_STEP_ARITH_SATURATED | FC_STEP_DEGRADED);
}

fc_step_status fc_controller_step(fc_controller *ctl, const fc_controller_inputs *in, fc_controller_outputs *out)
{
    fc_controller_telemetry *tm = &out->telemetry;
    motors_off(ctl, out);
    tm->attitude = ctl->last_attitude;
    tm->attitude_setpoint = ctl->last_attitude;
    tm->rate_radps = fc_vec3_zero();
    tm->reference.z_m = FC_INT(0, LENGTH);
    tm->reference.vz_mps = FC_INT(0, VEL);
    tm->reference.az_mps2 = FC_INT(0, ACCEL);
    tm->tilt_cos = FC_INT(1, RATIO);
    tm->allocation_saturation = 0u;
    tm->estimator_status = FC_STEP_OK;
    tm->altitude_status = FC_STEP_OK;
    tm->attitude_status = FC_STEP_OK;
    tm->allocation_status = FC_STEP_OK;
    tm->altitude = (fc_altitude_control_output){0};
    if (!ctl->ready) {
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &ctl->ar;
    ar->saturated = 0u;
    fc_step_status status = FC_STEP_OK;

    /* attitude: the filter runs on every step, armed or not, to stay aligned */
    fc_attitude_estimate estimate;
    tm->estimator_status = fc_attitude_estimator_step(&ctl->estimator, &in->imu, &estimate);
    status |= passed_on(tm->estimator_status);
    const fc_quat attitude = attitude_in_use(ctl, in, &estimate, &status);
    ctl->last_attitude = attitude;
    tm->attitude = attitude;
    tm->rate_radps = estimate.rate_radps;
    tm->tilt_cos = tilt_cos_of(ar, attitude);

    const bool inputs_ok = controller_inputs_usable(in);
    if (!inputs_ok) {
        status |= FC_STEP_BAD_INPUT;
    }
    if (in->command != FC_COMMAND_TRACK_PAD || !inputs_ok) {
        /* disarmed, or nothing to fly on: motors off, loops reset */
        if (ctl->last_command != FC_COMMAND_DISARM) {
            reset_loops(ctl);
        }
        ctl->last_command = FC_COMMAND_DISARM;
        return status;
    }
    if (ctl->last_command != FC_COMMAND_TRACK_PAD) {
        /* a new approach: the reference (3.6) starts again from z_r_init */
        reset_loops(ctl);
        fc_altitude_reference_restart(&ctl->reference, ctl->p.reference.offset_init_m);
    }
    ctl->last_command = FC_COMMAND_TRACK_PAD;

    /* altitude: reference (3.6) around the pad, then the altitude law */
    status |= passed_on(fc_altitude_reference_step(&ctl->reference, &in->pad, &tm->reference));
    const fc_altitude_control_input altitude_in = {in->position_m.z, in->velocity_mps.z, tm->reference,
                                                   tm->tilt_cos, ctl->last_saturation};
    tm->altitude_status = fc_altitude_control_step(&ctl->altitude, &altitude_in, &tm->altitude);
    status |= passed_on(tm->altitude_status);

    /* attitude: setpoint from the horizontal loop, then the moments */
    tm->attitude_setpoint = attitude_setpoint(ctl, in);
    const fc_attitude_control_input attitude_in = {attitude, tm->attitude_setpoint, estimate.rate_radps,
                                                   fc_vec3_zero(), ctl->last_saturation};
    fc_attitude_control_output attitude_out;
    tm->attitude_status = fc_attitude_control_step(&ctl->attitude, &attitude_in, &attitude_out);
    status |= passed_on(tm->attitude_status);

    /* allocation */
    const fc_allocation_demand demand = {tm->altitude.thrust_n, attitude_out.moment_nm};
    fc_allocation_output allocation_out;
    tm->allocation_status = fc_allocation_step(&ctl->allocation, &demand, &allocation_out);
    status |= passed_on(tm->allocation_status);
    ctl->last_saturation = allocation_out.saturation;
    tm->allocation_saturation = allocation_out.saturation;

    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        out->rotor_speed[i] = allocation_out.speed[i];
    }
    out->motors_on = true;
    out->thrust_n = demand.thrust_n;
    out->moment_nm = demand.moment_nm;
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

/* controller.c - the flight controller's one entry point (fc/controller.h). */
#include "fc/controller.h"

/* ---------------------------------------------------------------------- */
/* parameters                                                              */
/* ---------------------------------------------------------------------- */

/* The outer group's step, dt_s outer_divider times; by additions, so that
 * the defaults and init's check form the same value in both backends. */
static fc_real outer_step_s(const fc_controller_params *p)
{
    fc_arith ar = {0u};
    fc_real sum = FC_INT(0, DT);
    for (unsigned i = 0u; i < p->outer_divider && i < FC_OUTER_DIVIDER_MAX; i++) {
        sum = fc_add(&ar, sum, p->dt_s);
    }
    return sum;
}

/* The outer group at 100 Hz, or on every step if the step is slower: the
 * most steps that fit in 10 ms (a hair over, for the rounding of dt). */
static uint8_t default_outer_divider(fc_real dt_s)
{
    fc_arith ar = {0u};
    uint8_t steps = 1u;
    fc_real span_s = dt_s;
    while (steps < FC_OUTER_DIVIDER_MAX) {
        span_s = fc_add(&ar, span_s, dt_s);
        if (span_s > FC_C(0.0101f, DT)) {
            break;
        }
        steps++;
    }
    return steps;
}

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

/* The landing mission's defaults common to every airframe (fc/landing.h, fc/pad_motion.h). */
static void landing_common_defaults(fc_controller_params *p)
{
    fc_landing_params *l = &p->landing;
    fc_pad_motion_params *m = &p->pad_motion;
    l->dt_s = p->dt_s;
    m->dt_s = outer_step_s(p); /* minor frame 1 of the outer group */
    m->mode_count = 3u;
    m->covariance_init = FC_INT(10, MAT);
    m->covariance_trace_max = FC_INT(120, MAT);
    m->outlier_reset_count = 25u;
    m->horizon_s = FC_INT(1, TIME);
    m->error_average_gain = FC_C(0.02f, UNIT);
    m->adapt_amplitude_min_m = FC_C(0.003f, LENGTH);
    l->hold_settle_s = FC_INT(1, TIME);
    l->contact_confirm_s = FC_C(0.05f, TIME);
    l->press_at_contact = false;
    l->confidence_start = FC_C(0.6f, UNIT);
    l->confidence_abort = FC_C(0.25f, UNIT);
    l->tilt_cos_abort = FC_C(0.906f, RATIO); /* 25 deg */
    l->range_timeout_s = FC_C(0.3f, TIME);
    l->abort_retries_max = 3u;
    p->failsafe.bad_input_hold_s = FC_C(0.5f, TIME);
    p->failsafe.speed_gain_per_s = FC_INT(2, GAIN);
    p->failsafe.max_s = FC_INT(60, TIME);
}

/* The Crazyflie over a pad heaving 0-10 cm with periods of 2-10 s, a 50 Hz
 * ToF ranger: one dominant sinusoid, its frequency adapted, a 10 s window. */
static void landing_crazyflie_defaults(fc_controller_params *p)
{
    fc_landing_params *l = &p->landing;
    fc_pad_motion_params *m = &p->pad_motion;
    m->mode_period_s[0] = FC_C(2.5f, TIME);
    m->mode_period_s[1] = FC_C(4.5f, TIME);
    m->mode_period_s[2] = FC_INT(8, TIME);
    m->period_min_s = FC_C(1.8f, TIME);
    m->period_max_s = FC_INT(12, TIME);
    m->frequency_gain = FC_C(0.1f, UNIT);
    m->forgetting = FC_C(0.998f, UNIT);
    m->outlier_m = FC_C(0.15f, LENGTH);
    m->observe_min_s = FC_INT(5, TIME);
    m->tolerance_m = FC_C(0.02f, LENGTH);
    l->gear_height_m = FC_C(0.02f, LENGTH);
    l->hold_height_m = FC_C(0.3f, LENGTH);
    l->hold_tau_s = FC_INT(1, TIME);
    l->hold_settle_m = FC_C(0.05f, LENGTH);
    l->descent_tau_s = FC_C(1.5f, TIME);
    l->touchdown_dip_m = FC_C(0.04f, LENGTH);
    /* the plan's uncertainty: the pad estimate's (~1 cm) and the tracking error's */
    l->touchdown_window_m = FC_C(0.03f, LENGTH);
    /* the ToF's noise is 2-4 mm (1 mm steps): it cannot tell resting on the
     * pad from floating on the ground-effect cushion a few mm above it. So
     * 12 samples in a row under 5 mm, pressed (fc/landing.h): a vehicle still
     * in the air is on the surface well within the 0.25 s, and the ramp
     * starts from a vehicle at rest on the pad */
    l->contact_height_m = FC_C(0.005f, LENGTH);
    l->contact_confirm_s = FC_C(0.25f, TIME);
    l->press_at_contact = true; /* 28 g on a 2 cm ground-effect cushion */
    l->ramp_s = FC_C(0.3f, TIME);
    l->horizontal_start_m = FC_C(0.08f, LENGTH);
    l->horizontal_abort_m = FC_C(0.2f, LENGTH);
    l->pad_accel_max_mps2 = FC_INT(2, ACCEL);
    p->failsafe.descent_mps = FC_C(0.3f, VEL);
}

/* A larger vehicle over a ship's deck heaving up to 1 m with periods of 8-18 s,
 * a 100 Hz laser ranger: broadband, a fixed grid fitted over a 1 s window. */
static void landing_deck_defaults(fc_controller_params *p, fc_real gear_height_m)
{
    fc_landing_params *l = &p->landing;
    fc_pad_motion_params *m = &p->pad_motion;
    m->mode_period_s[0] = FC_C(8.5f, TIME);
    m->mode_period_s[1] = FC_INT(12, TIME);
    m->mode_period_s[2] = FC_INT(16, TIME);
    m->period_min_s = FC_C(6.5f, TIME);
    m->period_max_s = FC_INT(20, TIME);
    m->frequency_gain = FC_INT(0, UNIT);
    m->forgetting = FC_C(0.99f, UNIT);
    m->outlier_m = FC_C(0.5f, LENGTH);
    m->observe_min_s = FC_INT(10, TIME);
    m->tolerance_m = FC_C(0.2f, LENGTH); /* a 1 s prediction of a 1 m broadband heave */
    l->gear_height_m = gear_height_m;
    l->hold_height_m = FC_C(1.5f, LENGTH);
    l->hold_tau_s = FC_INT(2, TIME);
    l->hold_settle_m = FC_C(0.15f, LENGTH);
    l->descent_tau_s = FC_INT(2, TIME);
    l->touchdown_dip_m = FC_C(0.05f, LENGTH);
    /* descending at up to 0.75 m/s, the 20-40 ms between the GNSS and the
     * ranger's delays shift the pad's samples by centimetres: the check of
     * the predictions gets worse while the estimate now stays good */
    l->confidence_abort = FC_C(0.1f, UNIT);
    /* the pad estimate's error while descending (the delays above: 1-3 cm)
     * and the tracking error's */
    l->touchdown_window_m = FC_C(0.05f, LENGTH);
    /* the laser's noise is 5-10 mm: five samples in a row under 12 mm */
    l->contact_height_m = FC_C(0.012f, LENGTH);
    l->ramp_s = FC_C(0.5f, TIME);
    l->horizontal_start_m = FC_C(0.2f, LENGTH);
    l->horizontal_abort_m = FC_C(0.5f, LENGTH);
    l->pad_accel_max_mps2 = FC_INT(3, ACCEL);
    p->failsafe.descent_mps = FC_C(0.5f, VEL);
}

static void landing_defaults(fc_controller_params *p, fc_airframe airframe)
{
    landing_common_defaults(p);
    if (airframe == FC_AIRFRAME_CRAZYFLIE2) {
        landing_crazyflie_defaults(p);
    } else {
        landing_deck_defaults(p, airframe == FC_AIRFRAME_F450 ? FC_C(0.1f, LENGTH) : FC_C(0.18f, LENGTH));
    }
}

static void attitude_crazyflie_gains(fc_attitude_control_params *a)
{
    /* One rotor at 80 % leaves a constant moment of 0.2 T_hover x 46 mm
     * sin 45 deg = 2.4e-4..7.3e-4 N m on roll and pitch (15..46 g), i.e.
     * d = 14..44 rad/s^2 at Jx = 1.66e-5 kg m^2 (a 4 kg hexa's is ~6). The
     * defaults (wn = 10, kp = 100, no integral) hold it with a d/kp =
     * 0.14..0.44 rad error per axis, more than the horizontal integral
     * (2 m/s^2) takes back: the vehicle flies off (robustness-cf2). With
     * an integral the tilt left over after a step of d is d/ki (rad s),
     * the velocity it costs g d/ki. Roll/pitch: wn = 15 rad/s, zeta = 1
     * (kp = 225, kd = 30), ki = 1200: s^3 (tau s + 1) + kd s^2 + kp s + ki
     * (the motors' lag tau, 15..45 ms) has the integral's pair at
     * -4.2 +- 6j and the fast pair at -25 +- 29j (15 ms), -10 +- 25j
     * (30 ms), -5.4 +- 22j (45 ms; kp = 100's was -5.8 +- 14j there); a
     * step of d = 28 rad/s^2 peaks at 0.09..0.13 rad (0.28..0.30 with kp =
     * 100 and no integral). Yaw keeps wn = 5, adds ki = kp wn/5 = 25
     * (-1.9 +- 0.9j). Bounds: ki I_max = 120 rad/s^2 roll and pitch (26 %
     * of the budget, 7.8e-3 N m / Jx: while it trims a step the integral
     * overshoots d/ki, and a bound of 60 cut that short on vehicles that
     * start heavy), 7.5 rad/s^2 yaw (the weak rotor's torque
     * 0.2 x 0.112 N x 7 mm = 1.6e-4 N m is 5.3 rad/s^2 at Jz). */
    a->kp_per_s2.x = FC_INT(225, GAIN);
    a->kp_per_s2.y = FC_INT(225, GAIN);
    a->kd_per_s.x = FC_INT(30, GAIN);
    a->kd_per_s.y = FC_INT(30, GAIN);
    a->ki_per_s3 = fc_vec3_make(FC_INT(1200, GAIN), FC_INT(1200, GAIN), FC_INT(25, GAIN));
    a->integral_limit_rad = fc_vec3_make(FC_C(0.1f, ANGLE), FC_C(0.1f, ANGLE), FC_C(0.3f, ANGLE));
}

/* The airframe's mass and rotors; returns its inertia (kg m^2). */
static fc_vec3 airframe_defaults(fc_controller_params *p, fc_airframe airframe)
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
    return inertia;
}

void fc_controller_default_params(fc_controller_params *p, fc_airframe airframe, fc_altitude_variant variant,
                                  fc_real dt_s)
{
    const fc_vec3 inertia = airframe_defaults(p, airframe);
    p->dt_s = dt_s;
    p->outer_divider = default_outer_divider(dt_s);
    p->gravity_mps2 = FC_C(9.81f, ACCEL);
    p->use_external_attitude = false;
    fc_attitude_estimator_default_params(&p->estimator, dt_s);
    fc_attitude_control_default_params(&p->attitude, dt_s, inertia);
    p->attitude.moment_limit_nm = moment_budget_nm(&p->allocation);
    if (airframe == FC_AIRFRAME_CRAZYFLIE2) {
        attitude_crazyflie_gains(&p->attitude);
    }
    /* the 4.4 reference: tau_zr = 0.1 s, z_r_init = 1 m, z_r_bias = 0.18 m */
    p->reference.dt_s = dt_s;
    p->reference.tau_s = FC_C(0.1f, TIME);
    p->reference.offset_init_m = FC_C(1.0f, LENGTH);
    p->reference.bias_m = FC_C(0.18f, LENGTH);
    fc_altitude_control_variant_params(&p->altitude, variant, dt_s, p->mass_kg);
    thrust_range_n(&p->allocation, &p->altitude.thrust_min_n, &p->altitude.thrust_max_n);
    /* horizontal PID (2.6.4): wn = 1.5 rad/s, zeta = 0.9, a slow integral,
     * tilt at most 30 deg; no acceleration feedback (k_a = 0). The Crazyflie
     * (position at 100 Hz, 5-11 ms old, its attitude loop at wn = 15):
     * wn = 2.5 rad/s, which halves the drift after a rotor's step loss */
    fc_position_control_params *h = &p->horizontal;
    h->dt_s = outer_step_s(p); /* minor frame 0 of the outer group */
    const bool cf2 = airframe == FC_AIRFRAME_CRAZYFLIE2;
    h->kp_per_s2 = cf2 ? FC_C(6.25f, RATIO) : FC_C(2.25f, RATIO);
    /* a slow integral for every airframe: the Crazyflie's weak-rotor moment is
     * trimmed by its attitude integral above (k_I = 1 makes the hexa's position
     * loop oscillate with growing amplitude in the hexa-deck Monte-Carlo) */
    h->ki_per_s3 = FC_C(0.3f, RATIO);
    h->kd_per_s = cf2 ? FC_C(4.5f, RATIO) : FC_C(2.7f, RATIO);
    h->error_max_m = FC_INT(2, LENGTH);
    h->integral_max_mps2 = FC_INT(2, ACCEL);
    h->accel_max_mps2 = FC_INT(6, ACCEL);
    h->mass_kg = p->mass_kg;
    h->accel_fb_gain_per_s = FC_INT(0, RATIO);
    h->accel_fb_max_mps2 = FC_INT(0, ACCEL);
    h->tilt_max_rad = FC_C(0.5236f, ANGLE);
    /* only the direction of F is used: its floor is a tenth of the weight */
    fc_arith ar = {0u};
    h->thrust_min_n = fc_mul(&ar, fc_mul(&ar, p->mass_kg, p->gravity_mps2, FC_SHIFT(MASS, ACCEL, FORCE)),
                             FC_C(0.1f, UNIT), FC_SHIFT(FORCE, UNIT, FORCE));
    h->thrust_max_n = p->altitude.thrust_max_n;
    landing_defaults(p, airframe);
}

static bool failsafe_params_valid(const fc_failsafe_params *f)
{
    return fc_is_finite(f->bad_input_hold_s) && f->bad_input_hold_s >= FC_INT(0, TIME) &&
           f->bad_input_hold_s <= FC_INT(10, TIME) && fc_is_finite(f->descent_mps) &&
           f->descent_mps > FC_INT(0, VEL) && f->descent_mps <= FC_INT(5, VEL) &&
           fc_is_finite(f->speed_gain_per_s) && f->speed_gain_per_s > FC_INT(0, GAIN) &&
           f->speed_gain_per_s <= FC_INT(50, GAIN) && fc_is_finite(f->max_s) && f->max_s > FC_INT(0, TIME) &&
           f->max_s <= FC_INT(600, TIME);
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
    fc_position_control_reset(&ctl->position);
    ctl->have_attitude_setpoint = false; /* level until the position loop's next minor frame */
    ctl->last_saturation = 0u;
    ctl->last_thrust_n = FC_INT(0, FORCE);
}

static void clear_failsafe(fc_controller *ctl)
{
    ctl->failsafe = false;
    ctl->failsafe_s = FC_INT(0, TIME);
    ctl->failsafe_vz_mps = FC_INT(0, VEL);
    ctl->not_descending_s = FC_INT(0, TIME);
    ctl->failsafe_landed = false;
    ctl->good_input_s = FC_INT(0, TIME);
}

/* Level at the heading: the shortest rotation about z, [cos psi/2, 0, 0, sin psi/2]
 * from (cos psi, sin psi) by the half-angle formula, normalised. Its own
 * saturation record: 1 + cos psi reaches 2 at psi = 0, which UNIT holds only
 * to its last LSB in fixed (the direction is what counts, normalised all the same). */
static fc_quat level_at_heading(fc_real heading_cos, fc_real heading_sin)
{
    fc_arith ar = {0u};
    fc_quat q;
    if (heading_cos >= FC_INT(0, UNIT)) {
        q = (fc_quat){fc_add(&ar, FC_INT(1, UNIT), heading_cos), FC_INT(0, UNIT), FC_INT(0, UNIT), heading_sin};
    } else {
        /* the same rotation without the cancellation near psi = pi */
        q = (fc_quat){heading_sin, FC_INT(0, UNIT), FC_INT(0, UNIT), fc_sub(&ar, FC_INT(1, UNIT), heading_cos)};
    }
    bool ok = false;
    const fc_quat n = fc_quat_normalize(&ar, q, &ok);
    return ok ? n : fc_quat_identity();
}

fc_init_result fc_controller_init(fc_controller *ctl, const fc_controller_params *p)
{
    ctl->ready = false;
    ctl->p = *p;
    ctl->ar.saturated = 0u;
    ctl->last_command = FC_COMMAND_DISARM;
    ctl->last_saturation = 0u;
    ctl->last_attitude = fc_quat_identity();
    ctl->last_thrust_n = FC_INT(0, FORCE);
    ctl->gear_height_m = FC_INT(0, LENGTH);
    ctl->minor_frame = 0u;
    ctl->held_attitude_setpoint = fc_quat_identity();
    ctl->held_position_status = FC_STEP_OK;
    ctl->have_attitude_setpoint = false;
    ctl->pad_estimate = (fc_pad_motion_estimate){0};
    ctl->pad_estimate_age_s = FC_INT(0, DT);
    ctl->pending_pad_height_m = FC_INT(0, LENGTH);
    ctl->pending_pad_age_s = FC_INT(0, DT);
    ctl->pad_sample_pending = false;
    ctl->have_last_good = false;
    ctl->bad_input_s = FC_INT(0, TIME);
    clear_failsafe(ctl);
    /* the heading cache starts at psi = 0 */
    ctl->heading_rad = FC_INT(0, ANGLE);
    ctl->heading_cos = FC_INT(1, UNIT);
    ctl->heading_sin = FC_INT(0, UNIT);
    ctl->heading_level = level_at_heading(ctl->heading_cos, ctl->heading_sin);
    /* every module validates its own parameters; the first failure is the answer */
    fc_init_result result = FC_INIT_OK;
    const fc_init_result parts[] = {
        fc_attitude_estimator_init(&ctl->estimator, &p->estimator),
        fc_attitude_control_init(&ctl->attitude, &p->attitude),
        fc_allocation_init(&ctl->allocation, &p->allocation),
        fc_altitude_reference_init(&ctl->reference, &p->reference),
        fc_altitude_control_init(&ctl->altitude, &p->altitude),
        fc_position_control_init(&ctl->position, &p->horizontal),
        fc_pad_motion_init(&ctl->pad_motion, &p->pad_motion),
        fc_landing_init(&ctl->landing, &p->landing),
    };
    for (unsigned i = 0u; i < sizeof parts / sizeof parts[0]; i++) {
        if (parts[i] != FC_INIT_OK && result == FC_INIT_OK) {
            result = parts[i];
        }
    }
    /* the step uses the allocation's speeds and saturation, not its forward model */
    fc_allocation_set_wrench_output(&ctl->allocation, false);
    /* the inner group on dt, the outer group on dt outer_divider */
    const bool divider_ok = p->outer_divider >= 1u && p->outer_divider <= FC_OUTER_DIVIDER_MAX;
    const fc_real outer_s = outer_step_s(p);
    const bool same_step = divider_ok && p->estimator.dt_s == p->dt_s && p->attitude.dt_s == p->dt_s &&
                           p->reference.dt_s == p->dt_s && p->altitude.dt_s == p->dt_s &&
                           p->horizontal.dt_s == outer_s && p->pad_motion.dt_s == outer_s &&
                           p->landing.dt_s == p->dt_s;
    if (result == FC_INIT_OK &&
        (!same_step || !failsafe_params_valid(&p->failsafe) || !fc_is_finite(p->mass_kg) ||
         !(p->mass_kg > FC_INT(0, MASS)) || !fc_is_finite(p->gravity_mps2) ||
         !(p->gravity_mps2 > FC_INT(0, ACCEL)) || p->gravity_mps2 > FC_INT(100, ACCEL))) {
        result = FC_INIT_BAD_PARAM;
    }
    ctl->step_s = fc_convert(&ctl->ar, p->dt_s, FC_DT_FRAC, FC_TIME_FRAC);
    ctl->ready = result == FC_INIT_OK;
    return result;
}

/* ---------------------------------------------------------------------- */
/* one step                                                                */
/* ---------------------------------------------------------------------- */

/* The filter runs on every step, armed or not, to stay aligned; with the
 * platform's attitude in use it only checks the IMU and forms the rate
 * (fc_attitude_estimator_rate_step), and the heading input goes unused. */
static fc_step_status estimator_step(fc_controller *ctl, const fc_controller_inputs *in, fc_attitude_estimate *est)
{
    if (ctl->p.use_external_attitude) {
        return fc_attitude_estimator_rate_step(&ctl->estimator, &in->imu, est);
    }
    const fc_step_status heading_status =
        in->heading_fresh ? fc_attitude_estimator_take_heading(&ctl->estimator, in->heading_rad) : FC_STEP_OK;
    return fc_attitude_estimator_step(&ctl->estimator, &in->imu, est) | heading_status;
}

/* The attitude in use: the filter's, or the platform's if it is a usable
 * quaternion, taken at the attitude law's resolution (fc_quat16_normalize:
 * UNIT16 in fixed, 6.1e-5 a component; for a quaternion already unit its
 * rounding, with no 32-bit square). */
static fc_quat attitude_in_use(fc_controller *ctl, const fc_controller_inputs *in, const fc_attitude_estimate *est,
                               fc_step_status *status)
{
    if (!ctl->p.use_external_attitude) {
        return est->attitude;
    }
    bool ok = false;
    const fc_quat16 q = fc_quat16_normalize(&ctl->ar, in->attitude_external, &ok);
    if (!ok) {
        *status |= FC_STEP_BAD_INPUT;
        return ctl->last_attitude;
    }
    return fc_quat16_widen(q);
}

/* k_h = cos(roll) cos(pitch): the world-z component of the body z axis, 1 - 2(x^2 + y^2). */
static fc_real tilt_cos_of(fc_arith *ar, fc_quat q)
{
    const fc_real xx_yy = fc_dot2(ar, q.x, q.x, q.y, q.y, FC_SHIFT(UNIT, UNIT, RATIO));
    return fc_sub(ar, FC_INT(1, RATIO), fc_add(ar, xx_yy, xx_yy));
}

/* The inputs are numbers inside the physical range (fc/status.h): beyond it
 * a finite value is as bad as a NaN. The pad trajectory counts when tracking it. */
static bool controller_inputs_usable(const fc_controller_inputs *in)
{
    const fc_real length = FC_C(FC_INPUT_MAX_LENGTH_M, LENGTH);
    const fc_real speed = FC_C(FC_INPUT_MAX_SPEED_MPS, VEL);
    const fc_real accel = FC_C(FC_INPUT_MAX_ACCEL_MPS2, ACCEL);
    const bool pad_ok = in->command != FC_COMMAND_TRACK_PAD ||
                        (fc_within(in->pad.z_m, length) && fc_within(in->pad.vz_mps, speed) &&
                         fc_within(in->pad.az_mps2, accel));
    return fc_vec3_within(in->position_m, length) && fc_vec3_within(in->velocity_mps, speed) &&
           fc_vec3_within(in->position_setpoint_m, length) && fc_within(in->yaw_setpoint_rad, FC_C(7.0f, ANGLE)) &&
           pad_ok;
}

/* The bits of a module's status that the controller passes on. */
static fc_step_status passed_on(fc_step_status module_status)
{
    return module_status & (FC_STEP_BAD_INPUT | FC_STEP_OUTPUT_LIMITED | FC_STEP_ARITH_SATURATED | FC_STEP_DEGRADED);
}

/* The telemetry fields that only some paths of a ready step write (the
 * failsafe has no reference, a disarmed step runs no loop): their values when
 * not written. The others every path of a ready step writes once. */
static void telemetry_defaults(fc_controller_telemetry *tm)
{
    tm->reference.z_m = FC_INT(0, LENGTH);
    tm->reference.vz_mps = FC_INT(0, VEL);
    tm->reference.az_mps2 = FC_INT(0, ACCEL);
    tm->allocation_saturation = 0u;
    tm->altitude_status = FC_STEP_OK;
    tm->attitude_status = FC_STEP_OK;
    tm->allocation_status = FC_STEP_OK;
    tm->touchdown_window = false;
    tm->descent_blocked_by = FC_REASON_NONE;
}

/* The whole telemetry of a controller that is not ready. */
static void telemetry_not_ready(const fc_controller *ctl, fc_controller_telemetry *tm)
{
    telemetry_defaults(tm);
    tm->attitude = ctl->last_attitude;
    tm->attitude_setpoint = ctl->last_attitude;
    tm->rate_radps = fc_vec3_zero();
    tm->tilt_cos = FC_INT(1, RATIO);
    tm->estimator_status = FC_STEP_OK;
    tm->altitude = (fc_altitude_control_output){0};
    tm->pad = (fc_pad_motion_estimate){0};
    tm->gear_height_m = ctl->gear_height_m;
    tm->landing_state = FC_LANDING_IDLE;
    tm->landing_reason = FC_REASON_NONE;
    tm->landing_changed = false;
    tm->aborts = 0u;
}

/* The pad as the range finder sees it: a sample of its surface height
 * z - range k_h (a level pad under the vehicle), and the gear's height above
 * it. The sample waits for the pad model's minor frame (the newest one). */
static fc_step_status observe_pad(fc_controller *ctl, const fc_controller_inputs *in, bool position_ok,
                                  fc_real tilt_cos, bool *range_fresh)
{
    fc_arith *ar = &ctl->ar;
    const bool range_ok = fc_within(in->range_m, FC_INT(100, LENGTH)) && in->range_m >= FC_INT(0, LENGTH);
    *range_fresh = in->range_fresh && range_ok;
    if (*range_fresh) {
        const fc_real vertical_range = fc_mul(ar, in->range_m, tilt_cos, FC_SHIFT(LENGTH, RATIO, LENGTH));
        ctl->gear_height_m = fc_sub(ar, vertical_range, ctl->p.landing.gear_height_m);
        if (position_ok) {
            ctl->pending_pad_height_m = fc_sub(ar, in->position_m.z, vertical_range);
            ctl->pending_pad_age_s = FC_INT(0, DT);
            ctl->pad_sample_pending = true;
        }
    }
    return in->range_fresh && !range_ok ? FC_STEP_BAD_INPUT : FC_STEP_OK;
}

/* z + z' t + z'' t^2 / 2, z' + z'' t, z'': the trajectory t later. */
static fc_vertical_trajectory extrapolated(fc_arith *ar, fc_vertical_trajectory now, fc_real t_s)
{
    /* z'' t, and the mean speed over t, z' + z'' t / 2, times t */
    const fc_real speed_change_mps = fc_mul(ar, now.az_mps2, t_s, FC_SHIFT(ACCEL, DT, VEL));
    const fc_real mean_speed_mps =
        fc_add(ar, now.vz_mps, fc_mul(ar, speed_change_mps, FC_C(0.5f, UNIT), FC_SHIFT(VEL, UNIT, VEL)));
    fc_vertical_trajectory later = now;
    later.z_m = fc_add(ar, now.z_m, fc_mul(ar, mean_speed_mps, t_s, FC_SHIFT(VEL, DT, LENGTH)));
    later.vz_mps = fc_add(ar, now.vz_mps, speed_change_mps);
    return later;
}

/* Minor frame 1 of the outer group (every step with outer_divider 1): the
 * pad model takes the waiting sample, carried to this step along the model's
 * vertical speed, and gives a new estimate; minor frames 2 and on (with
 * outer_divider 3 or more) each do one piece of the model's next step ahead
 * of it (fc_pad_motion_work_ahead), which that step would do first otherwise.
 * On the other steps the estimate is the last one with its trajectory
 * extrapolated to this step. */
static fc_step_status pad_step(fc_controller *ctl, uint8_t frame, fc_pad_motion_estimate *estimate)
{
    fc_arith *ar = &ctl->ar;
    fc_step_status status = FC_STEP_OK;
    const uint8_t divider = ctl->p.outer_divider;
    if (divider >= 3u && frame >= 2u) {
        status = passed_on(fc_pad_motion_work_ahead(&ctl->pad_motion));
    }
    if (frame == (divider > 1u ? 1u : 0u)) {
        fc_pad_motion_sample sample = {FC_INT(0, LENGTH), false};
        if (ctl->pad_sample_pending) {
            const fc_real carried_m =
                fc_mul(ar, ctl->pad_estimate.now.vz_mps, ctl->pending_pad_age_s, FC_SHIFT(VEL, DT, LENGTH));
            sample.height_m = fc_add(ar, ctl->pending_pad_height_m, carried_m);
            sample.fresh = true;
            ctl->pad_sample_pending = false;
        }
        status |= passed_on(fc_pad_motion_step(&ctl->pad_motion, &sample, &ctl->pad_estimate));
        ctl->pad_estimate_age_s = FC_INT(0, DT);
    }
    *estimate = ctl->pad_estimate;
    if (ctl->pad_estimate_age_s != FC_INT(0, DT)) {
        estimate->now = extrapolated(ar, ctl->pad_estimate.now, ctl->pad_estimate_age_s);
    }
    /* one step older (bounded: the pad frame comes every outer_divider steps) */
    ctl->pad_estimate_age_s = fc_min(fc_add(ar, ctl->pad_estimate_age_s, ctl->p.dt_s), FC_C(1.0f, DT));
    if (ctl->pad_sample_pending) {
        ctl->pending_pad_age_s = fc_min(fc_add(ar, ctl->pending_pad_age_s, ctl->p.dt_s), FC_C(1.0f, DT));
    }
    return status;
}

/* The heading's (cos, sin) and level attitude, recomputed only when the setpoint changes. */
static void update_heading(fc_controller *ctl, fc_real yaw_rad)
{
    if (yaw_rad != ctl->heading_rad) {
        ctl->heading_rad = yaw_rad;
        fc_sincos(&ctl->ar, yaw_rad, &ctl->heading_sin, &ctl->heading_cos);
        ctl->heading_level = level_at_heading(ctl->heading_cos, ctl->heading_sin);
    }
}

/* Level at the heading of the setpoint (0 if it is no angle). */
static fc_quat level_attitude(fc_controller *ctl, fc_real yaw_rad)
{
    update_heading(ctl, fc_within(yaw_rad, FC_C(7.0f, ANGLE)) ? yaw_rad : FC_INT(0, ANGLE));
    return ctl->heading_level;
}

/* Horizontal PID -> F = m (a_des - g) -> attitude setpoint (fc/position_control.h),
 * in minor frame 0 of the outer group only, so that its cost never adds to
 * that of another part; held, with its status, for the major frame. Until
 * its first run (after arming, a reset or a level phase: at most
 * outer_divider - 1 steps, 8 ms at 500 Hz) the setpoint is level at the heading. */
static fc_step_status horizontal_step(fc_controller *ctl, const fc_controller_inputs *in, bool position_frame,
                                      fc_quat *attitude_sp)
{
    if (position_frame) {
        update_heading(ctl, in->yaw_setpoint_rad);
        const fc_position_control_input pin = {in->position_m,     in->velocity_mps,   in->position_setpoint_m,
                                               fc_vec3_zero(),     fc_vec3_zero(),     fc_vec3_zero(),
                                               ctl->heading_cos,   ctl->heading_sin};
        fc_position_control_output pout;
        ctl->held_position_status = passed_on(fc_position_control_step(&ctl->position, &pin, &pout));
        ctl->held_attitude_setpoint = pout.attitude_sp;
        ctl->have_attitude_setpoint = true;
    } else if (!ctl->have_attitude_setpoint) {
        *attitude_sp = level_attitude(ctl, in->yaw_setpoint_rad);
        return FC_STEP_OK;
    } else {
        /* held */
    }
    *attitude_sp = ctl->held_attitude_setpoint;
    return ctl->held_position_status;
}

/* Failsafe: a vertical-speed loop on the speed integrated from the
 * accelerometer, T = m (g + k_v (v_fs - v)) / k_h, and the motors stop when the
 * vehicle has stopped descending for 1 s (it is on the ground) or after max_s. */
static fc_real failsafe_thrust(fc_controller *ctl, const fc_controller_inputs *in, fc_quat attitude,
                               fc_real tilt_cos, fc_step_status estimator_status)
{
    fc_arith *ar = &ctl->ar;
    const fc_failsafe_params *f = &ctl->p.failsafe;
    if ((estimator_status & FC_STEP_BAD_INPUT) == 0u) {
        /* a_z = (R f)_z - g */
        const fc_vec3 specific_force_world = fc_quat_rotate(ar, attitude, in->imu.accel_mps2);
        const fc_real accel_z = fc_sub(ar, specific_force_world.z, ctl->p.gravity_mps2);
        ctl->failsafe_vz_mps =
            fc_clamp(fc_add(ar, ctl->failsafe_vz_mps, fc_mul(ar, accel_z, ctl->p.dt_s, FC_SHIFT(ACCEL, DT, VEL))),
                     FC_INT(-20, VEL), FC_INT(20, VEL));
    }
    ctl->failsafe_s = fc_min(fc_add(ar, ctl->failsafe_s, ctl->step_s), FC_INT(600, TIME));
    /* not descending: slower than a third of the failsafe rate */
    const bool descending = ctl->failsafe_vz_mps < fc_neg(ar, fc_mul(ar, f->descent_mps, FC_C(0.33f, UNIT),
                                                                      FC_SHIFT(VEL, UNIT, VEL)));
    ctl->not_descending_s = descending ? FC_INT(0, TIME) : fc_add(ar, ctl->not_descending_s, ctl->step_s);
    if ((ctl->failsafe_s > FC_C(1.5f, TIME) && ctl->not_descending_s > FC_INT(1, TIME)) || ctl->failsafe_s >= f->max_s) {
        ctl->failsafe_landed = true;
    }
    /* the mass: the adapted Theta of the altitude law (its nominal when not adaptive) */
    const fc_real mass = fc_clamp(ctl->altitude.theta_kg, ctl->p.altitude.mass_min_kg, ctl->p.altitude.mass_max_kg);
    const fc_real speed_error = fc_sub(ar, fc_neg(ar, f->descent_mps), ctl->failsafe_vz_mps);
    const fc_real accel = fc_add(ar, ctl->p.gravity_mps2,
                                 fc_mul(ar, f->speed_gain_per_s, speed_error, FC_SHIFT(GAIN, VEL, ACCEL)));
    const fc_real vertical = fc_mul(ar, mass, accel, FC_SHIFT(MASS, ACCEL, FORCE));
    const fc_real k_h = fc_max(tilt_cos, FC_C(0.5f, RATIO));
    const fc_real thrust = fc_div(ar, vertical, k_h, FC_DIV_SHIFT(FORCE, RATIO, FORCE));
    return fc_clamp(thrust, ctl->p.altitude.thrust_min_n, ctl->p.altitude.thrust_max_n);
}

/* The bad-input bookkeeping: the inputs to fly on (the last good ones for a
 * while), and whether the failsafe takes over. */
static const fc_controller_inputs *inputs_to_use(fc_controller *ctl, const fc_controller_inputs *in, bool inputs_ok,
                                                 bool armed)
{
    fc_arith *ar = &ctl->ar;
    if (inputs_ok) {
        /* what a bad step flies on; the rest it takes from its own inputs (below) */
        ctl->last_good.position_m = in->position_m;
        ctl->last_good.velocity_mps = in->velocity_mps;
        ctl->last_good.pad = in->pad;
        ctl->last_good.position_setpoint_m = in->position_setpoint_m;
        ctl->last_good.yaw_setpoint_rad = in->yaw_setpoint_rad;
        ctl->have_last_good = true;
        ctl->bad_input_s = FC_INT(0, TIME);
        if (ctl->failsafe) {
            ctl->good_input_s = fc_add(ar, ctl->good_input_s, ctl->step_s);
            if (ctl->good_input_s > ctl->p.failsafe.bad_input_hold_s && !ctl->failsafe_landed) {
                /* back: the mission starts again from HOLD (tracking from its reference) */
                clear_failsafe(ctl);
                ctl->last_command = FC_COMMAND_DISARM;
                fc_landing_force(&ctl->landing, FC_LANDING_IDLE, FC_REASON_INPUTS_BACK);
            }
        }
        return in;
    }
    ctl->good_input_s = FC_INT(0, TIME);
    ctl->bad_input_s = fc_min(fc_add(ar, ctl->bad_input_s, ctl->step_s), FC_INT(600, TIME));
    if (armed && !ctl->failsafe && (ctl->bad_input_s > ctl->p.failsafe.bad_input_hold_s || !ctl->have_last_good)) {
        ctl->failsafe = true;
        ctl->failsafe_vz_mps = ctl->have_last_good ? ctl->last_good.velocity_mps.z : FC_INT(0, VEL);
        fc_landing_force(&ctl->landing, FC_LANDING_FAILSAFE, FC_REASON_INPUTS_LOST);
    }
    if (ctl->have_last_good) {
        /* the sensors' values from the last good step; the command, IMU and range of this one */
        ctl->last_good.imu = in->imu;
        ctl->last_good.attitude_external = in->attitude_external;
        ctl->last_good.range_m = in->range_m;
        ctl->last_good.range_fresh = in->range_fresh;
        ctl->last_good.command = in->command;
        return &ctl->last_good;
    }
    return in;
}

static fc_landing_request landing_request_of(fc_controller_command command)
{
    switch (command) {
    case FC_COMMAND_HOLD:
        return FC_LANDING_REQUEST_HOLD;
    case FC_COMMAND_LAND:
        return FC_LANDING_REQUEST_LAND;
    case FC_COMMAND_DISARM:
    case FC_COMMAND_TRACK_PAD:
    case FC_COMMAND_COUNT:
    default:
        return FC_LANDING_REQUEST_NONE;
    }
}

static bool command_arms(fc_controller_command command)
{
    return command == FC_COMMAND_TRACK_PAD || command == FC_COMMAND_HOLD || command == FC_COMMAND_LAND;
}

/* The horizontal error to the pad's centre, |p_xy - sp_xy|. */
static fc_real horizontal_error_m(fc_arith *ar, const fc_controller_inputs *in)
{
    const fc_real dx = fc_sub(ar, in->position_m.x, in->position_setpoint_m.x);
    const fc_real dy = fc_sub(ar, in->position_m.y, in->position_setpoint_m.y);
    return fc_hypot3(ar, dx, dy, FC_INT(0, LENGTH));
}

static void landing_telemetry(const fc_controller *ctl, fc_controller_telemetry *tm, fc_landing_state state_before,
                              fc_landing_reason reason_before)
{
    tm->landing_state = ctl->landing.state;
    tm->landing_reason = ctl->landing.reason;
    tm->landing_changed = ctl->landing.state != state_before || ctl->landing.reason != reason_before;
    tm->aborts = ctl->landing.aborts;
}

fc_step_status fc_controller_step(fc_controller *ctl, const fc_controller_inputs *in_raw, fc_controller_outputs *out)
{
    fc_controller_telemetry *tm = &out->telemetry;
    if (!ctl->ready) {
        motors_off(ctl, out);
        telemetry_not_ready(ctl, tm);
        return FC_STEP_NOT_READY;
    }
    /* Outputs written once: the motors at the end of each path (off on the
     * paths that return early), the telemetry as it is formed, the fields
     * that only some paths form set first */
    telemetry_defaults(tm);
    fc_arith *ar = &ctl->ar;
    ar->saturated = 0u;
    fc_step_status status = FC_STEP_OK;
    /* the minor frame: the outer group's parts each in their own (header) */
    const uint8_t frame = ctl->minor_frame;
    ctl->minor_frame = (uint8_t)(frame + 1u < ctl->p.outer_divider ? frame + 1u : 0u);
    const bool position_frame = frame == 0u;
    const fc_landing_state state_before = ctl->landing.state;
    const fc_landing_reason reason_before = ctl->landing.reason;

    fc_attitude_estimate estimate;
    tm->estimator_status = estimator_step(ctl, in_raw, &estimate);
    status |= passed_on(tm->estimator_status);
    const fc_quat attitude = attitude_in_use(ctl, in_raw, &estimate, &status);
    ctl->last_attitude = attitude;
    tm->attitude = attitude;
    tm->attitude_setpoint = attitude;
    tm->rate_radps = estimate.rate_radps;
    tm->tilt_cos = tilt_cos_of(ar, attitude);

    const bool command_valid = command_arms(in_raw->command);
    const bool inputs_ok = controller_inputs_usable(in_raw);
    if (!inputs_ok) {
        status |= FC_STEP_BAD_INPUT;
    }
    const fc_controller_inputs *in = inputs_to_use(ctl, in_raw, inputs_ok, command_valid);

    /* the pad, learnt from the range finder in its minor frame */
    bool range_fresh = false;
    status |= observe_pad(ctl, in_raw, inputs_ok, tm->tilt_cos, &range_fresh);
    status |= pad_step(ctl, frame, &tm->pad);
    tm->gear_height_m = ctl->gear_height_m;

    if (!command_valid || (ctl->failsafe && ctl->failsafe_landed)) {
        /* disarmed, or the failsafe ended on the ground: motors off, loops reset */
        if (ctl->last_command != FC_COMMAND_DISARM) {
            reset_loops(ctl);
        }
        if (!command_valid) {
            clear_failsafe(ctl);
            fc_landing_reset(&ctl->landing);
        } else {
            fc_landing_force(&ctl->landing, FC_LANDING_LANDED, FC_REASON_FAILSAFE_LANDED);
            status |= FC_STEP_DEGRADED;
        }
        ctl->last_command = FC_COMMAND_DISARM;
        tm->altitude = (fc_altitude_control_output){0};
        landing_telemetry(ctl, tm, state_before, reason_before);
        motors_off(ctl, out);
        return status;
    }
    if (ctl->last_command != in->command && !ctl->failsafe) {
        const bool from_mission = ctl->last_command == FC_COMMAND_HOLD || ctl->last_command == FC_COMMAND_LAND;
        const bool to_mission = in->command == FC_COMMAND_HOLD || in->command == FC_COMMAND_LAND;
        if (!(from_mission && to_mission)) {
            /* a new task: loops start clean; (3.6) starts again from z_r_init */
            reset_loops(ctl);
            fc_altitude_reference_restart(&ctl->reference, ctl->p.reference.offset_init_m);
            fc_landing_reset(&ctl->landing);
        }
    }
    ctl->last_command = in->command;

    /* the vertical: what the altitude law tracks, or the ramp, or the failsafe */
    bool fly_reference = true;
    bool motors_on = true;
    fc_real thrust_n = FC_INT(0, FORCE);
    bool level = false;
    if (ctl->failsafe) {
        thrust_n = failsafe_thrust(ctl, in_raw, attitude, tm->tilt_cos, tm->estimator_status);
        fly_reference = false;
        level = true;
        status |= FC_STEP_DEGRADED;
    } else if (in->command == FC_COMMAND_TRACK_PAD) {
        status |= passed_on(fc_altitude_reference_step(&ctl->reference, &in->pad, &tm->reference));
    } else {
        const fc_landing_input lin = {landing_request_of(in->command), in->position_m.z, horizontal_error_m(ar, in),
                                      tm->tilt_cos, ctl->gear_height_m, range_fresh, ctl->last_thrust_n, &tm->pad};
        fc_landing_output lout;
        status |= passed_on(fc_landing_step(&ctl->landing, &lin, &lout));
        tm->reference = lout.reference;
        tm->touchdown_window = lout.touchdown_window;
        tm->descent_blocked_by = lout.blocked_by;
        fly_reference = lout.fly_reference;
        motors_on = lout.motors_on;
        thrust_n = lout.ramp_thrust_n;
        level = !fly_reference;
    }
    landing_telemetry(ctl, tm, state_before, reason_before);
    if (!motors_on || !fly_reference) {
        tm->altitude = (fc_altitude_control_output){0};
    }
    if (!motors_on) {
        reset_loops(ctl);
        motors_off(ctl, out);
        return status;
    }
    if (fly_reference) {
        const fc_altitude_control_input altitude_in = {in->position_m.z, in->velocity_mps.z, tm->reference,
                                                       tm->tilt_cos, ctl->last_saturation};
        tm->altitude_status = fc_altitude_control_step(&ctl->altitude, &altitude_in, &tm->altitude);
        status |= passed_on(tm->altitude_status);
        thrust_n = tm->altitude.thrust_n;
    }

    /* attitude: setpoint from the horizontal loop (level in the failsafe and the ramp), then the moments */
    if (level) {
        tm->attitude_setpoint = level_attitude(ctl, in->yaw_setpoint_rad);
        ctl->have_attitude_setpoint = false; /* the loop starts afresh after a level phase */
    } else {
        status |= horizontal_step(ctl, in, position_frame, &tm->attitude_setpoint);
    }
    /* on the pad (contact being confirmed, the thrust ramp) the feet and not
     * the moments hold the attitude: the integrals hold their trim */
    fc_attitude_control_hold_integral(&ctl->attitude, ctl->landing.state == FC_LANDING_TOUCHDOWN ||
                                                          ctl->landing.state == FC_LANDING_DISARM);
    const fc_attitude_control_input attitude_in = {attitude, tm->attitude_setpoint, estimate.rate_radps,
                                                   fc_vec3_zero(), ctl->last_saturation};
    fc_attitude_control_output attitude_out;
    tm->attitude_status = fc_attitude_control_step(&ctl->attitude, &attitude_in, &attitude_out);
    status |= passed_on(tm->attitude_status);

    /* allocation */
    const fc_allocation_demand demand = {thrust_n, attitude_out.moment_nm};
    fc_allocation_output allocation_out;
    tm->allocation_status = fc_allocation_step(&ctl->allocation, &demand, &allocation_out);
    status |= passed_on(tm->allocation_status);
    ctl->last_saturation = allocation_out.saturation;
    ctl->last_thrust_n = thrust_n;
    tm->allocation_saturation = allocation_out.saturation;

    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        out->rotor_speed[i] = allocation_out.speed[i];
    }
    out->rotor_count = ctl->allocation.rotor_count;
    out->motors_on = true;
    out->thrust_n = demand.thrust_n;
    out->moment_nm = demand.moment_nm;
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

/* controller_params.c - fc_controller's parameters (fc/controller.h): the
 * airframe presets, the nominal mass and what follows it, and the checks
 * across modules that fc_controller_init makes. Run at init only, apart
 * from the step. */
#include "fc/controller.h"
#include "controller_params.h"

fc_real fc_controller_outer_step_s(const fc_controller_params *p)
{
    fc_arith ar = {0u};
    fc_real sum = FC_INT(0, DT);
    for (unsigned i = 0u; i < p->outer_divider && i < FC_OUTER_DIVIDER_MAX; i++) {
        sum = fc_add(&ar, sum, p->dt_s);
    }
    return sum;
}

void fc_controller_set_outer_divider(fc_controller_params *p, uint8_t divider)
{
    p->outer_divider = divider;
    p->horizontal.dt_s = fc_controller_outer_step_s(p);
    p->pad_motion.dt_s = fc_controller_outer_step_s(p);
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

/* The landing mission's defaults common to every airframe (fc/landing.h, fc/pad_motion.h). */
static void landing_common_defaults(fc_controller_params *p)
{
    fc_landing_params *l = &p->landing;
    fc_pad_motion_params *m = &p->pad_motion;
    l->dt_s = p->dt_s;
    m->dt_s = fc_controller_outer_step_s(p); /* minor frame 1 of the outer group */
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
    /* descent shaping (2.25)-(2.28), off unless asked for. Centred, (2.26)
     * and (2.27) ask for k_r / delta_h + u_zbias = 0.4 m/s down, which
     * (3.6)'s own rate caps near the pad; 0.1 m off centre, 0.2 m/s.
     * (2.28): k_a |(d_h)_pad| / (|z| + delta_a), for a centred vehicle well
     * above the pad about k_a sin(tilt): the descent slows on a tilted deck
     * and holds at about 25 deg; off centre and near the pad it is the
     * horizontal offset that counts, |d_h| / (|z| + delta_a). Climbs are
     * slow (0.1 m/s): the field's climb while the deck rolls must not undo
     * the descent of its level moments. The descent commits 8 cm above the
     * surface, clear of a foot 0.3 m out on a deck tilted up to 15 deg */
    l->descent_shaping = false;
    l->shaping_commit_m = FC_C(0.08f, LENGTH);
    l->shaping_filter_s = FC_C(0.3f, TIME);
    l->shaping.k_r_m2ps = FC_C(0.03f, GAIN);
    l->shaping.delta_h_m = FC_C(0.1f, LENGTH);
    l->shaping.k_c_per_s = FC_C(0.5f, GAIN);
    l->shaping.u_zbias_mps = FC_C(0.1f, VEL);
    l->shaping.k_a_mps = FC_INT(1, GAIN);
    l->shaping.delta_a_m = FC_C(0.1f, LENGTH);
    l->shaping.max_descent_mps = FC_INT(1, VEL);
    l->shaping.max_climb_mps = FC_C(0.1f, VEL);
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
}

/* The safety parts (fc/input_gate.h, fc/vertical_estimator.h,
 * fc/land_detector.h, fc/failsafe.h), sized from the airframe: the gates
 * from its top speed and what its rotors can accelerate it by (T_max / m),
 * the hover thrust from its weight. The Crazyflie (motion capture or a
 * lighthouse, millimetres) flies slower and descends slower than the larger
 * vehicles (GNSS-class positions, centimetres to decimetres). */
static void safety_defaults(fc_controller_params *p, fc_airframe airframe)
{
    fc_arith ar = {0u};
    const bool cf2 = airframe == FC_AIRFRAME_CRAZYFLIE2;
    const fc_real weight_n = fc_mul(&ar, p->mass_kg, p->gravity_mps2, FC_SHIFT(MASS, ACCEL, FORCE));
    const fc_real accel_max_mps2 =
        fc_div(&ar, p->altitude.thrust_max_n, p->mass_kg, FC_DIV_SHIFT(FORCE, MASS, ACCEL));
    fc_input_gate_default_params(&p->gate, p->dt_s, cf2 ? FC_INT(5, VEL) : FC_INT(15, VEL),
                                 fc_clamp(accel_max_mps2, FC_INT(1, ACCEL), FC_INT(200, ACCEL)),
                                 cf2 ? FC_C(0.1f, LENGTH) : FC_C(0.3f, LENGTH));
    fc_vertical_estimator_default_params(&p->vertical, p->dt_s, p->gravity_mps2, weight_n);
    fc_land_detector_default_params(&p->land_detector, p->dt_s);
    fc_failsafe_default_params(&p->failsafe, p->dt_s, p->gravity_mps2, cf2 ? FC_C(0.3f, VEL) : FC_C(0.5f, VEL));
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

/* A slow tilt integral, ki = kp wn / 10 (the default wn = 10 rad/s, kp = 100:
 * ki = 100, the integral's pole near -1 rad/s), so that a steady moment (a
 * weak rotor, an offset centre of mass) is held with no steady attitude
 * error. The failsafe needs that: it flies level with no position loop, and
 * in flight the filter's accelerometer sees the thrust axis as up, so the
 * only attitude it can hold still is its estimate level; an error held
 * against that correction turns into a tilt that grows at the filter's k_p
 * times the error (fc/attitude_estimator.h), where the position loop's
 * tilt had balanced it. */
static void attitude_tilt_integral(fc_attitude_control_params *a)
{
    a->ki_per_s3.x = FC_INT(100, GAIN);
    a->ki_per_s3.y = FC_INT(100, GAIN);
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

/* What a gyro sample may change by (fc/attitude_estimator.h): the angular
 * acceleration all the rotors give on the roll or pitch axis (twice the
 * authority, over the inertia), and 0.5 rad/s of noise. */
static void gyro_plausibility(fc_controller_params *p, fc_vec3 inertia)
{
    fc_arith ar = {0u};
    const fc_vec3 budget = p->attitude.authority_nm;
    const fc_real roll = fc_div(&ar, fc_add(&ar, budget.x, budget.x), inertia.x, FC_DIV_SHIFT(MOMENT, INERTIA, GAIN));
    const fc_real pitch = fc_div(&ar, fc_add(&ar, budget.y, budget.y), inertia.y, FC_DIV_SHIFT(MOMENT, INERTIA, GAIN));
    p->estimator.gyro_accel_max_radps2 = fc_clamp(fc_max(roll, pitch), FC_INT(1, GAIN), FC_INT(30000, GAIN));
    p->estimator.gyro_jump_radps = FC_C(0.5f, RATE);
}

/* Everything that follows from the airframe's mass, inertia and rotors
 * (p->mass_kg, p->allocation), with the gains and limits of airframe. */
static void defaults_around(fc_controller_params *p, fc_airframe airframe, fc_vec3 inertia,
                            fc_altitude_variant variant, fc_real dt_s)
{
    p->dt_s = dt_s;
    p->outer_divider = default_outer_divider(dt_s);
    p->gravity_mps2 = FC_C(9.81f, ACCEL);
    p->use_external_attitude = false;
    fc_attitude_estimator_default_params(&p->estimator, dt_s);
    fc_attitude_control_default_params(&p->attitude, dt_s, inertia);
    /* the normalised units of the attitude and altitude laws are the allocation's */
    fc_real thrust_authority_n;
    (void)fc_allocation_authority_of(&p->allocation, &thrust_authority_n, &p->attitude.authority_nm);
    gyro_plausibility(p, inertia);
    if (airframe == FC_AIRFRAME_CRAZYFLIE2) {
        attitude_crazyflie_gains(&p->attitude);
    } else {
        attitude_tilt_integral(&p->attitude);
    }
    /* the 4.4 reference: tau_zr = 0.1 s, z_r_init = 1 m, z_r_bias = 0.18 m */
    p->reference.dt_s = dt_s;
    p->reference.tau_s = FC_C(0.1f, TIME);
    p->reference.offset_init_m = FC_C(1.0f, LENGTH);
    p->reference.bias_m = FC_C(0.18f, LENGTH);
    fc_altitude_control_variant_params(&p->altitude, variant, dt_s, p->mass_kg);
    thrust_range_n(&p->allocation, &p->altitude.thrust_min_n, &p->altitude.thrust_max_n);
    p->altitude.thrust_authority_n = thrust_authority_n;
    /* horizontal PID (2.6.4): wn = 1.5 rad/s, zeta = 0.9, a slow integral,
     * tilt at most 30 deg. The Crazyflie
     * (position at 100 Hz, 5-11 ms old, its attitude loop at wn = 15):
     * wn = 2.5 rad/s, which halves the drift after a rotor's step loss */
    fc_position_control_params *h = &p->horizontal;
    h->dt_s = fc_controller_outer_step_s(p); /* minor frame 0 of the outer group */
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
    /* acceleration feedback (2.10)-(2.11), horizontal (controller.c): I_a
     * takes a horizontal force the model lacks (wind on a changed mass,
     * drag) at k_a, faster than the slow position integral; |I_a| <= 1.5
     * m/s2 (8.7 deg of tilt). k_a = 1 /s from the SIL (sim_host/README.md:
     * the accel-feedback-mass-step scenario, and a sweep of k_a over the
     * hexa-deck and cf2-pad Monte-Carlo); the Crazyflie takes half of it,
     * its position loop (wn = 2.5 rad/s, the position 5-11 ms old) being
     * the first to oscillate as k_a grows. 0 flies without it */
    h->accel_fb_gain_per_s = cf2 ? FC_C(0.5f, RATIO) : FC_C(1.0f, RATIO);
    h->accel_fb_max_mps2 = FC_C(1.5f, ACCEL);
    h->tilt_max_rad = FC_C(0.5236f, ANGLE);
    h->thrust_max_n = p->altitude.thrust_max_n;
    landing_defaults(p, airframe);
    safety_defaults(p, airframe);
    fc_controller_set_mass(p, p->mass_kg);
    /* the rotors, unless fc_controller_set_velocity_output; a valid law all the same */
    p->output = FC_OUTPUT_ROTORS;
    fc_controller_velocity_defaults(&p->velocity, fc_vec3_make(FC_INT(1, RATIO), FC_INT(1, RATIO), FC_INT(1, RATIO)),
                                    fc_vec3_make(FC_INT(1, RATIO), FC_INT(1, RATIO), FC_INT(1, RATIO)));
}

void fc_controller_velocity_defaults(fc_velocity_output_params *v, fc_vec3 k_p_per_s, fc_vec3 a_p_per_s)
{
    fc_trajectory_tracking_params *t = &v->tracking;
    t->k_p_per_s = k_p_per_s;
    t->a_p_per_s = a_p_per_s;
    t->zeta = fc_vec3_make(FC_INT(1, RATIO), FC_INT(1, RATIO), FC_INT(1, RATIO));
    t->omega_n_radps = fc_vec3_make(FC_C(1.5f, RATE), FC_C(1.5f, RATE), FC_INT(2, RATE));
    t->u_max_mps = fc_vec3_make(FC_INT(3, VEL), FC_INT(3, VEL), FC_C(1.5f, VEL));
    v->yaw_gain_per_s = FC_INT(1, RATIO);
    v->yaw_rate_max_radps = FC_C(0.5f, RATE);
}

void fc_controller_set_velocity_output(fc_controller_params *p, const fc_velocity_output_params *v)
{
    p->output = FC_OUTPUT_VELOCITY;
    p->velocity = *v;
}

void fc_controller_default_params(fc_controller_params *p, fc_airframe airframe, fc_altitude_variant variant,
                                  fc_real dt_s)
{
    const fc_vec3 inertia = airframe_defaults(p, airframe);
    defaults_around(p, airframe, inertia, variant, dt_s);
}

void fc_controller_default_params_for(fc_controller_params *p, fc_airframe gains_of,
                                      const fc_allocation_params *rotors, fc_real mass_kg, fc_vec3 inertia_kgm2,
                                      fc_altitude_variant variant, fc_real dt_s)
{
    (void)airframe_defaults(p, gains_of);
    p->allocation = *rotors;
    p->mass_kg = mass_kg;
    defaults_around(p, gains_of, inertia_kgm2, variant, dt_s);
}

void fc_controller_set_mass(fc_controller_params *p, fc_real mass_kg)
{
    fc_arith ar = {0u};
    p->mass_kg = mass_kg;
    p->horizontal.mass_kg = mass_kg;
    fc_altitude_control_set_mass(&p->altitude, mass_kg);
    const fc_real weight_n = fc_mul(&ar, mass_kg, p->gravity_mps2, FC_SHIFT(MASS, ACCEL, FORCE));
    /* the position loop uses only the direction of F: its floor is a tenth of the weight */
    p->horizontal.thrust_min_n = fc_mul(&ar, weight_n, FC_C(0.1f, UNIT), FC_SHIFT(FORCE, UNIT, FORCE));
    fc_vertical_estimator_set_weight(&p->vertical, weight_n);
}

/* One g across the modules that use it. */
static bool one_gravity(const fc_controller_params *p)
{
    const fc_real g = p->gravity_mps2;
    return fc_is_finite(g) && g > FC_INT(0, ACCEL) && g <= FC_INT(100, ACCEL) && p->estimator.gravity_mps2 == g &&
           p->altitude.gravity_mps2 == g && p->vertical.gravity_mps2 == g && p->failsafe.gravity_mps2 == g;
}

/* One nominal mass: the position loop's, and inside the altitude law's
 * bounds, as its Theta0 is (Theta0 = m / (k_h k_g) at hover out of ground
 * effect is the mass). */
static bool one_mass(const fc_controller_params *p)
{
    const fc_real m = p->mass_kg;
    return fc_is_finite(m) && m > FC_INT(0, MASS) && p->horizontal.mass_kg == m &&
           fc_in_range(m, p->altitude.mass_min_kg, p->altitude.mass_max_kg) &&
           fc_in_range(p->altitude.theta0_kg, p->altitude.mass_min_kg, p->altitude.mass_max_kg);
}

/* SPEC "Units between modules": the attitude and altitude laws' normalised
 * units are the allocation's authorities, bit for bit (one function forms them). */
static bool one_authority(const fc_controller_params *p)
{
    fc_real thrust_n;
    fc_vec3 moment_nm;
    if (!fc_allocation_authority_of(&p->allocation, &thrust_n, &moment_nm)) {
        return true; /* the allocation's own init reports its parameters */
    }
    const fc_vec3 a = p->attitude.authority_nm;
    return p->altitude.thrust_authority_n == thrust_n && a.x == moment_nm.x && a.y == moment_nm.y &&
           a.z == moment_nm.z;
}

/* The parameters' agreement across modules: one step (the inner group's
 * dt, the outer group's dt outer_divider), then SPEC's "Safety contract":
 * one g, one nominal mass, and a maximum thrust of at least 1.5 x the
 * weight and at most what the rotors give (their sum, to a rounding of 1 %);
 * and one set of normalised units. */
fc_init_result fc_controller_params_agree(const fc_controller_params *p)
{
    const bool divider_ok = p->outer_divider >= 1u && p->outer_divider <= FC_OUTER_DIVIDER_MAX;
    const fc_real outer_s = fc_controller_outer_step_s(p);
    const fc_real dt = p->dt_s;
    const bool same_step = divider_ok && p->estimator.dt_s == dt && p->attitude.dt_s == dt &&
                           p->reference.dt_s == dt && p->altitude.dt_s == dt && p->horizontal.dt_s == outer_s &&
                           p->pad_motion.dt_s == outer_s && p->landing.dt_s == dt && p->gate.dt_s == dt &&
                           p->vertical.dt_s == dt && p->land_detector.dt_s == dt && p->failsafe.dt_s == dt;
    if (!same_step) {
        return FC_INIT_BAD_PARAM;
    }
    if (!one_gravity(p)) {
        return FC_INIT_GRAVITY_MISMATCH;
    }
    if (!one_mass(p)) {
        return FC_INIT_MASS_MISMATCH;
    }
    if (p->output == FC_OUTPUT_VELOCITY) {
        /* the vehicle's own autopilot has the rotors and their thrust (fc/controller.h) */
        return FC_INIT_OK;
    }
    fc_arith ar = {0u};
    const fc_real weight_n = fc_mul(&ar, p->mass_kg, p->gravity_mps2, FC_SHIFT(MASS, ACCEL, FORCE));
    if (p->altitude.thrust_max_n < fc_mul(&ar, weight_n, FC_C(1.5f, RATIO), FC_SHIFT(FORCE, RATIO, FORCE)) ||
        ar.saturated != 0u) {
        return FC_INIT_THRUST_TOO_LOW;
    }
    fc_real rotors_min_n;
    fc_real rotors_max_n;
    thrust_range_n(&p->allocation, &rotors_min_n, &rotors_max_n);
    if (p->altitude.thrust_max_n > fc_mul(&ar, rotors_max_n, FC_C(1.01f, RATIO), FC_SHIFT(FORCE, RATIO, FORCE))) {
        return FC_INIT_THRUST_ABOVE_ROTORS;
    }
    return one_authority(p) ? FC_INIT_OK : FC_INIT_AUTHORITY_MISMATCH;
}

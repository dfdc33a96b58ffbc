/*
 * fuzz_params: every _init on raw parameter bit patterns. Byte 0 picks the
 * module (estimator, attitude control, allocation, altitude reference,
 * altitude control, controller) and, for the defaults the raw bytes are laid
 * over, the airframe (bits 3-4); byte 1 the altitude-law variant; byte 2 the
 * offset (in 4-byte words) at which the rest of the input overwrites the
 * default parameters (so every field is reachable; a short input changes a
 * few). bool fields are reduced to their low bit (another bit pattern is not
 * a bool in C).
 * Whatever init returns, nothing may crash and a step must give finite
 * outputs (with FC_STEP_NOT_READY when init failed); when init returned
 * FC_INIT_OK, FUZZ_CLEAN_STEPS nominal steps must also keep the outputs inside
 * the limits the accepted parameters state.
 */
#include "fuzz_controller_check.h"

static void fix_bool(bool *v)
{
    unsigned char c;
    memcpy(&c, v, 1);
    c &= 1u;
    memcpy(v, &c, 1);
}

static void overlay(fuzz_bytes *b, void *params, size_t n, uint8_t word_offset)
{
    const size_t off = ((size_t)word_offset * 4u) % n;
    const size_t k = b->size < n - off ? b->size : n - off;
    memcpy((uint8_t *)params + off, b->data, k);
}

static void run_estimator(fuzz_bytes *b, const fc_controller_params *d, uint8_t off)
{
    fc_attitude_estimator_params p = d->estimator;
    overlay(b, &p, sizeof p, off);
    fc_attitude_estimator est;
    const fc_init_result r = fc_attitude_estimator_init(&est, &p);
    fc_imu_sample rest;
    memset(&rest, 0, sizeof rest);
    rest.accel_mps2.z = p.gravity_mps2;
    fc_attitude_estimate out;
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        const fc_step_status s = fc_attitude_estimator_step(&est, &rest, &out);
        FUZZ_UNIT_QUAT(out.attitude);
        FUZZ_FINITE_VEC3(out.rate_radps, RATE);
        FUZZ_FINITE_VEC3(out.gyro_bias_radps, RATE);
        FUZZ_FINITE(out.accel_weight, RATIO);
        if (r != FC_INIT_OK) {
            FUZZ_CHECK(s & FC_STEP_NOT_READY);
        } else {
            FUZZ_ABS_LE(out.gyro_bias_radps.x, p.gyro_bias_limit_radps, RATE);
            FUZZ_ABS_LE(out.gyro_bias_radps.y, p.gyro_bias_limit_radps, RATE);
            FUZZ_ABS_LE(out.gyro_bias_radps.z, p.gyro_bias_limit_radps, RATE);
            FUZZ_WITHIN(out.accel_weight, FC_C(0.0f, RATIO), FC_C(1.0f, RATIO), RATIO);
        }
    }
}

/* The bound of a normalised attitude moment (RATIO): the budget, clamped to
 * exactly in RATIO, plus the output's rounding to NORM16 (half an LSB, 2^9 LSB
 * of RATIO) in fixed; none in float (fc_real16 is float). limit <= 1.99 once
 * init accepted it: no overflow. */
static fc_real attitude_moment_bound(fc_real limit)
{
#if FC_NUMERIC_FIXED
    return limit + ((fc_real)1 << (FC_RATIO_FRAC - FC_NORM16_FRAC - 1));
#else
    return limit;
#endif
}

static void run_attitude_control(fuzz_bytes *b, const fc_controller_params *d, uint8_t off)
{
    fc_attitude_control_params p = d->attitude;
    overlay(b, &p, sizeof p, off);
    fc_attitude_control c;
    const fc_init_result r = fc_attitude_control_init(&c, &p);
    const fc_quat attitude = fc_quat_make(FC_C(0.9f, UNIT), FC_C(0.3f, UNIT), FC_C(-0.2f, UNIT), FC_C(0.1f, UNIT));
    const fc_quat attitude_desired = fc_quat_identity();
    const fc_vec3 rate_radps = fc_vec3_make(FC_C(1.0f, RATE), FC_C(-2.0f, RATE), FC_C(0.5f, RATE));
    const fc_vec3 rate_ff_radps = fc_vec3_zero();
    const fc_attitude_control_input in = {&attitude, &attitude_desired, &rate_radps, &rate_ff_radps, 0u};
    fc_attitude_control_output out;
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        const fc_step_status s = fc_attitude_control_step(&c, &in, &out);
        FUZZ_FINITE_VEC3(out.moment, NORM16);
        FUZZ_FINITE_VEC3(out.attitude_error_rad, ANGLE);
        if (r != FC_INIT_OK) {
            FUZZ_CHECK(s & FC_STEP_NOT_READY);
        } else {
            const fc_vec3 m = fc_vec3_widen16(out.moment, FC_NORM16_FRAC, FC_RATIO_FRAC);
            FUZZ_ABS_LE(m.x, attitude_moment_bound(p.moment_limit.x), RATIO);
            FUZZ_ABS_LE(m.y, attitude_moment_bound(p.moment_limit.y), RATIO);
            FUZZ_ABS_LE(m.z, attitude_moment_bound(p.moment_limit.z), RATIO);
        }
    }
}

static void run_allocation(fuzz_bytes *b, const fc_controller_params *d, uint8_t off)
{
    fc_allocation_params p = d->allocation;
    overlay(b, &p, sizeof p, off);
    static fc_allocation a;
    const fc_init_result r = fc_allocation_init(&a, &p);
    /* the altitude law's thrust limits and a small moment, in N and N m,
     * normalised by the authorities of the accepted parameters (a zero demand
     * when init failed: there are none) */
    const fc_vec3 moment = fc_vec3_make(FC_C(0.001f, MOMENT), FC_C(-0.002f, MOMENT), FC_C(0.0005f, MOMENT));
    fc_allocation_demand dem = fc_allocation_normalise(&a, d->altitude.thrust_max_n, moment);
    fc_allocation_output out;
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        const fc_step_status s = fc_allocation_step(&a, &dem, &out);
        FUZZ_FINITE(out.thrust_n, FORCE);
        FUZZ_FINITE_VEC3(out.moment_nm, MOMENT);
        for (int i = 0; i < FC_MAX_ROTORS; i++) {
            FUZZ_FINITE(out.speed[i], UNIT);
            FUZZ_FINITE(out.rotor_thrust_n[i], FORCE);
            if (r == FC_INIT_OK && i < p.rotor_count) {
                FUZZ_WITHIN(out.speed[i], p.rotor[i].speed_min, FC_C(1.0f, UNIT), UNIT);
            } else if (r != FC_INIT_OK) {
                FUZZ_CHECK(out.speed[i] == 0);
            }
        }
        if (r != FC_INIT_OK) {
            FUZZ_CHECK(s & FC_STEP_NOT_READY);
        }
        dem = fc_allocation_normalise(&a, d->altitude.thrust_min_n, moment);
    }
}

static void run_altitude_reference(fuzz_bytes *b, const fc_controller_params *d, uint8_t off)
{
    fc_altitude_reference_params p = d->reference;
    overlay(b, &p, sizeof p, off);
    fc_altitude_reference ref;
    const fc_init_result r = fc_altitude_reference_init(&ref, &p);
    fc_vertical_trajectory pad, out;
    memset(&pad, 0, sizeof pad);
    pad.z_m = FC_C(0.5f, LENGTH);
    pad.vz_mps = FC_C(0.3f, VEL);
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        const fc_step_status s = fc_altitude_reference_step(&ref, &pad, &out);
        FUZZ_FINITE(out.z_m, LENGTH);
        FUZZ_FINITE(out.vz_mps, VEL);
        FUZZ_FINITE(out.az_mps2, ACCEL);
        if (r != FC_INIT_OK) {
            FUZZ_CHECK(s & FC_STEP_NOT_READY);
        }
    }
}

static void run_altitude_control(fuzz_bytes *b, const fc_controller_params *d, uint8_t off)
{
    fc_altitude_control_params p = d->altitude;
    overlay(b, &p, sizeof p, off);
    fix_bool(&p.adaptive);
    fix_bool(&p.velocity_measured);
    static fc_altitude_control c;
    const fc_init_result r = fc_altitude_control_init(&c, &p);
    const fc_vertical_trajectory reference = {FC_C(1.0f, LENGTH), FC_INT(0, VEL), FC_INT(0, ACCEL)};
    const fc_altitude_control_input in = {FC_C(0.8f, LENGTH), FC_C(-0.4f, VEL), &reference, FC_C(0.95f, RATIO), 0u};
    fc_altitude_control_output out;
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        const fc_step_status s = fc_altitude_control_step(&c, &in, &out);
        FUZZ_FINITE(out.thrust_n, FORCE);
        FUZZ_FINITE(out.vertical_force_n, FORCE);
        FUZZ_FINITE(out.error_m, LENGTH);
        FUZZ_FINITE(out.sigma_mps, VEL);
        FUZZ_FINITE(out.sigma_tilde_mps, VEL);
        FUZZ_FINITE(out.rho_n, FORCE);
        FUZZ_FINITE(out.u0_av_n, FORCE);
        FUZZ_FINITE(out.u_nom_n, FORCE);
        FUZZ_FINITE(out.theta_kg, MASS);
        FUZZ_FINITE(out.observer_bound_n, FORCE);
        if (r != FC_INIT_OK) {
            FUZZ_CHECK(s & FC_STEP_NOT_READY);
        } else {
            FUZZ_WITHIN(out.thrust_n, p.thrust_min_n, p.thrust_max_n, FORCE);
        }
    }
}

static void run_controller(fuzz_bytes *b, const fc_controller_params *d, uint8_t off)
{
    static fc_controller_params p;
    p = *d;
    overlay(b, &p, sizeof p, off);
    fix_bool(&p.use_external_attitude);
    fix_bool(&p.altitude.adaptive);
    fix_bool(&p.altitude.velocity_measured);
    fix_bool(&p.landing.press_at_contact);
    fix_bool(&p.landing.descent_shaping);
    static fc_controller ctl;
    const fc_init_result r = fc_controller_init(&ctl, &p);
    fc_controller_inputs in;
    fuzz_controller_hover_inputs(&p, &in);
    static fc_controller_outputs out;
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        const fc_step_status s = fc_controller_step(&ctl, &in, &out);
        if (r == FC_INIT_OK) {
            fuzz_check_controller(&p, &out);
        } else {
            FUZZ_CHECK(s & FC_STEP_NOT_READY);
            FUZZ_CHECK(!out.motors_on);
            for (int i = 0; i < FC_MAX_ROTORS; i++) {
                FUZZ_CHECK(out.rotor_speed[i] == 0);
            }
            FUZZ_FINITE(out.thrust_n, FORCE);
            FUZZ_FINITE_VEC3(out.moment_nm, MOMENT);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_bytes b = {data, size};
    const uint8_t sel = fuzz_byte(&b);
    const uint8_t variant = fuzz_byte(&b);
    const uint8_t off = fuzz_byte(&b);
    static fc_controller_params d;
    fc_controller_default_params(&d, (fc_airframe)(((sel >> 3) & 3u) % FC_AIRFRAME_COUNT),
                                 (fc_altitude_variant)(variant % FC_ALT_VARIANT_COUNT), FC_C(0.002f, DT));
    switch ((sel & 7u) % 6u) {
    case 0: run_estimator(&b, &d, off); break;
    case 1: run_attitude_control(&b, &d, off); break;
    case 2: run_allocation(&b, &d, off); break;
    case 3: run_altitude_reference(&b, &d, off); break;
    case 4: run_altitude_control(&b, &d, off); break;
    default: run_controller(&b, &d, off); break;
    }
    return 0;
}

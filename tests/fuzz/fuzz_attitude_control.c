/*
 * fuzz_attitude_control: fc_attitude_control_step on raw bit patterns of the
 * values its input points to (attitude_values: quaternions of any length,
 * NaN, inf, denormal rates, any saturation bits). Byte 0 picks the airframe (the
 * controller's default attitude parameters for it: the allocation's authority
 * and the normalised budget); bit 2 of it sets ki to kp so that the integrals
 * and the anti-windup run too. Then up to FUZZ_MAX_STEPS inputs, then
 * FUZZ_CLEAN_STEPS level ones. Checks: every (normalised) moment finite and
 * inside +-moment_limit plus its rounding to NORM16, the error finite.
 */
#include "fc/controller.h"
#include "fuzz_common.h"

/* The bound of a normalised output moment (RATIO): the budget, which the law
 * holds in its sum's format NSUM (Q22: rounded, up to 2^-23 = 2 LSB of RATIO)
 * and clamps to exactly there, plus the output's rounding to NORM16 (half an
 * LSB, 2^-15 = 2^9 LSB of RATIO) in fixed; in float fc_real16 is float and the
 * output is not rounded. */
static fc_real moment_bound(fc_real limit)
{
#if FC_NUMERIC_FIXED
    return limit + ((fc_real)1 << (FC_RATIO_FRAC - 22 - 1)) + ((fc_real)1 << (FC_RATIO_FRAC - FC_NORM16_FRAC - 1));
#else
    return limit;
#endif
}

static void check(const fc_attitude_control_params *p, const fc_attitude_control_output *out)
{
    FUZZ_FINITE_VEC3(out->moment, NORM16);
    const fc_vec3 m = fc_vec3_widen16(out->moment, FC_NORM16_FRAC, FC_RATIO_FRAC);
    FUZZ_ABS_LE(m.x, moment_bound(p->moment_limit.x), RATIO);
    FUZZ_ABS_LE(m.y, moment_bound(p->moment_limit.y), RATIO);
    FUZZ_ABS_LE(m.z, moment_bound(p->moment_limit.z), RATIO);
    FUZZ_FINITE_VEC3(out->attitude_error_rad, ANGLE);
}

/* The values fc_attitude_control_input points to, in the order the fuzz
 * bytes give them. */
typedef struct attitude_values {
    fc_quat attitude;
    fc_quat attitude_desired;
    fc_vec3 rate_radps;
    fc_vec3 rate_ff_radps;
    uint8_t allocation_saturation;
} attitude_values;

static fc_step_status step(fc_attitude_control *c, const attitude_values *v, fc_attitude_control_output *out)
{
    const fc_attitude_control_input in = {&v->attitude, &v->attitude_desired, &v->rate_radps, &v->rate_ff_radps,
                                          v->allocation_saturation};
    return fc_attitude_control_step(c, &in, out);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_bytes b = {data, size};
    const uint8_t cfg = fuzz_byte(&b);
    static fc_controller_params cp;
    fc_controller_default_params(&cp, (fc_airframe)((cfg & 3u) % FC_AIRFRAME_COUNT), FC_ALT_VARIANT_SSC,
                                 FC_C(0.002f, DT));
    fc_attitude_control_params p = cp.attitude;
    if (cfg & 4u) {
        p.ki_per_s3 = p.kp_per_s2;
    }
    fc_attitude_control c;
    FUZZ_CHECK(fc_attitude_control_init(&c, &p) == FC_INIT_OK);

    attitude_values level;
    memset(&level, 0, sizeof level);
    level.attitude.w = FC_C(1.0f, UNIT);
    level.attitude_desired.w = FC_C(1.0f, UNIT);
    fc_attitude_control_output out;
    attitude_values in;
    for (int k = 0; k < FUZZ_MAX_STEPS && fuzz_take(&b, &in, sizeof in); k++) {
        (void)step(&c, &in, &out);
        check(&p, &out);
    }
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        (void)step(&c, &level, &out);
        check(&p, &out);
    }
    return 0;
}

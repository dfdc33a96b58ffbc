/*
 * fuzz_attitude_estimator: fc_attitude_estimator_step on raw fc_imu_sample bit
 * patterns. Byte 0: bit 0 picks dt (500 Hz or 100 Hz), bit 1 an alignment of
 * 1 sample instead of the default 100 (so that the aligned path is reached
 * within a few steps), bit 2 a level, at-rest sample before the fuzzed ones,
 * bit 3 a heading sample (raw bits) before each step. Then up to
 * FUZZ_MAX_STEPS samples, then FUZZ_CLEAN_STEPS at rest.
 * Checks: attitude a unit quaternion, rate, bias and weight finite, the bias
 * inside the bias limit, the weight in [0, 1].
 */
#include "fc/attitude_estimator.h"
#include "fuzz_common.h"

static void check(const fc_attitude_estimator *est, const fc_attitude_estimate *out)
{
    FUZZ_UNIT_QUAT(out->attitude);
    FUZZ_FINITE_VEC3(out->rate_radps, RATE);
    FUZZ_FINITE_VEC3(out->gyro_bias_radps, RATE);
    FUZZ_ABS_LE(out->gyro_bias_radps.x, est->p.gyro_bias_limit_radps, RATE);
    FUZZ_ABS_LE(out->gyro_bias_radps.y, est->p.gyro_bias_limit_radps, RATE);
    FUZZ_ABS_LE(out->gyro_bias_radps.z, est->p.gyro_bias_limit_radps, RATE);
    FUZZ_WITHIN(out->accel_weight, FC_C(0.0f, RATIO), FC_C(1.0f, RATIO), RATIO);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_bytes b = {data, size};
    const uint8_t cfg = fuzz_byte(&b);
    fc_attitude_estimator_params p;
    fc_attitude_estimator_default_params(&p, (cfg & 1u) ? FC_C(0.01f, DT) : FC_C(0.002f, DT));
    if (cfg & 2u) {
        p.alignment_samples = 1;
    }
    fc_attitude_estimator est;
    FUZZ_CHECK(fc_attitude_estimator_init(&est, &p) == FC_INIT_OK);

    fc_imu_sample rest;
    memset(&rest, 0, sizeof rest);
    rest.accel_mps2.z = FC_C(9.81f, ACCEL);
    fc_attitude_estimate out;
    if (cfg & 4u) {
        (void)fc_attitude_estimator_step(&est, &rest, &out);
        check(&est, &out);
    }
    fc_imu_sample imu;
    fc_real heading_rad;
    for (int k = 0; k < FUZZ_MAX_STEPS && fuzz_take(&b, &imu, sizeof imu); k++) {
        if ((cfg & 8u) && fuzz_take(&b, &heading_rad, sizeof heading_rad)) {
            (void)fc_attitude_estimator_take_heading(&est, heading_rad);
        }
        (void)fc_attitude_estimator_step(&est, &imu, &out);
        check(&est, &out);
    }
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        (void)fc_attitude_estimator_step(&est, &rest, &out);
        check(&est, &out);
    }
    return 0;
}

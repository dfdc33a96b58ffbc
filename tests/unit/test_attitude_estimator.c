/*
 * Tests of the complementary attitude filter (fc/attitude_estimator.h).
 * One source for both backends; tolerances per backend below. The truth and
 * the noise are computed in double here (host only); the estimator sees the
 * samples converted into its formats.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <math.h>
#include <float.h>
#include <cmocka.h>
#include "fc/attitude_estimator.h"
#include "test_support.h"

#if FC_NUMERIC_FIXED
#define BACKEND "fixed"
/* alignment: roll, pitch and yaw (read from the UNIT quaternion) within 32 LSB
 * of ANGLE (1.2e-7 rad) of those of the quantised sample */
#define ALIGN_TOL_RAD (32.0 / (double)(1 << FC_ANGLE_FRAC))
/* the same with 32767 samples: the mean is rounded once, whatever the count */
#define ALIGN_LONG_TOL_RAD ALIGN_TOL_RAD
/* integration over 1 s: one LSB of ANGLE per step (rate * dt is rounded to
 * ANGLE each step) over 500 steps, 1.9e-6 rad */
#define INTEGRATION_TOL_RAD (500.0 / (double)(1 << FC_ANGLE_FRAC))
/* the trust weight against the exact one for the unquantised |a|: 16 LSB of
 * RATIO plus what the length's error moves it, |a| 1.37 2^-14 / band (the
 * accelerometer's 16-bit components' roundings, sqrt(3)/2 over |M| >= 15000
 * for the |a| and g here, and the root's, 2^-16 of itself) */
#define WEIGHT_TOL_FOR(norm_mps2, band_mps2) \
    (16.0 / (double)(1 << FC_RATIO_FRAC) + (norm_mps2) * 1.37 / 16384.0 / (band_mps2))
/* a rate or a bias read back: 2 LSB of RATE */
#define RATE_TOL (2.0 / (double)(1 << FC_RATE_FRAC))
#else
#define BACKEND "float"
/* 8 float ulps of 1 (the sum of 100 samples and the single-precision atan2) */
#define ALIGN_TOL_RAD (8.0 * (double)FLT_EPSILON)
/* 32767 single-precision additions: the sum's rounding grows with the count */
#define ALIGN_LONG_TOL_RAD 1.0e-4
/* integration over 1 s: 500 single-precision quaternion products whose
 * roundings mostly cancel (5.5 ulps of 1 measured); 32 ulps */
#define INTEGRATION_TOL_RAD (32.0 * (double)FLT_EPSILON)
/* the trust weight: 8 ulps of 1 */
#define WEIGHT_TOL_FOR(norm_mps2, band_mps2) (8.0 * (double)FLT_EPSILON)
/* a rate or a bias read back (values up to 1 rad/s): 4 ulps of 1 */
#define RATE_TOL (4.0 * (double)FLT_EPSILON)
#endif

#define DEG (3.14159265358979323846 / 180.0)
/* a gyro sample that is bad input: NaN in float, beyond the 35 rad/s range in fixed */
#if FC_NUMERIC_FIXED
#define NAN_OR_BEYOND 60.0
#else
#define NAN_OR_BEYOND ((double)NAN)
#endif
#define G_MPS2 9.81
#define DT_S 0.002

/* ---- noise: 64-bit LCG (Knuth's MMIX constants) and Box-Muller ---------- */

typedef struct rng {
    uint64_t s;
    int has_spare;
    double spare;
} rng;

static double rng_uniform(rng *r)
{
    r->s = r->s * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(r->s >> 11) + 0.5) * (1.0 / 9007199254740992.0); /* (0, 1) */
}

static double rng_normal(rng *r)
{
    if (r->has_spare) {
        r->has_spare = 0;
        return r->spare;
    }
    const double u1 = rng_uniform(r), u2 = rng_uniform(r);
    const double radius = sqrt(-2.0 * log(u1));
    const double phase = 2.0 * 3.14159265358979323846 * u2;
    r->spare = radius * sin(phase);
    r->has_spare = 1;
    return radius * cos(phase);
}

/* ---- conversions and the truth (double) --------------------------------- */

static fc_real to_fc(double x, int frac)
{
    return fc_from_float((float)x, frac);
}

/* exact in both backends (fc_to_float would round a fixed value to 24 bits) */
static double from_fc(fc_real x, int frac)
{
#if FC_NUMERIC_FIXED
    return (double)x / (double)((int64_t)1 << frac);
#else
    (void)frac;
    return (double)x;
#endif
}

static fc_imu_sample sample(double gx, double gy, double gz, double ax, double ay, double az)
{
    fc_imu_sample s;
    s.gyro_radps =
        fc_vec3_make(to_fc(gx, FC_RATE_FRAC), to_fc(gy, FC_RATE_FRAC), to_fc(gz, FC_RATE_FRAC));
    s.accel_mps2 =
        fc_vec3_make(to_fc(ax, FC_ACCEL_FRAC), to_fc(ay, FC_ACCEL_FRAC), to_fc(az, FC_ACCEL_FRAC));
    return s;
}

typedef struct dquat {
    double w, x, y, z;
} dquat;

static dquat dq_from_fc(fc_quat q)
{
    const dquat d = {from_fc(q.w, FC_UNIT_FRAC), from_fc(q.x, FC_UNIT_FRAC),
                     from_fc(q.y, FC_UNIT_FRAC), from_fc(q.z, FC_UNIT_FRAC)};
    return d;
}

/* q = q_z(yaw) q_y(pitch) q_x(roll) */
static dquat dq_from_rpy(double roll, double pitch, double yaw)
{
    const double cr = cos(roll / 2), sr = sin(roll / 2), cp = cos(pitch / 2), sp = sin(pitch / 2);
    const double cy = cos(yaw / 2), sy = sin(yaw / 2);
    const dquat q = {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
                     cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy};
    return q;
}

static void dq_to_rpy(dquat q, double *roll, double *pitch, double *yaw)
{
    *roll = atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y));
    double s = 2 * (q.w * q.y - q.z * q.x);
    s = s > 1 ? 1 : (s < -1 ? -1 : s);
    *pitch = asin(s);
    *yaw = atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
}

/* the world's up direction seen in the body of q (body -> world): R^T e_z */
static void up_in_body(dquat q, double up[3])
{
    up[0] = 2 * (q.x * q.z - q.w * q.y);
    up[1] = 2 * (q.y * q.z + q.w * q.x);
    up[2] = 1 - 2 * (q.x * q.x + q.y * q.y);
}

/* angle between the up directions of two attitudes (the tilt error), rad */
static double tilt_between(dquat a, dquat b)
{
    double ua[3], ub[3];
    up_in_body(a, ua);
    up_in_body(b, ub);
    const double cx = ua[1] * ub[2] - ua[2] * ub[1];
    const double cy = ua[2] * ub[0] - ua[0] * ub[2];
    const double cz = ua[0] * ub[1] - ua[1] * ub[0];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), ua[0] * ub[0] + ua[1] * ub[1] + ua[2] * ub[2]);
}

static void assert_estimate_finite(const fc_attitude_estimate *e)
{
    assert_true(fc_quat_is_finite(e->attitude));
    assert_true(fc_vec3_is_finite(e->rate_radps));
    assert_true(fc_vec3_is_finite(e->gyro_bias_radps));
    assert_true(fc_is_finite(e->accel_weight));
    const dquat q = dq_from_fc(e->attitude);
    assert_true(fabs(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z - 1.0) < 1e-5);
    const double w = from_fc(e->accel_weight, FC_RATIO_FRAC);
    assert_true(w >= 0.0 && w <= 1.0);
}

static fc_attitude_estimator_params default_params(void)
{
    fc_attitude_estimator_params p;
    fc_attitude_estimator_default_params(&p, FC_C(0.002f, DT));
    return p;
}

/* Aligns est (alignment_samples steps) with the specific force of the attitude
 * `tilt` at rest; checks the alignment flag is raised on the last sample. */
static void align_at(fc_attitude_estimator *est, dquat tilt)
{
    double up[3];
    up_in_body(tilt, up);
    fc_attitude_estimate out;
    const fc_imu_sample s = sample(0, 0, 0, G_MPS2 * up[0], G_MPS2 * up[1], G_MPS2 * up[2]);
    for (unsigned i = 0; i < est->p.alignment_samples; i++) {
        const fc_step_status st = fc_attitude_estimator_step(est, &s, &out);
        assert_int_equal(st, FC_STEP_OK);
        assert_int_equal(out.aligned, i + 1u == est->p.alignment_samples);
    }
}

/* ---- parameters --------------------------------------------------------- */

static void test_default_params_init(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    /* Kp = 2 zeta w_c = 1.414 in RATE16 (half an LSB, 2^-11), Ki dt = w_c^2
     * dt = 0.002 in the finest of Q26, Q22, Q18, Q14 that holds it (Q22:
     * 0.002 2^22 = 8389 < 2^15; Q26 would not), half an LSB 2^-23 */
    assert_true(fabs(ts_val16(est.kp16_radps, FC_RATE16_FRAC) - 1.41421356) <= ldexp(1.0, -11) + 1e-7);
#if FC_NUMERIC_FIXED
    assert_int_equal(est.ki_dt16_frac, 22);
#endif
    assert_true(fabs(ts_val16(est.ki_dt16, est.ki_dt16_frac) - 0.002) <= ldexp(1.0, -23) + 1e-9);
}

typedef void (*param_mutation)(fc_attitude_estimator_params *p);

#define MUTATION(NAME, STATEMENT)                                                         \
    static void NAME(fc_attitude_estimator_params *p)                                     \
    {                                                                                     \
        STATEMENT;                                                                        \
    }
MUTATION(dt_zero, p->dt_s = FC_INT(0, DT))
MUTATION(dt_negative, p->dt_s = FC_C(-0.002f, DT))
MUTATION(dt_too_long, p->dt_s = FC_C(0.2f, DT))
MUTATION(crossover_zero, p->crossover_radps = FC_INT(0, RATE))
MUTATION(crossover_negative, p->crossover_radps = FC_C(-1.0f, RATE))
MUTATION(crossover_too_fast, p->crossover_radps = FC_C(60.0f, RATE))
MUTATION(damping_zero, p->damping = FC_INT(0, RATIO))
MUTATION(damping_negative, p->damping = FC_C(-0.7f, RATIO))
MUTATION(bias_limit_negative, p->gyro_bias_limit_radps = FC_C(-0.1f, RATE))
MUTATION(gravity_zero, p->gravity_mps2 = FC_INT(0, ACCEL))
MUTATION(gravity_negative, p->gravity_mps2 = FC_C(-9.81f, ACCEL))
MUTATION(band_negative, p->accel_trust_band_mps2 = FC_C(-1.0f, ACCEL))
MUTATION(band_zero, p->accel_trust_band_mps2 = FC_INT(0, ACCEL))
MUTATION(band_beyond_g, p->accel_trust_band_mps2 = FC_C(12.0f, ACCEL))
MUTATION(gyro_range_negative, p->gyro_range_radps = FC_C(-35.0f, RATE))
MUTATION(gyro_range_zero, p->gyro_range_radps = FC_INT(0, RATE))
MUTATION(accel_range_negative, p->accel_range_mps2 = FC_C(-157.0f, ACCEL))
MUTATION(accel_range_below_g, p->accel_range_mps2 = FC_C(5.0f, ACCEL))
MUTATION(no_alignment_samples, p->alignment_samples = 0u)
/* consistency: w_c dt = 0.5 (the loop would not be slow against the step) */
MUTATION(crossover_against_dt, p->dt_s = FC_C(0.05f, DT); p->crossover_radps = FC_C(10.0f, RATE))
MUTATION(heading_weight_negative, p->heading_weight = FC_C(-0.1f, RATIO))
MUTATION(heading_weight_above_1, p->heading_weight = FC_C(1.5f, RATIO))
MUTATION(heading_hold_below_dt, p->heading_hold_s = FC_C(0.001f, DT))
MUTATION(heading_hold_above_1_s, p->heading_hold_s = FC_C(1.5f, DT))
/* with a heading loop: gyro_range + bias_limit + 2 Kp = 100 + 0.2 + 40 > 127 rad/s */
MUTATION(heading_rate_bound, p->dt_s = FC_C(0.005f, DT); p->crossover_radps = FC_C(10.0f, RATE);
         p->damping = FC_C(1.0f, RATIO); p->gyro_range_radps = FC_C(100.0f, RATE))
#if !FC_NUMERIC_FIXED
MUTATION(dt_nan, p->dt_s = NAN)
MUTATION(crossover_inf, p->crossover_radps = INFINITY)
MUTATION(gravity_nan, p->gravity_mps2 = NAN)
MUTATION(band_inf, p->accel_trust_band_mps2 = INFINITY)
MUTATION(damping_nan, p->damping = NAN)
MUTATION(heading_weight_nan, p->heading_weight = NAN)
#endif

static void assert_not_ready(fc_attitude_estimator *est)
{
    fc_attitude_estimate out;
    memset(&out, 0x5a, sizeof out);
    const fc_imu_sample s = sample(0.1, 0.2, 0.3, 0, 0, G_MPS2);
    for (int i = 0; i < 3; i++) {
        assert_int_equal(fc_attitude_estimator_step(est, &s, &out), FC_STEP_NOT_READY);
        assert_false(out.aligned);
        assert_true(out.attitude.w == FC_INT(1, UNIT) && out.attitude.x == FC_INT(0, UNIT) &&
                    out.attitude.y == FC_INT(0, UNIT) && out.attitude.z == FC_INT(0, UNIT));
        assert_estimate_finite(&out);
    }
}

static void test_bad_params_rejected(void **state)
{
    (void)state;
    const param_mutation mutations[] = {
        dt_zero, dt_negative, dt_too_long, crossover_zero, crossover_negative, crossover_too_fast,
        damping_zero, damping_negative, bias_limit_negative, gravity_zero, gravity_negative,
        band_negative, band_zero, band_beyond_g, gyro_range_negative, gyro_range_zero,
        accel_range_negative, accel_range_below_g, no_alignment_samples, crossover_against_dt,
        heading_weight_negative, heading_weight_above_1, heading_hold_below_dt, heading_hold_above_1_s,
        heading_rate_bound,
#if !FC_NUMERIC_FIXED
        dt_nan, crossover_inf, gravity_nan, band_inf, damping_nan, heading_weight_nan,
#endif
    };
    const size_t n = sizeof mutations / sizeof mutations[0];
    for (size_t i = 0; i < n; i++) {
        fc_attitude_estimator est;
        fc_attitude_estimator_params p = default_params();
        mutations[i](&p);
        assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_BAD_PARAM);
        assert_not_ready(&est);
    }
    /* no parameters at all, and a state that was never initialised (zeroed) */
    fc_attitude_estimator est;
    assert_int_equal(fc_attitude_estimator_init(&est, NULL), FC_INIT_BAD_PARAM);
    assert_not_ready(&est);
    memset(&est, 0, sizeof est);
    assert_not_ready(&est);
    print_message("[%s] %u bad parameter sets rejected\n", BACKEND, (unsigned)n + 1u);
}

/* A failed init after a good one leaves the state not ready. */
static void test_reinit_with_bad_params(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    align_at(&est, dq_from_rpy(0.2, 0.1, 0));
    p.damping = FC_INT(0, RATIO);
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_BAD_PARAM);
    assert_not_ready(&est);
}

/* ---- alignment ---------------------------------------------------------- */

static void check_alignment(double roll, double pitch, uint16_t samples, double tol_rad)
{
    fc_attitude_estimator est;
    fc_attitude_estimator_params p = default_params();
    p.alignment_samples = samples;
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    const dquat truth = dq_from_rpy(roll, pitch, 0.7); /* the yaw is not seen by gravity */
    double up[3];
    up_in_body(truth, up);
    const fc_imu_sample s = sample(0.01, -0.02, 0.03, G_MPS2 * up[0], G_MPS2 * up[1], G_MPS2 * up[2]);
    fc_attitude_estimate out;
    for (unsigned i = 0; i + 1u < samples; i++) {
        assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
        assert_false(out.aligned);
        assert_true(out.attitude.w == FC_INT(1, UNIT) && out.attitude.x == FC_INT(0, UNIT) &&
                    out.attitude.y == FC_INT(0, UNIT) && out.attitude.z == FC_INT(0, UNIT));
        /* the rate is output during the alignment, with a zero bias */
        assert_true(fabs(from_fc(out.rate_radps.z, FC_RATE_FRAC) - 0.03) < RATE_TOL);
    }
    assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
    assert_true(out.aligned);
    assert_estimate_finite(&out);
    /* the reference: roll and pitch of the quantised sample the filter saw */
    const double ax = from_fc(s.accel_mps2.x, FC_ACCEL_FRAC);
    const double ay = from_fc(s.accel_mps2.y, FC_ACCEL_FRAC);
    const double az = from_fc(s.accel_mps2.z, FC_ACCEL_FRAC);
    const double roll_ref = atan2(ay, az), pitch_ref = atan2(-ax, sqrt(ay * ay + az * az));
    assert_true(fabs(roll_ref - roll) < 1e-6 && fabs(pitch_ref - pitch) < 1e-6);
    double r, pt, y;
    dq_to_rpy(dq_from_fc(out.attitude), &r, &pt, &y);
    print_message("[%s] alignment roll %+.1f pitch %+.1f deg, %u samples: errors %.1e %.1e %.1e rad\n",
                  BACKEND, roll / DEG, pitch / DEG, (unsigned)samples, r - roll_ref, pt - pitch_ref, y);
    assert_true(fabs(r - roll_ref) < tol_rad);
    assert_true(fabs(pt - pitch_ref) < tol_rad);
    assert_true(fabs(y) < tol_rad);
}

static void test_alignment_from_tilted_gravity(void **state)
{
    (void)state;
    check_alignment(25.0 * DEG, -40.0 * DEG, 100u, ALIGN_TOL_RAD);
    check_alignment(-60.0 * DEG, 15.0 * DEG, 1u, ALIGN_TOL_RAD);
    check_alignment(150.0 * DEG, 70.0 * DEG, 7u, ALIGN_TOL_RAD); /* upside down */
    check_alignment(0.0, 0.0, 32767u, ALIGN_TOL_RAD);
    check_alignment(5.0 * DEG, -3.0 * DEG, 32767u, ALIGN_LONG_TOL_RAD);
}

/* The mean of noisy samples: the attitude of the mean direction. */
static void test_alignment_averages_noise(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    fc_attitude_estimator_params p = default_params();
    p.alignment_samples = 500u;
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    const double roll = -12.0 * DEG, pitch = 33.0 * DEG;
    double up[3];
    up_in_body(dq_from_rpy(roll, pitch, 0), up);
    rng r = {12345u, 0, 0.0};
    fc_attitude_estimate out = {0};
    for (unsigned i = 0; i < p.alignment_samples; i++) {
        const fc_imu_sample s = sample(0, 0, 0, G_MPS2 * up[0] + 0.5 * rng_normal(&r),
                                       G_MPS2 * up[1] + 0.5 * rng_normal(&r),
                                       G_MPS2 * up[2] + 0.5 * rng_normal(&r));
        assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
    }
    assert_true(out.aligned);
    double er, ep, ey;
    dq_to_rpy(dq_from_fc(out.attitude), &er, &ep, &ey);
    /* 0.5 m/s2 rms over 500 samples: 0.5 / 9.81 / sqrt(500) = 2.3e-3 rad rms per axis */
    assert_true(fabs(er - roll) < 0.01);
    assert_true(fabs(ep - pitch) < 0.01);
    assert_true(fabs(ey) < ALIGN_TOL_RAD);
    print_message("[%s] alignment from 500 samples with 0.5 m/s2 noise: roll error %.2e rad, "
                  "pitch error %.2e rad\n",
                  BACKEND, er - roll, ep - pitch);
}

/* Bad samples during the alignment are skipped: only valid ones count. */
static void test_alignment_skips_bad_samples(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    fc_attitude_estimator_params p = default_params();
    p.alignment_samples = 10u;
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    const double roll = 10.0 * DEG, pitch = 5.0 * DEG;
    double up[3];
    up_in_body(dq_from_rpy(roll, pitch, 0), up);
    const fc_imu_sample good = sample(0, 0, 0, G_MPS2 * up[0], G_MPS2 * up[1], G_MPS2 * up[2]);
    const fc_imu_sample zero = sample(0, 0, 0, 0, 0, 0);
    const fc_imu_sample huge = sample(0, 0, 0, 0, 0, 300.0); /* beyond the 16 g range */
    fc_attitude_estimate out;
    for (int i = 0; i < 5; i++) {
        assert_int_equal(fc_attitude_estimator_step(&est, &good, &out), FC_STEP_OK);
    }
    for (int i = 0; i < 4; i++) {
        const fc_step_status st = fc_attitude_estimator_step(&est, (i & 1) ? &zero : &huge, &out);
        assert_true((st & FC_STEP_BAD_INPUT) != 0u);
        assert_false(out.aligned);
    }
    assert_int_equal(fc_attitude_estimator_step(&est, NULL, &out), FC_STEP_BAD_INPUT);
    for (int i = 0; i < 5; i++) {
        assert_false(out.aligned);
        assert_int_equal(fc_attitude_estimator_step(&est, &good, &out), FC_STEP_OK);
    }
    assert_true(out.aligned);
    double er, ep, ey;
    dq_to_rpy(dq_from_fc(out.attitude), &er, &ep, &ey);
    assert_true(fabs(er - roll) < ALIGN_TOL_RAD);
    assert_true(fabs(ep - pitch) < ALIGN_TOL_RAD);
}

/* ---- convergence under gyro bias and accelerometer noise ----------------- */

/*
 * The alignment is fed the gravity of an attitude tilted by 30 degrees, then
 * the vehicle is at rest and level: the filter starts 30 degrees off. The
 * gyro reads a bias of 0.05 rad/s on x and y plus 0.003 rad/s rms noise, the
 * accelerometer g plus 0.1 m/s2 rms noise per axis. w_c = 1 rad/s, zeta =
 * 0.707 (the defaults), dt = 2 ms, 40 s.
 *   tilt: < 1 degree at every step from 10 s on (the time it first stays
 *         there is printed);
 *   bias: x and y within 0.005 rad/s (10 %) of 0.05 rad/s at every step from
 *         20 s on, and their mean over the last 10 s within 0.001 rad/s.
 */
#define CONV_END_S 40.0
#define TILT_ASSERT_FROM_S 10.0
#define TILT_BOUND_DEG 1.0
#define BIAS_ASSERT_FROM_S 20.0
#define BIAS_BOUND_RADPS 0.005
#define BIAS_MEAN_BOUND_RADPS 0.001
#define BIAS_TRUE_RADPS 0.05

static void run_convergence(const char *name, double roll0, double pitch0, uint64_t seed)
{
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    const dquat start = dq_from_rpy(roll0, pitch0, 0);
    align_at(&est, start);
    const dquat level = {1, 0, 0, 0};

    rng r = {seed, 0, 0.0};
    const long steps = (long)(CONV_END_S / DT_S + 0.5);
    double last_tilt_violation_s = 0.0, last_bias_violation_s = 0.0;
    double max_tilt_after_deg = 0.0, max_bias_err_after = 0.0;
    double bias_sum_x = 0.0, bias_sum_y = 0.0;
    long bias_n = 0;
    fc_attitude_estimate out = {0};
    for (long k = 1; k <= steps; k++) {
        const double t = (double)k * DT_S;
        const fc_imu_sample s =
            sample(BIAS_TRUE_RADPS + 0.003 * rng_normal(&r), BIAS_TRUE_RADPS + 0.003 * rng_normal(&r),
                   0.003 * rng_normal(&r), 0.1 * rng_normal(&r), 0.1 * rng_normal(&r),
                   G_MPS2 + 0.1 * rng_normal(&r));
        const fc_step_status st = fc_attitude_estimator_step(&est, &s, &out);
        assert_int_equal(st, FC_STEP_OK);
        const double tilt_deg = tilt_between(dq_from_fc(out.attitude), level) / DEG;
        const double bx = from_fc(out.gyro_bias_radps.x, FC_RATE_FRAC);
        const double by = from_fc(out.gyro_bias_radps.y, FC_RATE_FRAC);
        const double bias_err = fmax(fabs(bx - BIAS_TRUE_RADPS), fabs(by - BIAS_TRUE_RADPS));
        if (tilt_deg >= TILT_BOUND_DEG) {
            last_tilt_violation_s = t;
        }
        if (bias_err >= BIAS_BOUND_RADPS) {
            last_bias_violation_s = t;
        }
        if (t >= TILT_ASSERT_FROM_S) {
            max_tilt_after_deg = fmax(max_tilt_after_deg, tilt_deg);
        }
        if (t >= BIAS_ASSERT_FROM_S) {
            max_bias_err_after = fmax(max_bias_err_after, bias_err);
        }
        if (t > CONV_END_S - 10.0) {
            bias_sum_x += bx;
            bias_sum_y += by;
            bias_n++;
        }
    }
    assert_estimate_finite(&out);
    const double mean_err_x = bias_sum_x / (double)bias_n - BIAS_TRUE_RADPS;
    const double mean_err_y = bias_sum_y / (double)bias_n - BIAS_TRUE_RADPS;
    print_message("[%s] %s: 30 deg tilt error, 0.05 rad/s x/y bias, w_c = 1 rad/s, zeta = 0.707:\n"
                  "    tilt < %.0f deg from %.3f s on (max %.3f deg after %.0f s);\n"
                  "    x/y bias within %.3f rad/s from %.3f s on (max error %.5f rad/s after %.0f s);\n"
                  "    mean bias error over the last 10 s: x %+.6f, y %+.6f rad/s\n",
                  BACKEND, name, TILT_BOUND_DEG, last_tilt_violation_s, max_tilt_after_deg,
                  TILT_ASSERT_FROM_S, BIAS_BOUND_RADPS, last_bias_violation_s, max_bias_err_after,
                  BIAS_ASSERT_FROM_S, mean_err_x, mean_err_y);
    assert_true(max_tilt_after_deg < TILT_BOUND_DEG);
    assert_true(last_tilt_violation_s < TILT_ASSERT_FROM_S);
    assert_true(max_bias_err_after < BIAS_BOUND_RADPS);
    assert_true(fabs(mean_err_x) < BIAS_MEAN_BOUND_RADPS);
    assert_true(fabs(mean_err_y) < BIAS_MEAN_BOUND_RADPS);
}

static void test_convergence_roll(void **state)
{
    (void)state;
    run_convergence("roll +30 deg", 30.0 * DEG, 0.0, 1u);
}

static void test_convergence_pitch(void **state)
{
    (void)state;
    run_convergence("pitch -30 deg", 0.0, -30.0 * DEG, 2u);
}

static void test_convergence_roll_and_pitch(void **state)
{
    (void)state;
    /* roll 21.4 deg and pitch 21.4 deg: a 30 deg tilt about a diagonal axis */
    run_convergence("roll/pitch 21.4/21.4 deg", 21.4 * DEG, 21.4 * DEG, 3u);
}

/* ---- accelerometer trust --------------------------------------------------- */

/* Two filters aligned level see the same tilted direction (10 degrees of roll)
 * with |a| = g and with |a| = 1.5 g; band = 0.75 g gives a weight of 1/3 there. */
static void test_reduced_trust_at_1_5_g(void **state)
{
    (void)state;
    fc_attitude_estimator_params p = default_params();
    p.accel_trust_band_mps2 = FC_C(0.75f * 9.81f, ACCEL);
    fc_attitude_estimator est_1g, est_15g;
    assert_int_equal(fc_attitude_estimator_init(&est_1g, &p), FC_INIT_OK);
    assert_int_equal(fc_attitude_estimator_init(&est_15g, &p), FC_INIT_OK);
    const dquat level = {1, 0, 0, 0};
    align_at(&est_1g, level);
    align_at(&est_15g, level);

    double up[3];
    up_in_body(dq_from_rpy(10.0 * DEG, 0, 0), up);
    const fc_imu_sample s1 = sample(0, 0, 0, G_MPS2 * up[0], G_MPS2 * up[1], G_MPS2 * up[2]);
    const fc_imu_sample s15 =
        sample(0, 0, 0, 1.5 * G_MPS2 * up[0], 1.5 * G_MPS2 * up[1], 1.5 * G_MPS2 * up[2]);
    fc_attitude_estimate out1, out15;
    for (int k = 0; k < 250; k++) { /* 0.5 s */
        assert_int_equal(fc_attitude_estimator_step(&est_1g, &s1, &out1), FC_STEP_OK);
        assert_int_equal(fc_attitude_estimator_step(&est_15g, &s15, &out15), FC_STEP_OK);
    }
    const double w1 = from_fc(out1.accel_weight, FC_RATIO_FRAC);
    const double w15 = from_fc(out15.accel_weight, FC_RATIO_FRAC);
    const double moved1 = tilt_between(dq_from_fc(out1.attitude), level) / DEG;
    const double moved15 = tilt_between(dq_from_fc(out15.attitude), level) / DEG;
    print_message("[%s] trust: |a| = g weight %.4f, moved %.3f deg in 0.5 s; |a| = 1.5 g weight "
                  "%.4f, moved %.3f deg\n",
                  BACKEND, w1, moved1, w15, moved15);
    assert_true(fabs(w1 - 1.0) < WEIGHT_TOL_FOR(G_MPS2, 0.75 * 9.81));
    assert_true(fabs(w15 - 1.0 / 3.0) < WEIGHT_TOL_FOR(1.5 * G_MPS2, 0.75 * 9.81));
    assert_true(moved15 < 0.5 * moved1);
    assert_true(moved15 > 0.1 * moved1);
    /* both move toward the measured roll */
    double r1, p1, y1, r15, p15, y15;
    dq_to_rpy(dq_from_fc(out1.attitude), &r1, &p1, &y1);
    dq_to_rpy(dq_from_fc(out15.attitude), &r15, &p15, &y15);
    assert_true(r1 > 0.0 && r15 > 0.0);
}

/* With the default band (2 m/s2) 1.5 g is outside the band: weight 0, a
 * gyro-only step reported as degraded, the attitude does not move; the trust
 * falls continuously inside the band. */
static void test_no_trust_outside_band(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    const dquat level = {1, 0, 0, 0};
    align_at(&est, level);
    double up[3];
    up_in_body(dq_from_rpy(10.0 * DEG, 0, 0), up);
    const fc_imu_sample s =
        sample(0, 0, 0, 1.5 * G_MPS2 * up[0], 1.5 * G_MPS2 * up[1], 1.5 * G_MPS2 * up[2]);
    fc_attitude_estimate out;
    for (int k = 0; k < 250; k++) {
        assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_DEGRADED);
    }
    assert_true(out.accel_weight == FC_INT(0, RATIO));
    assert_true(tilt_between(dq_from_fc(out.attitude), level) < 1e-7);

    /* weight against |a| along the band: 1 - ||a| - g| / 2, monotone */
    double previous = 2.0;
    for (int i = 0; i <= 12; i++) {
        const double norm = G_MPS2 + 0.2 * i;
        const fc_imu_sample si = sample(0, 0, 0, 0, 0, norm);
        fc_attitude_estimator_step(&est, &si, &out);
        const double w = from_fc(out.accel_weight, FC_RATIO_FRAC);
        const double expected = fmax(0.0, 1.0 - (norm - G_MPS2) / 2.0);
        assert_true(fabs(w - expected) < WEIGHT_TOL_FOR(norm, 2.0));
        assert_true(w <= previous);
        previous = w;
        /* and symmetric below g */
        const fc_imu_sample sb = sample(0, 0, 0, 0, 0, 2 * G_MPS2 - norm);
        fc_attitude_estimator_step(&est, &sb, &out);
        assert_true(fabs(from_fc(out.accel_weight, FC_RATIO_FRAC) - expected) <
                    WEIGHT_TOL_FOR(2 * G_MPS2 - norm, 2.0));
    }
}

/* The weight's tolerance where g and the band are not the defaults: in fixed
 * 16 LSB of RATIO plus what the length's error moves it (fc_direction16's
 * 16-bit mantissas and root, within 2^-13 of |a|); in float 8 ulps. */
#if FC_NUMERIC_FIXED
#define WEIGHT_TOL_IN(norm_mps2, band_mps2)                                                         \
    (16.0 / (double)(1 << FC_RATIO_FRAC) + 2.0 * (norm_mps2) * ldexp(1.0, -14) / (band_mps2))
#else
#define WEIGHT_TOL_IN(norm_mps2, band_mps2) (8.0 * (double)FLT_EPSILON)
#endif

/* Over the range of g: the weight 1 - ||a| - g| / band along the band, and a
 * tilted sample corrects the roll by as much whatever g. */
static void test_trust_over_gravity_range(void **state)
{
    (void)state;
    static const double gravities[] = {9.81, 1.5, 30.0, 99.0};
    double up[3];
    up_in_body(dq_from_rpy(10.0 * DEG, 0, 0), up);
    double roll_at_default = 0.0;
    for (size_t i = 0; i < sizeof gravities / sizeof gravities[0]; i++) {
        const double g = gravities[i], band = 0.5 * g;
        fc_attitude_estimator est;
        fc_attitude_estimator_params p = default_params();
        p.gravity_mps2 = to_fc(g, FC_ACCEL_FRAC);
        p.accel_trust_band_mps2 = to_fc(band, FC_ACCEL_FRAC);
        assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
        const dquat level = {1, 0, 0, 0};
        align_at(&est, level);
        fc_attitude_estimate out;
        for (int t = -9; t <= 9; t += 3) {
            const double norm = g + 0.1 * t * band;
            const fc_imu_sample s = sample(0, 0, 0, norm * up[0], norm * up[1], norm * up[2]);
            assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
            const double expected = 1.0 - 0.1 * fabs((double)t);
            assert_true(fabs(from_fc(out.accel_weight, FC_RATIO_FRAC) - expected) <
                        WEIGHT_TOL_IN(norm, band));
        }
        assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
        align_at(&est, level);
        const fc_imu_sample s = sample(0, 0, 0, g * up[0], g * up[1], g * up[2]);
        for (int k = 0; k < 250; k++) {
            assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
        }
        double roll, pitch, yaw;
        dq_to_rpy(dq_from_fc(out.attitude), &roll, &pitch, &yaw);
        if (i == 0) {
            roll_at_default = roll;
        }
        print_message("[%s] g %.2f m/s2: roll %.5f deg after 0.5 s\n", BACKEND, g, roll / DEG);
        assert_true(roll > 0.0 && fabs(roll - roll_at_default) < 1e-3 * roll_at_default);
    }
}

/* ---- gyro integration and the bias clamp ---------------------------------- */

/* A yaw rate with the accelerometer level: the heading follows the gyro (the
 * correction has nothing to say about yaw) and the tilt stays zero. */
static void test_gyro_integration_yaw(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    const dquat level = {1, 0, 0, 0};
    align_at(&est, level);
    const fc_imu_sample s = sample(0, 0, 1.0, 0, 0, G_MPS2);
    fc_attitude_estimate out;
    for (int k = 0; k < 500; k++) { /* 1 s at 1 rad/s */
        assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
    }
    double r, pt, y;
    dq_to_rpy(dq_from_fc(out.attitude), &r, &pt, &y);
    print_message("[%s] 1 s at 1 rad/s about z: yaw error %.2e rad\n", BACKEND, y - 1.0);
    assert_true(fabs(y - 1.0) < INTEGRATION_TOL_RAD);
    assert_true(fabs(r) < INTEGRATION_TOL_RAD && fabs(pt) < INTEGRATION_TOL_RAD);
    assert_true(fabs(from_fc(out.rate_radps.z, FC_RATE_FRAC) - 1.0) < RATE_TOL);
}

/* A bias of 0.3 rad/s against a limit of 0.1 rad/s: the estimate stops at the
 * limit and never passes it. */
static void test_bias_clamp(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    fc_attitude_estimator_params p = default_params();
    p.gyro_bias_limit_radps = FC_C(0.1f, RATE);
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    align_at(&est, (dquat){1, 0, 0, 0});
    const fc_imu_sample s = sample(0.3, -0.3, 0, 0, 0, G_MPS2);
    fc_attitude_estimate out;
    for (int k = 0; k < 5000; k++) {
        fc_attitude_estimator_step(&est, &s, &out);
        assert_true(out.gyro_bias_radps.x <= p.gyro_bias_limit_radps);
        assert_true(out.gyro_bias_radps.y >= -p.gyro_bias_limit_radps);
        assert_estimate_finite(&out);
    }
    assert_true(fabs(from_fc(out.gyro_bias_radps.x, FC_RATE_FRAC) - 0.1) < RATE_TOL);
    assert_true(fabs(from_fc(out.gyro_bias_radps.y, FC_RATE_FRAC) + 0.1) < RATE_TOL);
}

/* ---- bad input ------------------------------------------------------------ */

typedef struct prepared {
    fc_attitude_estimator est;
    fc_attitude_estimate last;
} prepared;

/* Aligned at roll 10 deg, then one good step with a known rate. */
static void prepare(prepared *f)
{
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&f->est, &p), FC_INIT_OK);
    const dquat tilt = dq_from_rpy(10.0 * DEG, 0, 0);
    align_at(&f->est, tilt);
    double up[3];
    up_in_body(tilt, up);
    const fc_imu_sample s = sample(0.2, -0.1, 0.3, G_MPS2 * up[0], G_MPS2 * up[1], G_MPS2 * up[2]);
    assert_int_equal(fc_attitude_estimator_step(&f->est, &s, &f->last), FC_STEP_OK);
}

static bool quat_equal(fc_quat a, fc_quat b)
{
    return a.w == b.w && a.x == b.x && a.y == b.y && a.z == b.z;
}

static bool vec_equal(fc_vec3 a, fc_vec3 b)
{
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

/* Bad gyro: attitude, bias and rate held; the status says so. */
static void check_bad_gyro(fc_imu_sample s, const char *what)
{
    prepared f;
    prepare(&f);
    fc_attitude_estimate out;
    for (int k = 0; k < 10; k++) {
        const fc_step_status st = fc_attitude_estimator_step(&f.est, &s, &out);
        assert_true((st & FC_STEP_BAD_INPUT) != 0u);
        assert_true((st & FC_STEP_ARITH_SATURATED) == 0u);
        assert_estimate_finite(&out);
        assert_true(out.aligned);
        assert_true(quat_equal(out.attitude, f.last.attitude));
        assert_true(vec_equal(out.rate_radps, f.last.rate_radps));
        assert_true(vec_equal(out.gyro_bias_radps, f.last.gyro_bias_radps));
        assert_true(out.accel_weight == FC_INT(0, RATIO));
    }
    print_message("[%s] bad input (%s): status 0x%x, attitude, rate and bias held\n", BACKEND, what,
                  (unsigned)fc_attitude_estimator_step(&f.est, &s, &out));
}

/* Bad accelerometer with a good gyro: gyro-only integration, weight 0, bias held. */
static void check_bad_accel(fc_imu_sample s, const char *what)
{
    prepared f;
    prepare(&f);
    s.gyro_radps = fc_vec3_make(FC_INT(0, RATE), FC_INT(0, RATE), FC_C(0.5f, RATE));
    fc_attitude_estimate out;
    for (int k = 0; k < 100; k++) {
        const fc_step_status st = fc_attitude_estimator_step(&f.est, &s, &out);
        assert_true((st & FC_STEP_BAD_INPUT) != 0u);
        assert_true((st & FC_STEP_ARITH_SATURATED) == 0u);
        assert_estimate_finite(&out);
        assert_true(vec_equal(out.gyro_bias_radps, f.last.gyro_bias_radps));
        assert_true(out.accel_weight == FC_INT(0, RATIO));
    }
    /* 0.2 s at 0.5 rad/s about body z (less the bias estimate, ~1e-5 rad/s here):
     * the tilt is unchanged and the heading turned by ~0.1 rad */
    const dquat before = dq_from_fc(f.last.attitude), after = dq_from_fc(out.attitude);
    const dquat level = {1, 0, 0, 0};
    assert_true(fabs(tilt_between(before, level) - tilt_between(after, level)) < 1e-6);
    const double dot =
        before.w * after.w + before.x * after.x + before.y * after.y + before.z * after.z;
    const double turned = 2.0 * acos(fmin(1.0, fabs(dot)));
    assert_true(fabs(turned - 0.1) < 1e-4);
    print_message("[%s] bad input (%s): status 0x%x, gyro-only step, bias held\n", BACKEND, what,
                  (unsigned)fc_attitude_estimator_step(&f.est, &s, &out));
}

static void test_bad_gyro_nan(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    /* no NaN in fixed: the nearest case is a gyro saturated at the int32 limit */
    fc_imu_sample s = sample(0, 0, 0, 0, 0, G_MPS2);
    s.gyro_radps.x = FC_REAL_MAX;
    check_bad_gyro(s, "saturated gyro");
#else
    check_bad_gyro(sample((double)NAN, 0, 0, 0, 0, G_MPS2), "NaN gyro");
    check_bad_gyro(sample(0, (double)INFINITY, 0, 0, 0, G_MPS2), "inf gyro");
#endif
}

static void test_bad_gyro_beyond_range(void **state)
{
    (void)state;
    check_bad_gyro(sample(0, 0, 36.0, 0, 0, G_MPS2), "gyro beyond range");
    check_bad_gyro(sample(-40.0, 0, 0, 0, 0, G_MPS2), "gyro beyond range");
}

static void test_bad_accel_inf(void **state)
{
    (void)state;
    /* fixed: fc_from_float turns infinity into the int32 limit, beyond the range */
    check_bad_accel(sample(0, 0, 0, (double)INFINITY, 0, G_MPS2), "inf accel");
    check_bad_accel(sample(0, 0, 0, 0, 0, -(double)INFINITY), "-inf accel");
#if !FC_NUMERIC_FIXED
    check_bad_accel(sample(0, 0, 0, 0, (double)NAN, G_MPS2), "NaN accel");
#endif
}

static void test_bad_accel_zero(void **state)
{
    (void)state;
    check_bad_accel(sample(0, 0, 0, 0, 0, 0), "zero accel");
}

static void test_bad_accel_beyond_range(void **state)
{
    (void)state;
    check_bad_accel(sample(0, 0, 0, 0, 0, 170.0), "accel beyond range");
}

/* No sample at all holds everything; good samples afterwards are accepted. */
static void test_null_sample_then_recovery(void **state)
{
    (void)state;
    prepared f;
    prepare(&f);
    fc_attitude_estimate out;
    assert_int_equal(fc_attitude_estimator_step(&f.est, NULL, &out),
                     FC_STEP_BAD_INPUT | FC_STEP_DEGRADED);
    assert_true(quat_equal(out.attitude, f.last.attitude));
    assert_estimate_finite(&out);
    const fc_imu_sample s = sample(0, 0, 0, 0, 0, G_MPS2);
    assert_int_equal(fc_attitude_estimator_step(&f.est, &s, &out), FC_STEP_OK);
    /* a NULL output is tolerated */
    assert_int_equal(fc_attitude_estimator_step(&f.est, &s, NULL), FC_STEP_OK);
}

/* ---- the rate step (the platform's attitude in use) ------------------------ */

/* The rate step forms gyro - b without aligning, correcting or integrating:
 * the attitude stays the identity of the unaligned filter however long it
 * runs on a tilted, turning sample, the rate is the gyro's (b = 0 from init)
 * and the bias does not move. */
static void test_rate_step_forms_the_rate_only(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    const fc_imu_sample s = sample(0.3, -0.2, 0.1, 2.0, -1.0, 9.5);
    fc_attitude_estimate out;
    for (unsigned k = 0; k < 2u * p.alignment_samples; k++) {
        assert_int_equal(fc_attitude_estimator_rate_step(&est, &s, &out), FC_STEP_OK);
    }
    assert_false(out.aligned);
    assert_true(quat_equal(out.attitude, fc_quat_identity()));
    assert_true(fabs(from_fc(out.rate_radps.x, FC_RATE_FRAC) - from_fc(s.gyro_radps.x, FC_RATE_FRAC)) == 0.0);
    assert_true(fabs(from_fc(out.rate_radps.y, FC_RATE_FRAC) - from_fc(s.gyro_radps.y, FC_RATE_FRAC)) == 0.0);
    assert_true(fabs(from_fc(out.rate_radps.z, FC_RATE_FRAC) - from_fc(s.gyro_radps.z, FC_RATE_FRAC)) == 0.0);
    assert_true(from_fc(out.gyro_bias_radps.x, FC_RATE_FRAC) == 0.0 &&
                from_fc(out.gyro_bias_radps.y, FC_RATE_FRAC) == 0.0 &&
                from_fc(out.gyro_bias_radps.z, FC_RATE_FRAC) == 0.0);
    assert_true(from_fc(out.accel_weight, FC_RATIO_FRAC) == 0.0);
    assert_estimate_finite(&out);
}

/* It checks the sample as the full step does: a bad gyro keeps the last good
 * rate, a bad accelerometer or no sample is reported, nothing degrades. */
static void test_rate_step_checks_the_sample(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    fc_attitude_estimate out;
    const fc_imu_sample good = sample(0.5, 0, 0, 0, 0, G_MPS2);
    assert_int_equal(fc_attitude_estimator_rate_step(&est, &good, &out), FC_STEP_OK);
    const fc_imu_sample fast_gyro = sample(40.0, 0, 0, 0, 0, G_MPS2);
    assert_int_equal(fc_attitude_estimator_rate_step(&est, &fast_gyro, &out), FC_STEP_BAD_INPUT);
    assert_true(fabs(from_fc(out.rate_radps.x, FC_RATE_FRAC) - 0.5) < RATE_TOL);
    const fc_imu_sample zero_accel = sample(-0.25, 0, 0, 0, 0, 0);
    assert_int_equal(fc_attitude_estimator_rate_step(&est, &zero_accel, &out), FC_STEP_BAD_INPUT);
    assert_true(fabs(from_fc(out.rate_radps.x, FC_RATE_FRAC) + 0.25) < RATE_TOL); /* the gyro was good */
    const fc_imu_sample far_accel = sample(0, 0, 0, 0, 0, 170.0);
    assert_int_equal(fc_attitude_estimator_rate_step(&est, &far_accel, &out), FC_STEP_BAD_INPUT);
    assert_int_equal(fc_attitude_estimator_rate_step(&est, NULL, &out), FC_STEP_BAD_INPUT);
    assert_true(fabs(from_fc(out.rate_radps.x, FC_RATE_FRAC)) < RATE_TOL);
    assert_estimate_finite(&out);
    assert_int_equal(fc_attitude_estimator_rate_step(&est, &good, NULL), FC_STEP_OK);
    /* before a successful init: not ready, the safe output */
    fc_attitude_estimator_params bad = p;
    bad.dt_s = FC_INT(0, DT);
    assert_int_equal(fc_attitude_estimator_init(&est, &bad), FC_INIT_BAD_PARAM);
    assert_int_equal(fc_attitude_estimator_rate_step(&est, &good, &out), FC_STEP_NOT_READY);
    assert_true(quat_equal(out.attitude, fc_quat_identity()));
    assert_true(from_fc(out.rate_radps.x, FC_RATE_FRAC) == 0.0);
}

/* ---- heading -------------------------------------------------------------- */

static double wrapped(double angle_rad)
{
    return atan2(sin(angle_rad), cos(angle_rad));
}

static double yaw_of(fc_quat q)
{
    double r, pt, y;
    dq_to_rpy(dq_from_fc(q), &r, &pt, &y);
    return y;
}

/* Level at rest with a gyro z bias; a heading sample of the true yaw every
 * `heading_every` steps (0: none). Returns the last estimate after `steps`. */
static fc_attitude_estimate fly_level_with_z_bias(fc_attitude_estimator *est, double bias_z_radps,
                                                  double true_yaw_rad, unsigned heading_every, unsigned steps)
{
    const fc_imu_sample s = sample(0, 0, bias_z_radps, 0, 0, G_MPS2);
    fc_attitude_estimate out;
    memset(&out, 0, sizeof out);
    for (unsigned k = 0; k < steps; k++) {
        if (heading_every != 0u && k % heading_every == 0u) {
            assert_int_equal(fc_attitude_estimator_take_heading(est, to_fc(true_yaw_rad, FC_ANGLE_FRAC)),
                             FC_STEP_OK);
        }
        assert_int_equal(fc_attitude_estimator_step(est, &s, &out), FC_STEP_OK);
    }
    return out;
}

/* Without a heading the yaw follows the gyro's z bias and the bias about the
 * up axis is not estimated (the header's unobservable direction). */
static void test_yaw_drifts_without_heading(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    align_at(&est, (dquat){1, 0, 0, 0});
    const fc_attitude_estimate out = fly_level_with_z_bias(&est, 0.01, 0.0, 0u, 15000u); /* 30 s */
    const double yaw = yaw_of(out.attitude);
    print_message("[%s] no heading, 0.01 rad/s z bias for 30 s: yaw %.4f rad, bias z %.2e rad/s\n", BACKEND,
                  yaw, from_fc(out.gyro_bias_radps.z, FC_RATE_FRAC));
    assert_true(fabs(yaw - 0.3) < 1e-3);
    assert_true(fabs(from_fc(out.gyro_bias_radps.z, FC_RATE_FRAC)) < 1e-6);
}

/* Heading samples at 100 Hz: the yaw holds and the z bias is learnt. With
 * w_h = 1 the heading loop is the tilt loop's, w_c = 1 rad/s, zeta 0.707: after
 * 20 s (20 time constants) the bias estimate is within 1 % of the truth. */
static void test_heading_estimates_the_z_bias(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    align_at(&est, (dquat){1, 0, 0, 0});
    const double truth_yaw = 0.0;
    const fc_attitude_estimate out = fly_level_with_z_bias(&est, 0.01, truth_yaw, 5u, 10000u);
    const double yaw_error = wrapped(yaw_of(out.attitude) - truth_yaw);
    const double bias_z = from_fc(out.gyro_bias_radps.z, FC_RATE_FRAC);
    print_message("[%s] heading at 100 Hz, 0.01 rad/s z bias, 20 s: yaw error %.2e rad, bias z %.5f rad/s\n",
                  BACKEND, yaw_error, bias_z);
    assert_true(fabs(yaw_error) < 1e-4);
    assert_true(fabs(bias_z - 0.01) < 1e-4);
    assert_true(fabs(from_fc(out.rate_radps.z, FC_RATE_FRAC)) < 1e-4);
}

/* A heading half a turn away (the sign branch beyond 90 deg) and one across
 * the +-pi seam: both end within 1e-3 rad of the sample. */
static void test_heading_far_off_converges(void **state)
{
    (void)state;
    const double targets[] = {3.1, -3.1, 2.0 * 3.14159265358979323846 + 0.5, -2.5};
    for (size_t i = 0; i < sizeof targets / sizeof targets[0]; i++) {
        fc_attitude_estimator est;
        const fc_attitude_estimator_params p = default_params();
        assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
        align_at(&est, (dquat){1, 0, 0, 0});
        const fc_attitude_estimate out = fly_level_with_z_bias(&est, 0.0, targets[i], 1u, 10000u);
        const double error = wrapped(yaw_of(out.attitude) - targets[i]);
        print_message("[%s] heading %.2f rad from yaw 0: error after 20 s %.2e rad\n", BACKEND, targets[i], error);
        assert_true(fabs(error) < 1e-3);
        assert_estimate_finite(&out);
    }
}

/* A sample given before the alignment's end gives the initial yaw. */
static void test_alignment_takes_the_heading(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    const dquat tilt = dq_from_rpy(0.1, -0.05, 0.0);
    double up[3];
    up_in_body(tilt, up);
    const fc_imu_sample s = sample(0, 0, 0, G_MPS2 * up[0], G_MPS2 * up[1], G_MPS2 * up[2]);
    fc_attitude_estimate out;
    for (unsigned i = 0; i < p.alignment_samples; i++) {
        if (i + 10u == p.alignment_samples) {
            assert_int_equal(fc_attitude_estimator_take_heading(&est, to_fc(1.2, FC_ANGLE_FRAC)), FC_STEP_OK);
        }
        assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
    }
    assert_true(out.aligned);
    double r, pt, y;
    dq_to_rpy(dq_from_fc(out.attitude), &r, &pt, &y);
    print_message("[%s] aligned with a heading of 1.2 rad: yaw %.7f, roll %.7f, pitch %.7f\n", BACKEND, y, r, pt);
    assert_true(fabs(y - 1.2) < 1e-5);
    assert_true(fabs(r - 0.1) < 1e-5 && fabs(pt + 0.05) < 1e-5);
}

/* One sample corrects for heading_hold_s and then no more; w_h = 0 ignores
 * every sample. */
static void test_heading_hold_and_weight(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    fc_attitude_estimator_params p = default_params();
    p.heading_hold_s = FC_C(0.02f, DT); /* 10 steps */
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    align_at(&est, (dquat){1, 0, 0, 0});
    assert_int_equal(fc_attitude_estimator_take_heading(&est, to_fc(0.5, FC_ANGLE_FRAC)), FC_STEP_OK);
    const fc_imu_sample s = sample(0, 0, 0, 0, 0, G_MPS2);
    fc_attitude_estimate out;
    double yaw_before = 0.0;
    for (int k = 0; k < 20; k++) {
        assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
        const double yaw = yaw_of(out.attitude);
        /* what the bias estimate alone turns in a step: -b_z dt */
        const double bias_turn = -from_fc(out.gyro_bias_radps.z, FC_RATE_FRAC) * DT_S;
        if (k < 10) {
            /* towards the sample, by Kp s dt = 1.4 mrad, far more than the bias */
            assert_true(yaw - yaw_before > 1e-3);
        } else {
            /* held: only the bias learnt in those 10 steps turns it on */
            assert_true(fabs(yaw - yaw_before - bias_turn) < 1e-7);
        }
        yaw_before = yaw;
    }
    /* w_h = 0: the same sample changes nothing */
    p.heading_weight = FC_INT(0, RATIO);
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    align_at(&est, (dquat){1, 0, 0, 0});
    assert_int_equal(fc_attitude_estimator_take_heading(&est, to_fc(0.5, FC_ANGLE_FRAC)), FC_STEP_OK);
    for (int k = 0; k < 20; k++) {
        assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
    }
    assert_true(fabs(yaw_of(out.attitude)) < 1e-6);
}

/* Bad headings are refused and leave the filter as it was. */
static void test_bad_heading_ignored(void **state)
{
    (void)state;
    fc_attitude_estimator est;
    const fc_attitude_estimator_params p = default_params();
    assert_int_equal(fc_attitude_estimator_take_heading(NULL, FC_INT(0, ANGLE)), FC_STEP_NOT_READY);
    memset(&est, 0, sizeof est);
    assert_int_equal(fc_attitude_estimator_take_heading(&est, FC_INT(0, ANGLE)), FC_STEP_NOT_READY);
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    align_at(&est, (dquat){1, 0, 0, 0});
    const fc_real bad[] = {
        FC_C(7.5f, ANGLE), FC_C(-7.5f, ANGLE), FC_REAL_MAX,
#if !FC_NUMERIC_FIXED
        NAN, INFINITY, -INFINITY,
#endif
    };
    const fc_imu_sample s = sample(0, 0, 0, 0, 0, G_MPS2);
    fc_attitude_estimate out;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(fc_attitude_estimator_take_heading(&est, bad[i]), FC_STEP_BAD_INPUT);
        assert_int_equal(est.heading_steps_left, 0u);
        assert_int_equal(fc_attitude_estimator_step(&est, &s, &out), FC_STEP_OK);
        assert_true(fabs(yaw_of(out.attitude)) < 1e-6);
    }
}

/* ---- the formats: nothing saturates at the ends of the sensor ranges ------ */

static void run_extremes(const fc_attitude_estimator_params *p, double gyro_radps, double accel_mps2,
                         const char *what)
{
    fc_attitude_estimator est;
    assert_int_equal(fc_attitude_estimator_init(&est, p), FC_INIT_OK);
    align_at(&est, dq_from_rpy(170.0 * DEG, -80.0 * DEG, 0)); /* far from the truth below */
    fc_attitude_estimate out;
    rng r = {99u, 0, 0.0};
    const double g = from_fc(p->gravity_mps2, FC_ACCEL_FRAC);
    for (int k = 0; k < 4000; k++) {
        const double sx = rng_uniform(&r) < 0.5 ? -1.0 : 1.0;
        const double sy = rng_uniform(&r) < 0.5 ? -1.0 : 1.0;
        fc_imu_sample s;
        switch (k % 4) {
        case 0: /* full-scale rates on every axis, full-scale specific force */
            s = sample(sx * gyro_radps, sy * gyro_radps, -sx * gyro_radps, sy * accel_mps2,
                       sx * accel_mps2, -accel_mps2);
            break;
        case 1: /* full-scale rates, gravity trusted (weight 1) */
            s = sample(-sx * gyro_radps, sx * gyro_radps, sy * gyro_radps, 0, 0, sy * g);
            break;
        case 2: /* at rest with gravity somewhere else */
            s = sample(0, 0, 0, sx * g * 0.6, 0, sy * g * 0.8);
            break;
        default: /* a tiny specific force */
            s = sample(sx * gyro_radps, 0, 0, 0, 1e-4, 0);
            break;
        }
        if (p->heading_weight > FC_INT(0, RATIO) && k % 7 == 0) {
            /* headings over the whole accepted range, most of them far off */
            const double yaw = 7.0 * (2.0 * rng_uniform(&r) - 1.0);
            assert_int_equal(fc_attitude_estimator_take_heading(&est, to_fc(yaw, FC_ANGLE_FRAC)), FC_STEP_OK);
        }
        const fc_step_status st = fc_attitude_estimator_step(&est, &s, &out);
        assert_true((st & (FC_STEP_ARITH_SATURATED | FC_STEP_BAD_INPUT | FC_STEP_NOT_READY)) == 0u);
        assert_estimate_finite(&out);
    }
    print_message("[%s] no saturation: %s\n", BACKEND, what);
}

static void test_no_saturation_at_range_limits(void **state)
{
    (void)state;
    fc_attitude_estimator_params p = default_params();
    p.gyro_jump_radps = FC_INT(0, RATE); /* full-scale rates of either sign, step to step */
    run_extremes(&p, 35.0, 16.0 * 9.80665, "defaults, 35 rad/s and 16 g on every axis, headings at w_h 1");
    /* the widest parameters: w_c = 10, Kp = 20, bias limit 0.8, ranges 100 rad/s and 256 m/s2 */
    p.dt_s = FC_C(0.005f, DT);
    p.crossover_radps = FC_C(10.0f, RATE);
    p.damping = FC_C(1.0f, RATIO);
    p.gyro_bias_limit_radps = FC_C(0.8f, RATE);
    p.accel_trust_band_mps2 = FC_C(9.8f, ACCEL);
    p.gyro_range_radps = FC_C(100.0f, RATE);
    p.accel_range_mps2 = FC_C(256.0f, ACCEL);
    /* 100 + 0.8 + 2 x 20 > 127 rad/s: no heading loop at these gains */
    p.heading_weight = FC_INT(0, RATIO);
    run_extremes(&p, 100.0, 256.0, "w_c 10 rad/s, Kp 20 rad/s, 100 rad/s and 256 m/s2 on every axis");
    /* the widest with a heading loop: 86 + 0.8 + 2 x 20 <= 127 */
    p.heading_weight = FC_INT(1, RATIO);
    p.gyro_range_radps = FC_C(86.0f, RATE);
    run_extremes(&p, 86.0, 256.0, "the same at 86 rad/s with headings at w_h 1");
    p.gyro_range_radps = FC_C(100.0f, RATE);
    p.heading_weight = FC_INT(0, RATIO);
    /* the longest step for that gyro range: 1.9 rad per step and axis, Ki dt = 0.475 */
    p.dt_s = FC_C(0.019f, DT);
    p.crossover_radps = FC_C(5.0f, RATE);
    p.damping = FC_C(2.0f, RATIO);
    run_extremes(&p, 100.0, 256.0, "dt 19 ms, w_c 5 rad/s, Kp 20 rad/s, 100 rad/s and 256 m/s2");
}

/* A gyro sample that jumps further than gyro_jump + gyro_accel_max t from the
 * last good one is a glitch: bad input, not used (the rate stays the last good
 * one inside the filter, gyro_ok says not to fly on it); the next sample
 * that agrees is taken. The defaults: 2 rad/s + 1000 rad/s^2 x 2 ms = 4 rad/s. */
static void test_gyro_glitch_rejected(void **state)
{
    (void)state;
    fc_attitude_estimator_params p = default_params();
    fc_attitude_estimator est;
    assert_int_equal(fc_attitude_estimator_init(&est, &p), FC_INIT_OK);
    align_at(&est, dq_from_rpy(0, 0, 0));
    fc_attitude_estimate out;
    fc_imu_sample s = sample(0.5, 0, 0, 0, 0, G_MPS2);
    assert_int_equal(fc_attitude_estimator_step(&est, &s, &out) & FC_STEP_BAD_INPUT, 0u);
    assert_true(out.gyro_ok);
    /* 30 rad/s inside the 35 rad/s range, 29.5 from the last: rejected */
    s = sample(30.0, 0, 0, 0, 0, G_MPS2);
    assert_true((fc_attitude_estimator_step(&est, &s, &out) & FC_STEP_BAD_INPUT) != 0u);
    assert_false(out.gyro_ok);
    assert_true(out.accel_ok);
    assert_true(fabs(from_fc(out.rate_radps.x, FC_RATE_FRAC) - 0.5) < 1e-3);
    /* back near the last good one: taken */
    s = sample(0.6, 0, 0, 0, 0, G_MPS2);
    assert_int_equal(fc_attitude_estimator_step(&est, &s, &out) & FC_STEP_BAD_INPUT, 0u);
    assert_true(out.gyro_ok);
    /* a change of 3.9 rad/s in one step is inside 4 rad/s: taken */
    s = sample(4.5, 0, 0, 0, 0, G_MPS2);
    assert_int_equal(fc_attitude_estimator_step(&est, &s, &out) & FC_STEP_BAD_INPUT, 0u);
    /* ten bad steps later the slack is 2 + 11 x 2 = 24 rad/s: a change of 20 is taken */
    s = sample(NAN_OR_BEYOND, 0, 0, 0, 0, G_MPS2);
    for (int k = 0; k < 10; k++) {
        (void)fc_attitude_estimator_step(&est, &s, &out);
        assert_false(out.gyro_ok);
    }
    s = sample(24.5, 0, 0, 0, 0, G_MPS2);
    assert_int_equal(fc_attitude_estimator_step(&est, &s, &out) & FC_STEP_BAD_INPUT, 0u);
    assert_true(out.gyro_ok);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_params_init),
        cmocka_unit_test(test_gyro_glitch_rejected),
        cmocka_unit_test(test_bad_params_rejected),
        cmocka_unit_test(test_reinit_with_bad_params),
        cmocka_unit_test(test_alignment_from_tilted_gravity),
        cmocka_unit_test(test_alignment_averages_noise),
        cmocka_unit_test(test_alignment_skips_bad_samples),
        cmocka_unit_test(test_convergence_roll),
        cmocka_unit_test(test_convergence_pitch),
        cmocka_unit_test(test_convergence_roll_and_pitch),
        cmocka_unit_test(test_reduced_trust_at_1_5_g),
        cmocka_unit_test(test_no_trust_outside_band),
        cmocka_unit_test(test_trust_over_gravity_range),
        cmocka_unit_test(test_gyro_integration_yaw),
        cmocka_unit_test(test_bias_clamp),
        cmocka_unit_test(test_bad_gyro_nan),
        cmocka_unit_test(test_bad_gyro_beyond_range),
        cmocka_unit_test(test_bad_accel_inf),
        cmocka_unit_test(test_bad_accel_zero),
        cmocka_unit_test(test_bad_accel_beyond_range),
        cmocka_unit_test(test_null_sample_then_recovery),
        cmocka_unit_test(test_rate_step_forms_the_rate_only),
        cmocka_unit_test(test_rate_step_checks_the_sample),
        cmocka_unit_test(test_yaw_drifts_without_heading),
        cmocka_unit_test(test_heading_estimates_the_z_bias),
        cmocka_unit_test(test_heading_far_off_converges),
        cmocka_unit_test(test_alignment_takes_the_heading),
        cmocka_unit_test(test_heading_hold_and_weight),
        cmocka_unit_test(test_bad_heading_ignored),
        cmocka_unit_test(test_no_saturation_at_range_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

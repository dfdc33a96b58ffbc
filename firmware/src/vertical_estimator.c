/* vertical_estimator.c - vertical speed, accelerometer bias, gear height and
 * hover thrust (fc/vertical_estimator.h). */
#include "fc/vertical_estimator.h"

void fc_vertical_estimator_default_params(fc_vertical_estimator_params *p, fc_real dt_s, fc_real gravity_mps2,
                                          fc_real weight_n)
{
    p->dt_s = dt_s;
    p->gravity_mps2 = gravity_mps2;
    p->speed_crossover_radps = FC_INT(1, RATIO);
    p->height_crossover_radps = FC_INT(2, RATIO);
    p->accel_bias_limit_mps2 = FC_C(0.5f, ACCEL);
    p->accel_tau_s = FC_C(0.05f, DT);
    p->bias_average_tau_s = FC_INT(2, TIME);
    p->hover_tau_s = FC_INT(2, TIME);
    fc_vertical_estimator_set_weight(p, weight_n);
    p->range_period_max_s = FC_C(0.1f, DT);
}

void fc_vertical_estimator_set_weight(fc_vertical_estimator_params *p, fc_real weight_n)
{
    fc_arith ar = {0u};
    p->hover_thrust_n = weight_n;
    p->hover_min_n = fc_mul(&ar, weight_n, FC_C(0.5f, UNIT), FC_SHIFT(FORCE, UNIT, FORCE));
    p->hover_max_n = fc_mul(&ar, weight_n, FC_C(1.5f, RATIO), FC_SHIFT(FORCE, RATIO, FORCE));
}

static bool vertical_params_valid(const fc_vertical_estimator_params *p)
{
    const bool finite = fc_is_finite(p->dt_s) && fc_is_finite(p->gravity_mps2) &&
                        fc_is_finite(p->speed_crossover_radps) && fc_is_finite(p->height_crossover_radps) &&
                        fc_is_finite(p->accel_bias_limit_mps2) && fc_is_finite(p->accel_tau_s) &&
                        fc_is_finite(p->bias_average_tau_s) &&
                        fc_is_finite(p->hover_tau_s) && fc_is_finite(p->hover_thrust_n) &&
                        fc_is_finite(p->hover_min_n) && fc_is_finite(p->hover_max_n) &&
                        fc_is_finite(p->range_period_max_s);
    return finite && p->dt_s > FC_INT(0, DT) && p->dt_s <= FC_C(0.1f, DT) && p->gravity_mps2 > FC_INT(0, ACCEL) &&
           p->gravity_mps2 <= FC_INT(100, ACCEL) && p->speed_crossover_radps > FC_INT(0, RATIO) &&
           p->speed_crossover_radps <= FC_INT(10, RATIO) && p->height_crossover_radps > FC_INT(0, RATIO) &&
           p->height_crossover_radps <= FC_INT(10, RATIO) && p->accel_bias_limit_mps2 > FC_INT(0, ACCEL) &&
           p->accel_bias_limit_mps2 <= FC_INT(5, ACCEL) && p->accel_tau_s >= p->dt_s &&
           p->accel_tau_s <= FC_INT(1, DT) && p->hover_tau_s >= FC_C(0.1f, TIME) &&
           p->bias_average_tau_s >= FC_C(0.1f, TIME) && p->bias_average_tau_s <= FC_INT(100, TIME) &&
           p->hover_tau_s <= FC_INT(100, TIME) && p->hover_min_n > FC_INT(0, FORCE) &&
           p->hover_min_n <= p->hover_thrust_n && p->hover_thrust_n <= p->hover_max_n &&
           p->hover_max_n <= FC_INT(1000, FORCE) && p->range_period_max_s > FC_INT(0, DT) &&
           p->range_period_max_s <= FC_INT(1, DT);
}

fc_init_result fc_vertical_estimator_init(fc_vertical_estimator *v, const fc_vertical_estimator_params *p)
{
    v->ready = false;
    v->ar.saturated = 0u;
    v->est = (fc_vertical_estimate){0};
    if (!vertical_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    v->p = *p;
    fc_arith *ar = &v->ar;
    /* the loop's gains from exact products (w_v <= 10, dt <= 0.1: inside RATIO) */
    const fc_real two_w_v = fc_add(ar, p->speed_crossover_radps, p->speed_crossover_radps);
    const fc_real w_v_sq = fc_mul(ar, p->speed_crossover_radps, p->speed_crossover_radps, FC_SHIFT(RATIO, RATIO, RATIO));
    v->dt = fc_gain_of(p->dt_s, FC_DT_FRAC);
    v->speed_gain = fc_gain_of_product(two_w_v, FC_RATIO_FRAC, p->dt_s, FC_DT_FRAC);
    v->bias_gain_per_s = fc_gain_of_product(w_v_sq, FC_RATIO_FRAC, p->dt_s, FC_DT_FRAC);
    v->speed_gain_rest = fc_gain_of_product(fc_mul(ar, two_w_v, FC_INT(3, RATIO), FC_SHIFT(RATIO, RATIO, RATIO)),
                                            FC_RATIO_FRAC, p->dt_s, FC_DT_FRAC);
    v->bias_gain_rest_per_s = fc_gain_of_product(fc_mul(ar, w_v_sq, FC_INT(9, RATIO), FC_SHIFT(RATIO, RATIO, RATIO)),
                                                 FC_RATIO_FRAC, p->dt_s, FC_DT_FRAC);
    v->height_gain_per_s = fc_gain_of(fc_add(ar, p->height_crossover_radps, p->height_crossover_radps), FC_RATIO_FRAC);
    v->height_speed_gain_per_s2 = fc_gain_of_product(p->height_crossover_radps, FC_RATIO_FRAC,
                                                     p->height_crossover_radps, FC_RATIO_FRAC);
    v->accel_filter_gain = fc_gain_of(fc_div(ar, p->dt_s, p->accel_tau_s, FC_DIV_SHIFT(DT, DT, UNIT)), FC_UNIT_FRAC);
    v->hover_gain = fc_gain_of(fc_div(ar, p->dt_s, p->hover_tau_s, FC_DIV_SHIFT(DT, TIME, UNIT)), FC_UNIT_FRAC);
    v->bias_average_gain =
        fc_gain_of(fc_div(ar, p->dt_s, p->bias_average_tau_s, FC_DIV_SHIFT(DT, TIME, UNIT)), FC_UNIT_FRAC);
    v->gravity_mps2 = fc_gain_of(p->gravity_mps2, FC_ACCEL_FRAC);
    v->inv_gravity_s2pm =
        fc_gain_of(fc_div(ar, FC_INT(1, ACCEL), p->gravity_mps2, FC_DIV_SHIFT(ACCEL, ACCEL, RATIO)), FC_RATIO_FRAC);
    fc_vertical_estimator_reset(v);
    v->est.hover_thrust_n = p->hover_thrust_n;
    v->ready = v->ar.saturated == 0u;
    return v->ready ? FC_INIT_OK : FC_INIT_BAD_PARAM;
}

void fc_vertical_estimator_reset(fc_vertical_estimator *v)
{
    v->est.vz_mps = FC_INT(0, VEL);
    v->est.accel_z_mps2 = FC_INT(0, ACCEL);
    v->est.accel_bias_mps2 = FC_INT(0, ACCEL);
    v->bias_fast_mps2 = FC_INT(0, ACCEL);
    v->est.gear_height_m = FC_INT(0, LENGTH);
    v->est.gear_height_known = false;
    v->range_gap_s = FC_INT(0, DT);
}

/* (R f)_z - g: the third row of R(q), [2(xz - wy), 2(yz + wx), 1 - 2(x^2 + y^2)],
 * times the specific force, less gravity. The row from q in UNIT16 (its
 * products exact in UNIT16_SQ, each entry rounded once to UNIT16), each
 * entry within 2^-12 of R's: the vertical acceleration within 3 2^-12 |f|,
 * a bias at a steady attitude that the bias loop takes out. */
static fc_real vertical_accel_mps2(fc_arith *ar, const fc_quat *q, const fc_vec3 *f, fc_real gravity_mps2)
{
    const fc_quat16 h = fc_quat16_round_unit(*q); /* q is unit (fc_vertical_estimator_input) */
    const int sq = FC_UNIT16_SQ_FRAC, to = FC_UNIT16_FRAC;
    /* each sum of two products within 1 + 2^-12: twice it fits 32 bits */
    const fc_real16 r20 = fc_narrow16(ar, 2 * fc_dot2_16(h.x, h.z, fc_neg16(h.w), h.y), sq, to);
    const fc_real16 r21 = fc_narrow16(ar, 2 * fc_dot2_16(h.y, h.z, h.w, h.x), sq, to);
    const fc_real16 r22 = fc_narrow16(ar, FC_INT(1, UNIT16_SQ) - 2 * fc_sumsq2_16(h.x, h.y), sq, to);
    const int to_accel = FC_SHIFT(ACCEL, UNIT16, ACCEL);
    const fc_real up = fc_add_inline(ar, fc_add_inline(ar, fc_mul_by16(ar, f->x, r20, to_accel), fc_mul_by16(ar, f->y, r21, to_accel)),
                              fc_mul_by16(ar, f->z, r22, to_accel));
    return fc_sub_inline(ar, up, gravity_mps2);
}

/* h' = v, v' = a - b (the prediction), with a the bias-corrected acceleration. */
static void predict(fc_vertical_estimator *v, fc_real accel_mps2)
{
    fc_arith *ar = &v->ar;
    if (v->est.gear_height_known) {
        v->est.gear_height_m =
            fc_add_inline(ar, v->est.gear_height_m, fc_mul_gain(ar, v->est.vz_mps, v->dt, FC_GAIN_SHIFT(VEL, LENGTH)));
    }
    v->est.vz_mps = fc_clamp(fc_add_inline(ar, v->est.vz_mps, fc_mul_gain(ar, accel_mps2, v->dt, FC_GAIN_SHIFT(ACCEL, VEL))),
                             FC_INT(-100, VEL), FC_INT(100, VEL));
}

/* The measured speed corrects the speed (l1 dt) and the bias (l2 dt); the
 * bias's average follows it over bias_average_tau_s. At rest the loop runs
 * at three times its crossover (l1 x 3, l2 x 9) and the average is the bias
 * itself: nothing moves, nothing ripples, and the flight starts with it. */
static void correct_by_speed(fc_vertical_estimator *v, fc_real vz_measured_mps, bool at_rest)
{
    fc_arith *ar = &v->ar;
    const fc_real residual = fc_sub_inline(ar, vz_measured_mps, v->est.vz_mps);
    const fc_gain speed_gain = at_rest ? v->speed_gain_rest : v->speed_gain;
    const fc_gain bias_gain = at_rest ? v->bias_gain_rest_per_s : v->bias_gain_per_s;
    v->est.vz_mps = fc_add_inline(ar, v->est.vz_mps, fc_mul_gain(ar, residual, speed_gain, FC_GAIN_SHIFT(VEL, VEL)));
    const fc_real bias_step = fc_mul_gain(ar, residual, bias_gain, FC_GAIN_SHIFT(VEL, ACCEL));
    v->bias_fast_mps2 = fc_clamp(fc_sub_inline(ar, v->bias_fast_mps2, bias_step), fc_neg(ar, v->p.accel_bias_limit_mps2),
                                 v->p.accel_bias_limit_mps2);
    const fc_real change = fc_sub_inline(ar, v->bias_fast_mps2, v->est.accel_bias_mps2);
    v->est.accel_bias_mps2 =
        at_rest ? v->bias_fast_mps2
                : fc_add_inline(ar, v->est.accel_bias_mps2,
                         fc_mul_gain(ar, change, v->bias_average_gain, FC_GAIN_SHIFT(ACCEL, ACCEL)));
}

/* A range sample corrects the gear height, and the speed when nothing else does. */
static void correct_by_range(fc_vertical_estimator *v, fc_real gear_height_m, bool speed_too)
{
    fc_arith *ar = &v->ar;
    if (!v->est.gear_height_known) {
        v->est.gear_height_m = gear_height_m;
        v->est.gear_height_known = true;
        v->range_gap_s = FC_INT(0, DT);
        return;
    }
    const fc_real gap_s = fc_min(v->range_gap_s, v->p.range_period_max_s);
    v->range_gap_s = FC_INT(0, DT);
    const fc_real residual = fc_sub_inline(ar, gear_height_m, v->est.gear_height_m);
    const fc_real height_gain = fc_mul_gain(ar, gap_s, v->height_gain_per_s, FC_GAIN_SHIFT(DT, RATIO));
    v->est.gear_height_m =
        fc_add_inline(ar, v->est.gear_height_m, fc_mul(ar, height_gain, residual, FC_SHIFT(RATIO, LENGTH, LENGTH)));
    if (speed_too) {
        const fc_real speed_gain = fc_mul_gain(ar, gap_s, v->height_speed_gain_per_s2, FC_GAIN_SHIFT(DT, RATIO));
        v->est.vz_mps = fc_add_inline(ar, v->est.vz_mps, fc_mul(ar, speed_gain, residual, FC_SHIFT(RATIO, LENGTH, VEL)));
    }
}

/* Without an accelerometer: the acceleration the thrust gives against the
 * hover thrust, a = g (T k_h / T_h - 1). */
static fc_real thrust_model_accel_mps2(fc_vertical_estimator *v, const fc_vertical_estimator_input *in)
{
    fc_arith *ar = &v->ar;
    const fc_real vertical_thrust_n = fc_mul(ar, in->thrust_n, in->tilt_cos, FC_SHIFT(FORCE, RATIO, FORCE));
    const fc_real load_factor = fc_div(ar, vertical_thrust_n, v->est.hover_thrust_n, FC_DIV_SHIFT(FORCE, FORCE, RATIO));
    return fc_mul_gain(ar, fc_sub(ar, load_factor, FC_INT(1, RATIO)), v->gravity_mps2, FC_GAIN_SHIFT(RATIO, ACCEL));
}

/* T_h += (dt / tau) (T k_h - T_h (a + g) / g), inside its bounds. */
static void learn_hover_thrust(fc_vertical_estimator *v, const fc_vertical_estimator_input *in, fc_real accel_mps2)
{
    fc_arith *ar = &v->ar;
    const fc_real vertical_thrust_n = fc_mul(ar, in->thrust_n, in->tilt_cos, FC_SHIFT(FORCE, RATIO, FORCE));
    const fc_real load_factor =
        fc_mul_gain(ar, fc_add_inline(ar, accel_mps2, v->p.gravity_mps2), v->inv_gravity_s2pm, FC_GAIN_SHIFT(ACCEL, RATIO));
    const fc_real held_n = fc_mul(ar, v->est.hover_thrust_n, load_factor, FC_SHIFT(FORCE, RATIO, FORCE));
    const fc_real step_n = fc_mul_gain(ar, fc_sub_inline(ar, vertical_thrust_n, held_n), v->hover_gain, FC_GAIN_SHIFT(FORCE, FORCE));
    v->est.hover_thrust_n = fc_clamp(fc_add_inline(ar, v->est.hover_thrust_n, step_n), v->p.hover_min_n, v->p.hover_max_n);
}

/* The estimate handed out, field by field (a struct assignment is a byte
 * loop on the ATmega at -Os). */
static inline __attribute__((always_inline)) void vertical_copy_estimate(fc_vertical_estimate *to,
                                                                        const fc_vertical_estimate *from)
{
    to->vz_mps = from->vz_mps;
    to->accel_z_mps2 = from->accel_z_mps2;
    to->accel_bias_mps2 = from->accel_bias_mps2;
    to->gear_height_m = from->gear_height_m;
    to->hover_thrust_n = from->hover_thrust_n;
    to->gear_height_known = from->gear_height_known;
}

fc_step_status fc_vertical_estimator_step(fc_vertical_estimator *v, const fc_vertical_estimator_input *in,
                                          fc_vertical_estimate *out)
{
    if (!v->ready) {
        *out = (fc_vertical_estimate){0};
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &v->ar;
    ar->saturated = 0u;
    fc_step_status status = FC_STEP_OK;
    /* at most 1 s + a step of at most 0.1 s: inside DT, no saturation */
    v->range_gap_s = fc_min(v->range_gap_s + v->p.dt_s, FC_INT(1, DT));
    fc_real accel_mps2;
    if (in->accel_ok) {
        const fc_real raw_mps2 = vertical_accel_mps2(ar, in->attitude, in->accel_mps2, v->p.gravity_mps2);
        accel_mps2 = fc_sub_inline(ar, raw_mps2, in->vz_ok ? v->bias_fast_mps2 : v->est.accel_bias_mps2);
    } else {
        accel_mps2 = thrust_model_accel_mps2(v, in);
        status |= FC_STEP_DEGRADED;
    }
    const fc_real change = fc_sub_inline(ar, accel_mps2, v->est.accel_z_mps2);
    v->est.accel_z_mps2 =
        fc_add_inline(ar, v->est.accel_z_mps2, fc_mul_gain(ar, change, v->accel_filter_gain, FC_GAIN_SHIFT(ACCEL, ACCEL)));
    predict(v, accel_mps2);
    if (in->vz_ok) {
        correct_by_speed(v, in->vz_mps, in->at_rest);
    }
    if (in->gear_height_fresh) {
        correct_by_range(v, in->gear_height_m, !in->vz_ok);
    }
    if (in->learn_hover && in->accel_ok) {
        learn_hover_thrust(v, in, accel_mps2);
    }
    vertical_copy_estimate(out, &v->est);
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

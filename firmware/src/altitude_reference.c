/* altitude_reference.c - the landing reference (3.6) (fc/altitude_reference.h). */
#include "fc/altitude_reference.h"

static bool reference_params_valid(const fc_altitude_reference_params *p)
{
    fc_arith scratch = {0u};
    return fc_is_finite(p->dt_s) && fc_is_finite(p->tau_s) && fc_is_finite(p->offset_init_m) &&
           fc_is_finite(p->bias_m) && p->dt_s > FC_INT(0, DT) && p->dt_s <= FC_C(0.1f, DT) &&
           p->tau_s >= FC_C(0.01f, TIME) && p->tau_s <= FC_INT(1000, TIME) &&
           fc_abs(&scratch, p->offset_init_m) <= FC_INT(1000, LENGTH) &&
           fc_abs(&scratch, p->bias_m) <= FC_INT(100, LENGTH);
}

fc_init_result fc_altitude_reference_init(fc_altitude_reference *ref,
                                          const fc_altitude_reference_params *p)
{
    ref->ready = false;
    ref->ar.saturated = 0u;
    ref->decay = FC_INT(0, UNIT);
    ref->offset_m = FC_INT(0, LENGTH);
    ref->bias_m = FC_INT(0, LENGTH);
    ref->offset_rate_mps = FC_INT(0, VEL);
    ref->offset_accel_mps2 = FC_INT(0, ACCEL);
    if (!reference_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    fc_arith *ar = &ref->ar;
    /* dt / tau as RATIO, then the share of the decay a step takes, 1 - e^(-dt/tau) */
    const fc_real dt_over_tau = fc_div(ar, p->dt_s, p->tau_s, FC_DIV_SHIFT(DT, TIME, RATIO));
    ref->decay_loss_per_step = fc_gain_of(fc_sub(ar, FC_INT(1, UNIT), fc_exp_neg(ar, dt_over_tau)), FC_UNIT_FRAC);
    ref->inv_tau_per_s = fc_div(ar, FC_INT(1, TIME), p->tau_s, FC_DIV_SHIFT(TIME, TIME, GAIN));
    ref->bias_m = p->bias_m;
    ref->ready = true;
    fc_altitude_reference_restart(ref, p->offset_init_m);
    if (ref->ar.saturated != 0u) {
        /* the offset's rate or acceleration does not fit its format: not ready */
        ref->ready = false;
        return FC_INIT_BAD_PARAM;
    }
    return FC_INIT_OK;
}

void fc_altitude_reference_restart(fc_altitude_reference *ref, fc_real offset_m)
{
    fc_arith *ar = &ref->ar;
    ref->decay = FC_INT(1, UNIT);
    /* the range init accepts; beyond it (or not finite) the offset is clamped / zero */
    ref->offset_m = fc_is_finite(offset_m) ? fc_clamp(offset_m, FC_INT(-1000, LENGTH), FC_INT(1000, LENGTH))
                                           : FC_INT(0, LENGTH);
    /* z_r_init / tau and z_r_init / tau^2 */
    ref->offset_rate_mps = fc_mul(ar, ref->offset_m, ref->inv_tau_per_s, FC_SHIFT(LENGTH, GAIN, VEL));
    ref->offset_accel_mps2 =
        fc_mul(ar, ref->offset_rate_mps, ref->inv_tau_per_s, FC_SHIFT(VEL, GAIN, ACCEL));
}

fc_step_status fc_altitude_reference_step(fc_altitude_reference *ref, const fc_vertical_trajectory *pad,
                                          fc_vertical_trajectory *reference)
{
    if (!ref->ready) {
        reference->z_m = FC_INT(0, LENGTH);
        reference->vz_mps = FC_INT(0, VEL);
        reference->az_mps2 = FC_INT(0, ACCEL);
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &ref->ar;
    ar->saturated = 0u;
    fc_step_status status = FC_STEP_OK;
    fc_vertical_trajectory pad_used = *pad;
    const fc_real length = FC_C(FC_INPUT_MAX_LENGTH_M, LENGTH);
    const fc_real speed = FC_C(FC_INPUT_MAX_SPEED_MPS, VEL);
    const fc_real accel = FC_C(FC_INPUT_MAX_ACCEL_MPS2, ACCEL);
    if (!fc_within(pad->z_m, length) || !fc_within(pad->vz_mps, speed) || !fc_within(pad->az_mps2, accel)) {
        /* a still pad at the bias-free origin keeps the reference defined */
        pad_used.z_m = FC_INT(0, LENGTH);
        pad_used.vz_mps = FC_INT(0, VEL);
        pad_used.az_mps2 = FC_INT(0, ACCEL);
        status |= FC_STEP_BAD_INPUT;
    }
    /* (3.6) and its derivatives: the three terms scaled by the same decay,
     * read to 2^-15 (UNIT16), which the decay itself keeps in 32 bits */
    const fc_real16 decay16 = fc_narrow16(ar, ref->decay, FC_UNIT_FRAC, FC_UNIT16_FRAC);
    const fc_real offset_now = fc_mul_by16(ar, ref->offset_m, decay16, FC_SHIFT(LENGTH, UNIT16, LENGTH));
    reference->z_m = fc_add_inline(ar, fc_add_inline(ar, pad_used.z_m, ref->bias_m), offset_now);
    reference->vz_mps =
        fc_sub_inline(ar, pad_used.vz_mps, fc_mul_by16(ar, ref->offset_rate_mps, decay16, FC_SHIFT(VEL, UNIT16, VEL)));
    reference->az_mps2 = fc_add_inline(
        ar, pad_used.az_mps2, fc_mul_by16(ar, ref->offset_accel_mps2, decay16, FC_SHIFT(ACCEL, UNIT16, ACCEL)));
    const fc_real decay_loss = fc_mul_gain(ar, ref->decay, ref->decay_loss_per_step, FC_GAIN_SHIFT(UNIT, UNIT));
    /* decay in [0, 1] and its loss a share of it in [0, 1): no saturation test */
    ref->decay = ref->decay - decay_loss;
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

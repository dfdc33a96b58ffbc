/* vec3.c - three-vectors (fc/vec3.h). One source for both backends. */
#include "fc/vec3.h"

fc_vec3 fc_vec3_neg(fc_arith *ar, fc_vec3 v)
{
    return fc_vec3_make(fc_neg(ar, v.x), fc_neg(ar, v.y), fc_neg(ar, v.z));
}

fc_real fc_vec3_norm(fc_arith *ar, fc_vec3 v, int frac)
{
    (void)frac; /* the norm keeps the format of the components */
    return fc_hypot3(ar, v.x, v.y, v.z);
}

fc_vec3 fc_vec3_normalize(fc_arith *ar, fc_vec3 v, int frac, bool *ok)
{
    return fc_vec3_divide_by_norm(ar, v, fc_vec3_norm(ar, v, frac), ok);
}

fc_vec3 fc_vec3_divide_by_norm(fc_arith *ar, fc_vec3 v, fc_real norm, bool *ok)
{
    if (!(norm > FC_INT(0, UNIT)) || !fc_is_finite(norm)) {
        *ok = false;
        return fc_vec3_zero();
    }
    *ok = true;
    /* (v << UNIT) / |v|: both in format frac, the quotient in UNIT */
    const int shift = FC_UNIT_FRAC;
    return fc_vec3_make(fc_div(ar, v.x, norm, shift), fc_div(ar, v.y, norm, shift),
                        fc_div(ar, v.z, norm, shift));
}

fc_vec3 fc_vec3_clamp_norm(fc_arith *ar, fc_vec3 v, fc_real max_norm, int frac)
{
    bool clamped = false;
    return fc_vec3_clamp_norm_report(ar, v, max_norm, frac, &clamped);
}

fc_vec3 fc_vec3_clamp_norm_report(fc_arith *ar, fc_vec3 v, fc_real max_norm, int frac, bool *clamped)
{
    *clamped = false;
    if (max_norm >= FC_INT(0, UNIT) && fc_hypot3_within(v.x, v.y, v.z, max_norm)) {
        return v; /* |v| <= max_norm, the common case: in fixed decided without the root */
    }
    fc_arith probe = {0u};
    fc_real norm = fc_vec3_norm(&probe, v, frac);
    fc_real limit = max_norm;
    if (probe.saturated != 0u) {
        /* |v| of a vector near the corners of its format does not fit the format
         * (fixed only): compare and divide with |v|/2 and max_norm/2 instead */
        const fc_real half = FC_C(0.5f, UNIT);
        norm = fc_vec3_norm(ar, fc_vec3_scale(ar, v, half, FC_UNIT_FRAC), frac);
        limit = fc_mul(ar, max_norm, half, FC_UNIT_FRAC);
    }
    if (!(norm > limit)) {
        return v;
    }
    /* max_norm / |v| < 1 as UNIT; the direction of v is kept */
    const fc_real ratio = fc_div(ar, limit, norm, FC_UNIT_FRAC);
    const fc_vec3 scaled = fc_vec3_scale(ar, v, ratio, FC_UNIT_FRAC);
    *clamped = scaled.x != v.x || scaled.y != v.y || scaled.z != v.z;
    return scaled;
}



/*
 * tests/fuzz/fuzz_common.h - what every libFuzzer harness shares: reading the
 * fuzz bytes as raw bit patterns of the input structs, and the checks (abort()
 * on failure, with a line saying which output broke which bound).
 */
#ifndef FC_FUZZ_COMMON_H
#define FC_FUZZ_COMMON_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fc/quat.h"
#include "fc/scalar.h"
#include "fc/vec3.h"

/* Fuzzed steps per input at most, then FUZZ_CLEAN_STEPS steps of a benign
 * input (so a bad value carried in the state shows up afterwards). */
#define FUZZ_MAX_STEPS 24
#define FUZZ_CLEAN_STEPS 4

/* A cursor over the fuzz bytes. */
typedef struct fuzz_bytes {
    const uint8_t *data;
    size_t size;
} fuzz_bytes;

static inline uint8_t fuzz_byte(fuzz_bytes *b)
{
    if (b->size == 0) {
        return 0;
    }
    const uint8_t v = b->data[0];
    b->data++;
    b->size--;
    return v;
}

/* Fills n bytes of dst from the cursor, zero-padding at the end of the input.
 * Returns 0 when the input was already exhausted. */
static inline int fuzz_take(fuzz_bytes *b, void *dst, size_t n)
{
    if (b->size == 0) {
        return 0;
    }
    const size_t k = b->size < n ? b->size : n;
    memset(dst, 0, n);
    memcpy(dst, b->data, k);
    b->data += k;
    b->size -= k;
    return 1;
}

static inline void fuzz_fail(const char *what, float value, const char *file, int line)
{
    fprintf(stderr, "%s:%d: fuzz check failed: %s (value %.9g)\n", file, line, what, (double)value);
    abort();
}

/* Values as float, whatever the backend; frac is the Q-format in fixed. */
#define FUZZ_F(x, KIND) fc_to_float((x), FC_FRAC(KIND))

/* finite (float backend; always true in fixed) */
#define FUZZ_FINITE(x, KIND)                                                     \
    do {                                                                         \
        const float fuzz_v_ = FUZZ_F((x), KIND);                                 \
        if (!isfinite(fuzz_v_)) {                                                \
            fuzz_fail(#x " is not finite", fuzz_v_, __FILE__, __LINE__);         \
        }                                                                        \
    } while (0)

#define FUZZ_FINITE_VEC3(v, KIND)   \
    do {                            \
        FUZZ_FINITE((v).x, KIND);   \
        FUZZ_FINITE((v).y, KIND);   \
        FUZZ_FINITE((v).z, KIND);   \
    } while (0)

/* lo <= x <= hi up to a rounding allowance: relative 1e-5 in float, 4 LSB in
 * fixed (clamps are exact there; the slack covers the vector scalings). */
static inline int fuzz_within(fc_real x, fc_real lo, fc_real hi, int frac)
{
#if FC_NUMERIC_FIXED
    (void)frac;
    return (int64_t)x >= (int64_t)lo - 4 && (int64_t)x <= (int64_t)hi + 4;
#else
    (void)frac;
    if (!isfinite(x)) {
        return 0;
    }
    const float tol = 1e-5f * (fabsf(lo) > fabsf(hi) ? fabsf(lo) : fabsf(hi)) + 1e-30f;
    return x >= lo - tol && x <= hi + tol;
#endif
}

#define FUZZ_WITHIN(x, lo, hi, KIND)                                                          \
    do {                                                                                      \
        if (!fuzz_within((x), (lo), (hi), FC_FRAC(KIND))) {                                   \
            fprintf(stderr, "bounds [%.9g, %.9g]\n", (double)FUZZ_F((lo), KIND),              \
                    (double)FUZZ_F((hi), KIND));                                              \
            fuzz_fail(#x " out of [" #lo ", " #hi "]", FUZZ_F((x), KIND), __FILE__, __LINE__); \
        }                                                                                     \
    } while (0)

/* |x| <= lim */
#define FUZZ_ABS_LE(x, lim, KIND) FUZZ_WITHIN((x), -(lim), (lim), KIND)

#define FUZZ_CHECK(cond)                                                  \
    do {                                                                  \
        if (!(cond)) {                                                    \
            fuzz_fail(#cond, 0.0f, __FILE__, __LINE__);                   \
        }                                                                 \
    } while (0)

/* A unit quaternion within 1e-3 on |q|^2 (both backends, checked in float). */
#define FUZZ_UNIT_QUAT(q)                                                                       \
    do {                                                                                        \
        const float fw_ = FUZZ_F((q).w, UNIT), fx_ = FUZZ_F((q).x, UNIT);                       \
        const float fy_ = FUZZ_F((q).y, UNIT), fz_ = FUZZ_F((q).z, UNIT);                       \
        const float n2_ = fw_ * fw_ + fx_ * fx_ + fy_ * fy_ + fz_ * fz_;                        \
        if (!isfinite(n2_) || fabsf(n2_ - 1.0f) > 1e-3f) {                                      \
            fuzz_fail(#q " is not a unit quaternion (|q|^2 shown)", n2_, __FILE__, __LINE__);   \
        }                                                                                       \
    } while (0)

#endif /* FC_FUZZ_COMMON_H */

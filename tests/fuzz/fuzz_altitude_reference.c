/*
 * fuzz_altitude_reference: fc_altitude_reference_step on raw
 * fc_vertical_trajectory bit patterns (the pad's height and derivatives).
 * Byte 0: bit 0 picks dt (500 Hz or 100 Hz); built with -DFUZZ_RESTART=1,
 * bit 1 also restarts the offset with the raw bits of the next 4 bytes
 * (fc_altitude_reference_restart is not a _step: off in CI, see README.md,
 * finding altitude_reference-restart-1). Parameters: the controller's
 * (the 4.4 reference: tau 0.1 s, offset 1 m, bias 0.18 m). Then up to
 * FUZZ_MAX_STEPS pad samples, then FUZZ_CLEAN_STEPS at zero.
 * Checks: z_r, z_r', z_r'' finite.
 */
#include "fc/controller.h"
#include "fuzz_common.h"

static void check(const fc_vertical_trajectory *r)
{
    FUZZ_FINITE(r->z_m, LENGTH);
    FUZZ_FINITE(r->vz_mps, VEL);
    FUZZ_FINITE(r->az_mps2, ACCEL);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_bytes b = {data, size};
    const uint8_t cfg = fuzz_byte(&b);
    static fc_controller_params cp;
    fc_controller_default_params(&cp, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC,
                                 (cfg & 1u) ? FC_C(0.01f, DT) : FC_C(0.002f, DT));
    fc_altitude_reference ref;
    FUZZ_CHECK(fc_altitude_reference_init(&ref, &cp.reference) == FC_INIT_OK);
#if defined(FUZZ_RESTART) && FUZZ_RESTART
    if (cfg & 2u) {
        fc_real offset;
        (void)fuzz_take(&b, &offset, sizeof offset);
        fc_altitude_reference_restart(&ref, offset);
    }
#endif
    fc_vertical_trajectory zero;
    memset(&zero, 0, sizeof zero);
    fc_vertical_trajectory pad, out;
    for (int k = 0; k < FUZZ_MAX_STEPS && fuzz_take(&b, &pad, sizeof pad); k++) {
        (void)fc_altitude_reference_step(&ref, &pad, &out);
        check(&out);
    }
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        (void)fc_altitude_reference_step(&ref, &zero, &out);
        check(&out);
    }
    return 0;
}

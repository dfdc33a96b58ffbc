/*
 * fuzz_altitude_control: fc_altitude_control_step on raw
 * fc_altitude_control_input bit patterns (height, speed, reference, tilt
 * cosine, saturation bits). Byte 0 picks the airframe (bits 0-1, for the mass
 * and the thrust range), byte 1 the law variant (modulo the 12 variants):
 * the controller's default parameters for them. Then up to FUZZ_MAX_STEPS
 * inputs, then FUZZ_CLEAN_STEPS at hover on the reference.
 * Checks: thrust in [thrust_min, thrust_max], every other output finite.
 */
#include "fc/controller.h"
#include "fuzz_common.h"

static void check(const fc_altitude_control_params *p, const fc_altitude_control_output *out)
{
    FUZZ_WITHIN(out->thrust_n, p->thrust_min_n, p->thrust_max_n, FORCE);
    FUZZ_FINITE(out->vertical_force_n, FORCE);
    FUZZ_FINITE(out->error_m, LENGTH);
    FUZZ_FINITE(out->sigma_mps, VEL);
    FUZZ_FINITE(out->sigma_tilde_mps, VEL);
    FUZZ_FINITE(out->rho_n, FORCE);
    FUZZ_FINITE(out->u0_av_n, FORCE);
    FUZZ_FINITE(out->u_nom_n, FORCE);
    FUZZ_FINITE(out->theta_kg, MASS);
    FUZZ_FINITE(out->observer_bound_n, FORCE);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_bytes b = {data, size};
    const uint8_t cfg = fuzz_byte(&b);
    const uint8_t variant = fuzz_byte(&b);
    static fc_controller_params cp;
    fc_controller_default_params(&cp, (fc_airframe)((cfg & 3u) % FC_AIRFRAME_COUNT),
                                 (fc_altitude_variant)(variant % FC_ALT_VARIANT_COUNT), FC_C(0.002f, DT));
    static fc_altitude_control c;
    FUZZ_CHECK(fc_altitude_control_init(&c, &cp.altitude) == FC_INIT_OK);

    fc_altitude_control_input hover;
    memset(&hover, 0, sizeof hover);
    hover.z_m = FC_C(1.0f, LENGTH);
    hover.reference.z_m = FC_C(1.0f, LENGTH);
    hover.tilt_cos = FC_C(1.0f, RATIO);
    fc_altitude_control_output out;
    fc_altitude_control_input in;
    for (int k = 0; k < FUZZ_MAX_STEPS && fuzz_take(&b, &in, sizeof in); k++) {
        (void)fc_altitude_control_step(&c, &in, &out);
        check(&cp.altitude, &out);
    }
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        (void)fc_altitude_control_step(&c, &hover, &out);
        check(&cp.altitude, &out);
    }
    return 0;
}

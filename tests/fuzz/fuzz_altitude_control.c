/*
 * fuzz_altitude_control: fc_altitude_control_step on raw bit patterns of its
 * input's values (altitude_values: height, speed, reference, tilt cosine,
 * saturation bits). Byte 0 picks the airframe (bits 0-1, for the mass
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

/* The values of fc_altitude_control_input, the reference among them (the
 * input points to it), in the order the fuzz bytes give them. */
typedef struct altitude_values {
    fc_real z_m;
    fc_real vz_mps;
    fc_vertical_trajectory reference;
    fc_real tilt_cos;
    uint8_t allocation_saturation;
} altitude_values;

static fc_step_status step(fc_altitude_control *c, const altitude_values *v, fc_altitude_control_output *out)
{
    const fc_altitude_control_input in = {v->z_m, v->vz_mps, &v->reference, v->tilt_cos, v->allocation_saturation};
    return fc_altitude_control_step(c, &in, out);
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

    altitude_values hover;
    memset(&hover, 0, sizeof hover);
    hover.z_m = FC_C(1.0f, LENGTH);
    hover.reference.z_m = FC_C(1.0f, LENGTH);
    hover.tilt_cos = FC_C(1.0f, RATIO);
    fc_altitude_control_output out;
    altitude_values in;
    for (int k = 0; k < FUZZ_MAX_STEPS && fuzz_take(&b, &in, sizeof in); k++) {
        (void)step(&c, &in, &out);
        check(&cp.altitude, &out);
    }
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        (void)step(&c, &hover, &out);
        check(&cp.altitude, &out);
    }
    return 0;
}

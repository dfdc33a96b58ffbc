/*
 * fuzz_controller: fc_controller_step, the whole controller, on raw
 * fc_controller_inputs bit patterns (IMU, external attitude, position,
 * velocity, pad trajectory, setpoints, and any command value). Byte 0: bits
 * 0-1 the airframe, bit 2 use_external_attitude, bit 3 a 100 Hz step instead
 * of 500 Hz; byte 1 the altitude-law variant (modulo 12): the parameters are
 * fc_controller_default_params for them. Then up to FUZZ_MAX_STEPS inputs,
 * then FUZZ_CLEAN_STEPS hovering ones.
 * Checks (fuzz_controller_check.h): rotor speeds in [0, 1] and >= u_min when
 * the motors run, 0 above the rotor count; thrust in [thrust_min,
 * thrust_max]; moments inside +-moment_limit; the telemetry's quaternions of
 * unit length and everything else finite.
 */
#include "fuzz_controller_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_bytes b = {data, size};
    const uint8_t cfg = fuzz_byte(&b);
    const uint8_t variant = fuzz_byte(&b);
    static fc_controller_params p;
    fc_controller_default_params(&p, (fc_airframe)((cfg & 3u) % FC_AIRFRAME_COUNT),
                                 (fc_altitude_variant)(variant % FC_ALT_VARIANT_COUNT),
                                 (cfg & 8u) ? FC_C(0.01f, DT) : FC_C(0.002f, DT));
    p.use_external_attitude = (cfg & 4u) != 0;
    static fc_controller ctl;
    FUZZ_CHECK(fc_controller_init(&ctl, &p) == FC_INIT_OK);

    fc_controller_inputs hover;
    fuzz_controller_hover_inputs(&p, &hover);
    static fc_controller_outputs out;
    fc_controller_inputs in;
    for (int k = 0; k < FUZZ_MAX_STEPS && fuzz_take(&b, &in, sizeof in); k++) {
        fuzz_controller_bools(&in);
        (void)fc_controller_step(&ctl, &in, &out);
        fuzz_check_controller(&p, &out);
    }
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        (void)fc_controller_step(&ctl, &hover, &out);
        fuzz_check_controller(&p, &out);
    }
    return 0;
}

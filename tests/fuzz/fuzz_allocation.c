/*
 * fuzz_allocation: fc_allocation_step on raw fc_allocation_demand bit
 * patterns. The demand is normalised (NORM16, fc/allocation.h): in fixed four
 * int16 values, every pattern a demand in [-2, 2) of F_max and the moment
 * authorities (-32768 included, one below the symmetric range); in float four
 * floats, NaN, infinities and any magnitude included. Byte 0 picks the preset
 * (Crazyflie 2, F450, 4 kg hexa); bit 2 of it makes every rotor r != s
 * (torque exponent 2.3: the iterated correction). Then up to FUZZ_MAX_STEPS
 * demands, then FUZZ_CLEAN_STEPS zero demands.
 * Checks: speed[i] in [u_min,i, 1] for i < n and 0 above, rotor thrusts in
 * [0, T_max,i], achieved thrust and moments (physical: N, N m) finite, and
 * no arithmetic saturation: the step's 16-bit formats hold every NORM16
 * demand of these quad-X and hexa-X geometries (fc/allocation.h, Formats).
 */
#include "fc/allocation.h"
#include "fuzz_common.h"

static void check(const fc_allocation_params *p, const fc_allocation_output *out, fc_step_status status)
{
    FUZZ_CHECK((status & FC_STEP_ARITH_SATURATED) == 0u);
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        if (i < p->rotor_count) {
            FUZZ_WITHIN(out->speed[i], p->rotor[i].speed_min, FC_C(1.0f, UNIT), UNIT);
            FUZZ_WITHIN(out->rotor_thrust_n[i], FC_C(0.0f, FORCE), p->rotor[i].thrust_max_n, FORCE);
        } else {
            FUZZ_CHECK(out->speed[i] == 0);
            FUZZ_CHECK(out->rotor_thrust_n[i] == 0);
        }
    }
    FUZZ_FINITE(out->thrust_n, FORCE);
    FUZZ_FINITE_VEC3(out->moment_nm, MOMENT);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_bytes b = {data, size};
    const uint8_t cfg = fuzz_byte(&b);
    fc_allocation_params p;
    switch (cfg & 3u) {
    case 0: fc_allocation_preset_crazyflie2(&p); break;
    case 1: fc_allocation_preset_f450(&p); break;
    default: fc_allocation_preset_hexa_x_4kg(&p); break; /* 2 and 3 */
    }
    if (cfg & 4u) {
        for (int i = 0; i < p.rotor_count; i++) {
            p.rotor[i].torque_exponent = FC_C(2.3f, RATIO);
        }
    }
    /* init (a pseudo-inverse) once per configuration; each input starts from a copy */
    static fc_allocation initialised[8];
    static uint8_t done[8];
    const unsigned which = cfg & 7u;
    if (!done[which]) {
        FUZZ_CHECK(fc_allocation_init(&initialised[which], &p) == FC_INIT_OK);
        done[which] = 1;
    }
    static fc_allocation a;
    a = initialised[which];

    fc_allocation_demand zero;
    memset(&zero, 0, sizeof zero);
    fc_allocation_output out;
    fc_allocation_demand d;
    for (int k = 0; k < FUZZ_MAX_STEPS && fuzz_take(&b, &d, sizeof d); k++) {
        const fc_step_status status = fc_allocation_step(&a, &d, &out);
        check(&p, &out, status);
    }
    for (int k = 0; k < FUZZ_CLEAN_STEPS; k++) {
        const fc_step_status status = fc_allocation_step(&a, &zero, &out);
        check(&p, &out, status);
    }
    return 0;
}

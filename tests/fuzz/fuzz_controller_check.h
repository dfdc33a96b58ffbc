/*
 * tests/fuzz/fuzz_controller_check.h - the checks of fc_controller_step's
 * outputs against the limits in the parameters it was initialised with
 * (shared by fuzz_controller and fuzz_params).
 */
#ifndef FC_FUZZ_CONTROLLER_CHECK_H
#define FC_FUZZ_CONTROLLER_CHECK_H

#include "fc/controller.h"
#include "fuzz_common.h"

/* The bound of a moment in N m: its normalised limit (RATIO) times the
 * authority (MOMENT), plus one NORM16 LSB of the authority for the rounding
 * of the normalised moment. */
static inline fc_real fuzz_moment_bound_nm(fc_real limit, fc_real authority_nm)
{
    fc_arith ar = {0u};
    const fc_real bound = fc_add(&ar, limit, FC_C(1.0f / 16384.0f, RATIO));
    return fc_mul(&ar, bound, authority_nm, FC_SHIFT(RATIO, MOMENT, MOMENT));
}

static inline void fuzz_check_controller(const fc_controller_params *p, const fc_controller_outputs *out)
{
    FUZZ_CHECK(out->rotor_count <= FC_MAX_ROTORS);
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        if (i < out->rotor_count) {
            FUZZ_WITHIN(out->rotor_speed[i], FC_C(0.0f, UNIT), FC_C(1.0f, UNIT), UNIT);
            if (out->motors_on) {
                FUZZ_WITHIN(out->rotor_speed[i], p->allocation.rotor[i].speed_min, FC_C(1.0f, UNIT), UNIT);
            }
        } else {
            FUZZ_CHECK(out->rotor_speed[i] == 0);
        }
    }
    if (out->motors_on) {
        FUZZ_CHECK(out->rotor_count == p->allocation.rotor_count);
        FUZZ_WITHIN(out->thrust_n, p->altitude.thrust_min_n, p->altitude.thrust_max_n, FORCE);
    } else {
        FUZZ_WITHIN(out->thrust_n, p->altitude.thrust_min_n < 0 ? p->altitude.thrust_min_n : 0,
                    p->altitude.thrust_max_n, FORCE);
    }
    FUZZ_FINITE_VEC3(out->moment_nm, MOMENT);
    /* the normalised budget times the authority (the attitude law's own, which
     * init checked is the allocation's) */
    FUZZ_ABS_LE(out->moment_nm.x, fuzz_moment_bound_nm(p->attitude.moment_limit.x, p->attitude.authority_nm.x), MOMENT);
    FUZZ_ABS_LE(out->moment_nm.y, fuzz_moment_bound_nm(p->attitude.moment_limit.y, p->attitude.authority_nm.y), MOMENT);
    FUZZ_ABS_LE(out->moment_nm.z, fuzz_moment_bound_nm(p->attitude.moment_limit.z, p->attitude.authority_nm.z), MOMENT);

    const fc_controller_telemetry *t = &out->telemetry;
    FUZZ_UNIT_QUAT(t->attitude);
    FUZZ_UNIT_QUAT(t->attitude_setpoint);
    FUZZ_FINITE_VEC3(t->rate_radps, RATE);
    FUZZ_FINITE(t->reference.z_m, LENGTH);
    FUZZ_FINITE(t->reference.vz_mps, VEL);
    FUZZ_FINITE(t->reference.az_mps2, ACCEL);
    FUZZ_FINITE(t->altitude.thrust_n, FORCE);
    FUZZ_FINITE(t->altitude.vertical_force_n, FORCE);
    FUZZ_FINITE(t->altitude.error_m, LENGTH);
    FUZZ_FINITE(t->altitude.sigma_mps, VEL);
    FUZZ_FINITE(t->altitude.sigma_tilde_mps, VEL);
    FUZZ_FINITE(t->altitude.rho_n, FORCE);
    FUZZ_FINITE(t->altitude.u0_av_n, FORCE);
    FUZZ_FINITE(t->altitude.u_nom_n, FORCE);
    FUZZ_FINITE(t->altitude.theta_kg, MASS);
    FUZZ_FINITE(t->altitude.observer_bound_n, FORCE);
    /* cos(roll) cos(pitch), computed from the quaternion: a few LSB past +-1 is rounding */
    FUZZ_WITHIN(t->tilt_cos, FC_C(-1.001f, RATIO), FC_C(1.001f, RATIO), RATIO);
}

/* Hovering level at 1 m over a still pad at 0, tracking it. */
static inline void fuzz_controller_hover_inputs(const fc_controller_params *p, fc_controller_inputs *in)
{
    memset(in, 0, sizeof *in);
    in->imu.accel_mps2.z = p->gravity_mps2;
    in->attitude_external.w = FC_C(1.0f, UNIT);
    in->position_m.z = FC_C(1.0f, LENGTH);
    in->command = FC_COMMAND_TRACK_PAD;
}

/* A bool holds 0 or 1; raw bytes laid over one are reduced to their low bit
 * (another bit pattern is not a value of the type, as for the params). */
static inline void fuzz_controller_bools(fc_controller_inputs *in)
{
    unsigned char raw;
    memcpy(&raw, &in->range_fresh, 1);
    in->range_fresh = (raw & 1u) != 0u;
    memcpy(&raw, &in->heading_fresh, 1);
    in->heading_fresh = (raw & 1u) != 0u;
}

#endif /* FC_FUZZ_CONTROLLER_CHECK_H */

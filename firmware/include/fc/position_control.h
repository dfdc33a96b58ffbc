/*
 * fc/position_control.h - horizontal position control and acceleration
 * control, dissertation 2.6.2 and 2.6.4 (Figures 2.8, 2.9).
 *
 * Position (2.6.4), horizontal (x, y of the world ENU frame):
 *   e   = sat(p_sp - p)            the error vector saturated by its length,
 *                                  keeping its direction (fc_vec3_clamp_norm)
 *   a_h = k_P e + k_D (v_sp - v) + I + a_ff,h,  |a_h| <= accel_max (direction kept)
 *   I  += k_I dt e,  |I| <= integral_max, and only while a_h is not limited
 *         (by accel_max, the tilt limit or the thrust limit) or the error
 *         drives the output back out of the limit (e . a_h,unsat < 0)
 *
 * Acceleration (2.6.2), with a_des = (a_h, a_ff,z) and g = (0, 0, -g0):
 *   F_req = m (a_des - g - I_a)                                       (2.11)
 *   I_a  += k_a dt (a_meas - a_des),  |I_a| <= accel_fb_max           (Figure 2.8)
 *         the acceleration feedback: a low-gain integral of the measured
 *         minus the wanted acceleration, correcting mass errors and
 *         aerodynamic differences; frozen while the thrust is limited.
 *   F_req,z >= thrust_min; |F_req,h| <= F_req,z tan(tilt_max) (direction kept);
 *   |F_req| <= thrust_max (direction kept).
 *
 * Attitude setpoint from the thrust direction b3 = F/|F| and a heading given as
 * the unit vector (cos psi, sin psi) (no trigonometry per step):
 *   q_tilt ~ [1 + b3_z, -b3_y, b3_x, 0]  the shortest rotation taking world z to b3
 *   q_yaw  ~ [1 + cos psi, 0, 0, sin psi]  (psi in the left half plane:
 *            [sin psi, 0, 0, 1 - cos psi], the same rotation without the
 *            cancellation near psi = pi)
 *   q_sp = normalise(q_tilt (x) q_yaw), w >= 0   (body -> world)
 * Its body z axis is b3 exactly (q_yaw keeps z); its body x axis is the heading
 * when level and tilts with the thrust. Collective thrust along body z = |F|.
 * A step is two halves that a caller may run in different steps of its own
 * (fc/controller.h runs them in two minor frames): the demand (the errors,
 * the PID, F_req and its limits, both integrators) and the attitude (b3,
 * the heading, q_sp and |F_req|), which reads only the demand's F_req.
 * Cost per step: the direction of F in UNIT16 and its length (one
 * reciprocal root, fc_vec3_direction16), q_tilt (x) q_yaw in 16-bit products, one
 * reciprocal root for |q| = |q_tilt| |q_yaw|. The horizontal law is 2-D
 * (x, y); a saturation forms its norm only when the 1-norm |x| + |y| (+ |z|)
 * exceeds the limit (fc_norm1_within), which it seldom does.
 */
#ifndef FC_POSITION_CONTROL_H
#define FC_POSITION_CONTROL_H

#include "fc/quat.h"
#include "fc/status.h"

typedef struct fc_position_control_params {
    fc_real dt_s;                 /* DT: the fixed step, (0, 0.1] */
    fc_real kp_per_s2;            /* RATIO: k_P, [0, 100] (m/s2)/m */
    fc_real ki_per_s3;            /* RATIO: k_I, [0, 100] (m/s2)/(m s) */
    fc_real kd_per_s;             /* RATIO: k_D, [0, 100] (m/s2)/(m/s) */
    fc_real error_max_m;          /* LENGTH: saturation of |e|, (0, 100] */
    fc_real integral_max_mps2;    /* ACCEL: |I| limit, [0, 50] */
    fc_real accel_max_mps2;       /* ACCEL: |a_h| limit, (0, 50] */
    fc_real mass_kg;              /* MASS: m of (2.11), (0, 100] */
    fc_real accel_fb_gain_per_s;  /* RATIO: k_a of the acceleration feedback, [0, 10] */
    fc_real accel_fb_max_mps2;    /* ACCEL: |I_a| limit, [0, 20] */
    fc_real tilt_max_rad;         /* ANGLE: largest tilt of the thrust from vertical, (0, 1.4] */
    fc_real thrust_min_n;         /* FORCE: floor of the vertical thrust component, > 0 */
    fc_real thrust_max_n;         /* FORCE: collective thrust limit, > thrust_min, <= 1000 */
} fc_position_control_params;

/* The demand's input, by reference: the caller holds the vectors (the
 * controller: its estimate, setpoint and measurement), the demand reads
 * them in place instead of copying them. The pointers must be
 * valid (non-NULL, each to one fc_vec3) for the call only: the demand reads
 * them during the call and keeps none of them. They may point to the same
 * vector (a zero shared by the setpoint speed and the feedforward), not into
 * the output (written before the last of them is read). World ENU frame,
 * z up. Not finite: see fc_position_control_step. */
typedef struct fc_position_control_input {
    const fc_vec3 *position_m;      /* LENGTH: p (z unused by the position law) */
    const fc_vec3 *velocity_mps;    /* VEL: v (z unused) */
    const fc_vec3 *position_sp_m;   /* LENGTH: p_sp (z unused) */
    const fc_vec3 *velocity_sp_mps; /* VEL: v_sp, the feedforward of the D term; zero to regulate */
    const fc_vec3 *accel_ff_mps2;   /* ACCEL: a_ff; z is the wanted vertical acceleration */
    const fc_vec3 *accel_meas_mps2; /* ACCEL: measured kinematic acceleration a (gravity removed) */
    bool accel_meas_ok;             /* false: no measurement this step, the feedback I_a is held */
} fc_position_control_input;

typedef struct fc_position_control_output {
    fc_vec3 accel_des_mps2;    /* ACCEL: a_des (after the horizontal limit) */
    fc_vec3 thrust_world_n;    /* FORCE: F_req after the limits, world */
    fc_quat attitude_sp;       /* UNIT: attitude setpoint, body -> world */
    fc_real thrust_n;          /* FORCE: collective thrust along body z, |F_req| */
} fc_position_control_output;

/* The law's constants as fc_gain (fc/scalar.h): a 32 x 16-bit product each.
 * Their 15 significant bits hold every one within 2^-15 of itself, far
 * inside the tolerance any of them is tuned or measured to (a mass known to
 * 3e-5 of itself, a gain to 3e-5), and the signals they multiply keep their
 * 32-bit formats. */
typedef struct fc_position_control {
    fc_position_control_params p;
    fc_gain kp;                /* k_P, (m/s2)/m */
    fc_gain kd;                /* k_D, (m/s2)/(m/s) */
    fc_gain ki_dt;             /* k_I dt, (m/s2)/m */
    fc_gain fb_dt;             /* k_a dt, dimensionless */
    fc_gain mass;              /* m, kg */
    fc_gain tan_tilt_max;      /* tan(tilt_max), <= 5.8 */
    fc_vec3 integral_mps2;     /* ACCEL: I (x, y; z = 0) */
    fc_vec3 accel_fb_mps2;     /* ACCEL: I_a */
    bool ready;
    fc_arith ar;
} fc_position_control;

fc_init_result fc_position_control_init(fc_position_control *pc, const fc_position_control_params *p);

/* Clears both integrators. */
void fc_position_control_reset(fc_position_control *pc);

/* One whole step: fc_position_control_demand, then fc_position_control_attitude
 * at the heading (heading_cos, heading_sin) = (cos psi, sin psi) (UNIT; only
 * the direction matters, |(c, s)| in [0.5, 1.5]).
 * Bad input: a non-finite position, velocity or setpoint gives a zero error
 * (no integration); a non-finite feedforward is taken as zero; a non-finite
 * measured acceleration freezes the acceleration feedback (as accel_meas_ok
 * false does, without BAD_INPUT: a missing sample is no bad input); a bad heading is
 * taken as psi = 0. Not ready: identity attitude, zero thrust. */
fc_step_status fc_position_control_step(fc_position_control *pc, const fc_position_control_input *in,
                                        fc_real heading_cos, fc_real heading_sin, fc_position_control_output *out);

/* The demand half of a step: out->accel_des_mps2 and out->thrust_world_n
 * (F_req after the limits), the integrators updated; the status bits of the
 * position, velocity, feedforward and measurement (as fc_position_control_step).
 * out->attitude_sp and out->thrust_n are left as they were. */
fc_step_status fc_position_control_demand(fc_position_control *pc, const fc_position_control_input *in,
                                          fc_position_control_output *out);

/* The attitude half: out->attitude_sp and out->thrust_n of out->thrust_world_n
 * (a demand's F_req, F_z > 0) at the heading (cos psi, sin psi) (a bad
 * heading: psi = 0, FC_STEP_BAD_INPUT). The law's state is not read or
 * changed, so a demand's F_req may wait for it. */
fc_step_status fc_position_control_attitude(fc_position_control *pc, fc_real heading_cos, fc_real heading_sin,
                                            fc_position_control_output *out);

#endif /* FC_POSITION_CONTROL_H */

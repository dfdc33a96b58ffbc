/* plant.c - the rigid-body multirotor, rotors, ground effect, pad and contact (plant.h). */
#include "plant.h"

#include <math.h>
#include <string.h>

void pad_eval(const pad_params *p, double t_s, pad_state *out)
{
    /* the fault's clock: t' = t0 + k (t - t0), so z'(t) = k dz/dt', z'' = k^2 d2z/dt'2 */
    const bool warped = p->warp_factor > 0.0 && t_s > p->warp_start_s;
    const double warp = warped ? p->warp_factor : 1.0;
    const double t = warped ? p->warp_start_s + warp * (t_s - p->warp_start_s) : t_s;
    out->z_m = p->base_m;
    out->vz_mps = 0.0;
    out->az_mps2 = 0.0;
    out->roll_rad = out->pitch_rad = out->roll_rate_radps = out->pitch_rate_radps = 0.0;
    if (pad_tilts(p)) {
        /* the deck's roll and pitch on the same (warped) clock as its heave */
        const double roll_phase = p->roll_omega_radps * t + p->roll_phase_rad;
        const double pitch_phase = p->pitch_omega_radps * t + p->pitch_phase_rad;
        out->roll_rad = p->roll_amplitude_rad * sin(roll_phase);
        out->pitch_rad = p->pitch_amplitude_rad * sin(pitch_phase);
        out->roll_rate_radps = warp * p->roll_amplitude_rad * p->roll_omega_radps * cos(roll_phase);
        out->pitch_rate_radps = warp * p->pitch_amplitude_rad * p->pitch_omega_radps * cos(pitch_phase);
    }
    switch (p->model) {
    case PAD_SINE: {
        /* (3.1): z_d = A/2 sin(w t) + A/2 */
        const double half = 0.5 * p->amplitude_m, w = p->omega_radps;
        const double s = sin(w * t), c = cos(w * t);
        out->z_m += half * s + half;
        out->vz_mps = half * w * c;
        out->az_mps2 = -half * w * w * s;
        break;
    }
    case PAD_WAVES:
        for (int k = 0; k < p->wave_count; k++) {
            const double a = p->wave_amplitude_m[k], w = p->wave_omega_radps[k];
            const double phase = w * t + p->wave_phase_rad[k];
            const double s = sin(phase), c = cos(phase);
            out->z_m += a * s;
            out->vz_mps += a * w * c;
            out->az_mps2 -= a * w * w * s;
        }
        break;
    case PAD_STILL:
    default:
        break;
    }
    out->vz_mps *= warp;
    out->az_mps2 *= warp * warp;
    if (p->growth_scale > 0.0 && t_s > p->growth_start_s) {
        /* the heave grows linearly to growth_scale over growth_duration_s (a fault; the
         * growth's own rate is left out of z' and z'') */
        const double ramp = fmin(1.0, (t_s - p->growth_start_s) / fmax(p->growth_duration_s, 1e-9));
        const double factor = 1.0 + (p->growth_scale - 1.0) * ramp;
        out->z_m = p->base_m + factor * (out->z_m - p->base_m);
        out->vz_mps *= factor;
        out->az_mps2 *= factor;
    }
}

bool pad_tilts(const pad_params *p)
{
    return p->roll_amplitude_rad > 0.0 || p->pitch_amplitude_rad > 0.0;
}

quat pad_attitude(const pad_state *pad)
{
    return quat_from_rpy(pad->roll_rad, pad->pitch_rad, 0.0);
}

v3 pad_normal(const pad_state *pad)
{
    /* R_y(pitch) R_x(roll) e_z */
    const double cr = cos(pad->roll_rad), sr = sin(pad->roll_rad);
    const double cp = cos(pad->pitch_rad), sp = sin(pad->pitch_rad);
    return v3_make(cr * sp, -sr, cr * cp);
}

v3 pad_angular_velocity(const pad_state *pad)
{
    /* pitch' e_y + R_y(pitch) roll' e_x */
    return v3_make(pad->roll_rate_radps * cos(pad->pitch_rad), pad->pitch_rate_radps,
                   -pad->roll_rate_radps * sin(pad->pitch_rad));
}

double pad_height_of(const pad_state *pad, v3 x)
{
    return v3_dot(v3_make(x.x, x.y, x.z - pad->z_m), pad_normal(pad));
}

double plant_ground_gain(double radius_m, double rho, double height_m)
{
    const double ratio = radius_m / (4.0 * height_m);
    return 1.0 / (1.0 - rho * ratio * ratio);
}

double plant_rotor_height_min(const plant_params *p, int i)
{
    return p->gear_height_m + p->rotor[i].position_m.z;
}

double plant_mass_target(const plant_params *p, double t)
{
    double mu = p->mass_kg;
    for (int k = 0; k < p->mass_step_count; k++) {
        if (t >= p->mass_step_time_s[k]) {
            mu = p->mass_step_kg[k];
        }
    }
    return mu;
}

v3 plant_inertia(const plant_params *p, double m)
{
    return v3_axpy(p->inertia_kgm2, m - p->mass_kg, p->inertia_per_kg);
}

const char *plant_params_check(const plant_params *p)
{
    if (!(p->mass_kg > 0.0) || !(p->gravity_mps2 > 0.0)) {
        return "mass and gravity must be positive";
    }
    if (!(p->inertia_kgm2.x > 0.0 && p->inertia_kgm2.y > 0.0 && p->inertia_kgm2.z > 0.0)) {
        return "inertia must be positive";
    }
    if (p->velocity_input &&
        !(p->velocity_k_p_per_s.x > 0.0 && p->velocity_k_p_per_s.y > 0.0 && p->velocity_k_p_per_s.z > 0.0 &&
          p->velocity_a_p_per_s.x >= 0.0 && p->velocity_a_p_per_s.y >= 0.0 && p->velocity_a_p_per_s.z >= 0.0 &&
          p->velocity_thrust_max_n > p->mass_kg * p->gravity_mps2 && p->velocity_tilt_max_rad > 0.0 &&
          p->velocity_tilt_max_rad < 1.5)) {
        return "velocity input: k_P > 0, a_P >= 0, thrust above the weight, a tilt limit in (0, 1.5) rad";
    }
    if (p->rotor_count < 1 || p->rotor_count > PLANT_MAX_ROTORS) {
        return "rotor count out of range";
    }
    if (!(p->mass_tau_s > 0.0)) {
        return "mass filter time constant must be positive";
    }
    for (int k = 0; k < p->mass_step_count; k++) {
        if (!(p->mass_step_kg[k] > 0.0)) {
            return "step masses must be positive";
        }
        const v3 inertia = plant_inertia(p, p->mass_step_kg[k]);
        if (!(inertia.x > 0.0 && inertia.y > 0.0 && inertia.z > 0.0)) {
            return "inertia after a mass step must stay positive";
        }
    }
    for (int i = 0; i < p->rotor_count; i++) {
        const plant_rotor *r = &p->rotor[i];
        if (fabs(v3_norm(r->axis) - 1.0) > 1e-6) {
            return "rotor axes must be unit vectors";
        }
        if (!(r->thrust_max_n > 0.0) || !(r->thrust_exponent > 0.0) || !(r->torque_exponent > 0.0) ||
            !(r->speed_min >= 0.0 && r->speed_min < 1.0) || !(r->tau_s >= 0.0) || !(r->efficiency >= 0.0)) {
            return "rotor parameters out of range";
        }
        if (p->ground_effect) {
            /* the floor of h keeps (3.2) finite: k_g_max at the gear touching */
            const double h_min = plant_rotor_height_min(p, i);
            const double h_sing = sqrt(p->ge_rho) * p->ge_radius_m / 4.0;
            if (!(h_min > 1.05 * h_sing)) {
                return "ground effect: the gear leaves the rotors below the singularity of (3.2)";
            }
        }
    }
    if (p->ground_effect && !(p->ge_radius_m > 0.0 && p->ge_rho >= 0.0)) {
        return "ground effect: radius must be positive and rho non-negative";
    }
    if (p->foot_count < 1 || p->foot_count > PLANT_MAX_FEET) {
        return "foot count out of range";
    }
    if (p->contact && !(p->contact_stiffness_n_per_m > 0.0 && p->contact_damping_ns_per_m >= 0.0 &&
                        p->friction >= 0.0 && p->slip_speed_mps > 0.0)) {
        return "contact parameters out of range";
    }
    return NULL;
}

/* u^e, with the common exponents exact and fast. */
static double upow(double u, double e)
{
    if (e == 2.0) {
        return u * u;
    }
    if (e == 1.0) {
        return u;
    }
    return pow(u, e);
}

/* Velocity input: the vehicle's own attitude loop, a PD on the error to the
 * thrust's direction at natural frequency VELOCITY_ATTITUDE_WN and damping
 * VELOCITY_ATTITUDE_ZETA (far faster than the translation); the contact's
 * moments act against it. */
#define VELOCITY_ATTITUDE_WN 20.0
#define VELOCITY_ATTITUDE_ZETA 0.8

/* Velocity input: the world thrust of the vehicle's own autopilot at state
 * s (plant.h): m (-a_P v + k_P u + g e_z) + c_d v, F_z in [0, T_max], the
 * tilt and then the norm limited. */
static v3 velocity_thrust_w(const plant *pl, const plant_state *s)
{
    const plant_params *p = &pl->p;
    if (!pl->velocity_motors_on) {
        return v3_make(0.0, 0.0, 0.0);
    }
    const v3 k = p->velocity_k_p_per_s, a = p->velocity_a_p_per_s, u = pl->velocity_cmd_mps;
    const v3 accel = v3_make(-a.x * s->v.x + k.x * u.x, -a.y * s->v.y + k.y * u.y,
                             -a.z * s->v.z + k.z * u.z + p->gravity_mps2);
    v3 f = v3_axpy(v3_scale(accel, s->m), p->drag_n_per_mps, s->v);
    f.z = fmin(fmax(f.z, 0.0), p->velocity_thrust_max_n);
    const double horizontal = hypot(f.x, f.y), horizontal_max = f.z * tan(p->velocity_tilt_max_rad);
    if (horizontal > horizontal_max) {
        const double k_h = horizontal_max / horizontal;
        f.x *= k_h;
        f.y *= k_h;
    }
    const double norm = v3_norm(f);
    return norm > p->velocity_thrust_max_n ? v3_scale(f, p->velocity_thrust_max_n / norm) : f;
}

/* The attitude whose body z is along f, at heading yaw (level at yaw when f is 0). */
static quat attitude_of_thrust(v3 f, double yaw)
{
    const double norm = v3_norm(f);
    const v3 b3 = norm > 1e-9 ? v3_scale(f, 1.0 / norm) : v3_make(0.0, 0.0, 1.0);
    const v3 c = v3_make(cos(yaw), sin(yaw), 0.0);
    v3 b2 = v3_cross(b3, c);
    const double n2 = v3_norm(b2);
    b2 = n2 > 1e-9 ? v3_scale(b2, 1.0 / n2) : v3_make(-sin(yaw), cos(yaw), 0.0);
    const v3 b1 = v3_cross(b2, b3);
    /* the rotation matrix [b1 b2 b3] as a quaternion (Shepperd) */
    const double m00 = b1.x, m11 = b2.y, m22 = b3.z, trace = m00 + m11 + m22;
    quat q;
    if (trace > 0.0) {
        const double t = 2.0 * sqrt(1.0 + trace);
        q = quat_make(0.25 * t, (b2.z - b3.y) / t, (b3.x - b1.z) / t, (b1.y - b2.x) / t);
    } else if (m00 > m11 && m00 > m22) {
        const double t = 2.0 * sqrt(1.0 + m00 - m11 - m22);
        q = quat_make((b2.z - b3.y) / t, 0.25 * t, (b2.x + b1.y) / t, (b3.x + b1.z) / t);
    } else if (m11 > m22) {
        const double t = 2.0 * sqrt(1.0 + m11 - m00 - m22);
        q = quat_make((b3.x - b1.z) / t, (b2.x + b1.y) / t, 0.25 * t, (b3.y + b2.z) / t);
    } else {
        const double t = 2.0 * sqrt(1.0 + m22 - m00 - m11);
        q = quat_make((b1.y - b2.x) / t, (b3.x + b1.z) / t, (b3.y + b2.z) / t, 0.25 * t);
    }
    return quat_normalize(q);
}

void plant_set_velocity_command(plant *pl, v3 velocity_mps, double yaw_rate_radps, bool motors_on)
{
    pl->velocity_cmd_mps = v3_make(isfinite(velocity_mps.x) ? velocity_mps.x : 0.0,
                                   isfinite(velocity_mps.y) ? velocity_mps.y : 0.0,
                                   isfinite(velocity_mps.z) ? velocity_mps.z : 0.0);
    pl->yaw_rate_cmd_radps = isfinite(yaw_rate_radps) ? yaw_rate_radps : 0.0;
    pl->velocity_motors_on = motors_on;
}

/* The model: derivative of s at time t with the held commands, and diagnostics. */
static void derivative(const plant *pl, const pad_state *pad_t, double mu, const plant_state *s, plant_state *ds,
                       plant_diag *diag)
{
    const plant_params *p = &pl->p;
    double r[3][3];
    quat_to_matrix(s->q, r);
    const pad_state pad = *pad_t;
    const bool tilting = pad_tilts(&p->pad);
    const v3 pad_n = tilting ? pad_normal(&pad) : v3_make(0.0, 0.0, 1.0);
    const v3 pad_rate = tilting ? pad_angular_velocity(&pad) : v3_make(0.0, 0.0, 0.0);

    /* rotors (velocity input: the autopilot's thrust along body z) */
    v3 force_b = v3_make(0.0, 0.0, 0.0), moment_b = v3_make(0.0, 0.0, 0.0);
    double gain_weighted = 0.0, thrust_sum = 0.0;
    v3 velocity_moment_b = v3_make(0.0, 0.0, 0.0);
    if (p->velocity_input) {
        /* along body z; the attitude loop turns body z towards the thrust's direction */
        const v3 thrust_w = velocity_thrust_w(pl, s);
        force_b = v3_make(0.0, 0.0, v3_norm(thrust_w));
        const quat target = attitude_of_thrust(thrust_w, pl->yaw_rad);
        quat e = quat_mul(quat_make(s->q.w, -s->q.x, -s->q.y, -s->q.z), target);
        if (e.w < 0.0) {
            e = quat_make(-e.w, -e.x, -e.y, -e.z);
        }
        const v3 inertia_now = plant_inertia(p, s->m);
        const v3 rate_ff = mat_apply_t(r, v3_make(0.0, 0.0, pl->yaw_rate_cmd_radps));
        const double wn = VELOCITY_ATTITUDE_WN, kd = 2.0 * VELOCITY_ATTITUDE_ZETA * VELOCITY_ATTITUDE_WN;
        const v3 accel = v3_sub(v3_scale(v3_make(e.x, e.y, e.z), 2.0 * wn * wn), v3_scale(v3_sub(s->w, rate_ff), kd));
        velocity_moment_b = v3_mul(inertia_now, accel);
    }
    for (int i = 0; i < p->rotor_count && !p->velocity_input; i++) {
        const plant_rotor *rot = &p->rotor[i];
        const double u = s->u[i] > 0.0 ? s->u[i] : 0.0;
        const double thrust = rot->efficiency * rot->thrust_max_n * upow(u, rot->thrust_exponent);
        const double torque = rot->efficiency * rot->torque_max_nm * upow(u, rot->torque_exponent);
        double kg = 1.0;
        if (p->ground_effect) {
            /* (3.2) as h^2 / (h^2 - rho (R/4)^2), h floored at the gear touching */
            double h = s->p.z + r[2][0] * rot->position_m.x + r[2][1] * rot->position_m.y +
                       r[2][2] * rot->position_m.z - pad.z_m;
            if (tilting) {
                h = pad_height_of(&pad, v3_add(s->p, mat_apply(r, rot->position_m)));
            }
            h = h > pl->height_min[i] ? h : pl->height_min[i];
            kg = h * h / (h * h - pl->ge_c);
        }
        const double t_i = kg * thrust;
        force_b = v3_axpy(force_b, t_i, rot->axis);
        moment_b = v3_axpy(v3_axpy(moment_b, t_i, pl->lever[i]), torque, rot->axis);
        gain_weighted += kg * thrust;
        thrust_sum += thrust;
        if (diag != NULL) {
            diag->rotor_thrust_n[i] = kg * thrust;
            diag->ground_gain_rotor[i] = kg;
        }
    }

    /* contact of the feet with the pad's plane */
    v3 contact_w = v3_make(0.0, 0.0, 0.0), contact_moment_w = v3_make(0.0, 0.0, 0.0);
    double clearance = (double)INFINITY;
    int in_contact = 0;
    for (int f = 0; f < p->foot_count && (p->contact || diag != NULL); f++) {
        const v3 arm_w = mat_apply(r, p->foot_m[f]);
        const double height = tilting ? pad_height_of(&pad, v3_add(s->p, arm_w)) : s->p.z + arm_w.z - pad.z_m;
        if (height < clearance) {
            clearance = height;
        }
        if (!p->contact || height >= 0.0) {
            continue;
        }
        in_contact++;
        const v3 v_foot = v3_add(s->v, mat_apply(r, v3_cross(s->w, p->foot_m[f])));
        if (tilting) {
            /* along the deck's normal, against the surface point's own motion */
            const v3 foot_w = v3_add(s->p, arm_w);
            const v3 surface_v = v3_add(v3_make(0.0, 0.0, pad.vz_mps),
                                        v3_cross(pad_rate, v3_make(foot_w.x, foot_w.y, foot_w.z - pad.z_m)));
            const v3 v_rel = v3_sub(v_foot, surface_v);
            const double v_n = v3_dot(v_rel, pad_n);
            double normal_force = -p->contact_stiffness_n_per_m * height - p->contact_damping_ns_per_m * v_n;
            normal_force = normal_force > 0.0 ? normal_force : 0.0;
            const v3 v_t = v3_axpy(v_rel, -v_n, pad_n);
            const double slip_t = sqrt(v3_dot(v_t, v_t) + p->slip_speed_mps * p->slip_speed_mps);
            const v3 fc = v3_axpy(v3_scale(pad_n, normal_force), -p->friction * normal_force / slip_t, v_t);
            contact_w = v3_add(contact_w, fc);
            contact_moment_w = v3_add(contact_moment_w, v3_cross(arm_w, fc));
            continue;
        }
        const double penetration_rate = pad.vz_mps - v_foot.z;
        double normal = -p->contact_stiffness_n_per_m * height + p->contact_damping_ns_per_m * penetration_rate;
        if (normal < 0.0) {
            normal = 0.0; /* a spring-damper that never pulls */
        }
        const double slip = sqrt(v_foot.x * v_foot.x + v_foot.y * v_foot.y + p->slip_speed_mps * p->slip_speed_mps);
        const double k = -p->friction * normal / slip;
        const v3 fc = v3_make(k * v_foot.x, k * v_foot.y, normal);
        contact_w = v3_add(contact_w, fc);
        contact_moment_w = v3_add(contact_moment_w, v3_cross(arm_w, fc));
    }

    const double m = s->m;
    const v3 force_w = v3_add(v3_add(mat_apply(r, force_b), contact_w), v3_scale(v3_sub(s->v, pl->wind_mps), -p->drag_n_per_mps));
    ds->p = s->v;
    ds->v = v3_make(force_w.x / m, force_w.y / m, force_w.z / m - p->gravity_mps2);
    /* q' = 1/2 q (x) [0, w] */
    const quat dq = quat_mul(s->q, quat_make(0.0, s->w.x, s->w.y, s->w.z));
    ds->q = quat_make(0.5 * dq.w, 0.5 * dq.x, 0.5 * dq.y, 0.5 * dq.z);
    const v3 inertia = plant_inertia(p, m);
    const v3 moment = v3_add(v3_add(v3_add(moment_b, mat_apply_t(r, contact_moment_w)), pl->disturbance_moment_b),
                             velocity_moment_b);
    const v3 gyro = v3_cross(s->w, v3_mul(inertia, s->w));
    ds->w = v3_make((moment.x - gyro.x) / inertia.x, (moment.y - gyro.y) / inertia.y, (moment.z - gyro.z) / inertia.z);

    ds->m = (mu - m) / p->mass_tau_s;
    for (int i = 0; i < PLANT_MAX_ROTORS; i++) {
        ds->u[i] = 0.0;
    }
    for (int i = 0; i < p->rotor_count; i++) {
        if (p->rotor[i].tau_s > 0.0) {
            ds->u[i] = (pl->u_cmd[i] - s->u[i]) / p->rotor[i].tau_s;
        }
    }
    if (diag != NULL) {
        diag->force_b = force_b;
        diag->moment_b = moment_b;
        diag->contact_force_w = contact_w;
        /* specific force: the non-gravitational acceleration, in the body frame */
        diag->specific_force_b = mat_apply_t(r, v3_scale(force_w, 1.0 / m));
        diag->ground_gain = thrust_sum > 0.0 ? gain_weighted / thrust_sum : 1.0;
        if (!p->ground_effect || p->velocity_input) {
            diag->ground_gain = 1.0;
        } else if (thrust_sum <= 0.0) {
            /* no thrust: the gain the rotors would see, averaged */
            double sum = 0.0;
            for (int i = 0; i < p->rotor_count; i++) {
                const double h = tilting ? pad_height_of(&pad, v3_add(s->p, mat_apply(r, p->rotor[i].position_m)))
                                         : s->p.z + v3_dot(v3_make(r[2][0], r[2][1], r[2][2]), p->rotor[i].position_m) - pad.z_m;
                const double h_min = plant_rotor_height_min(p, i);
                sum += plant_ground_gain(p->ge_radius_m, p->ge_rho, h > h_min ? h : h_min);
            }
            diag->ground_gain = sum / p->rotor_count;
        }
        diag->gear_clearance_m = clearance;
        diag->feet_in_contact = in_contact;
        diag->mass_target_kg = mu;
        diag->pad = pad;
    }
}

_Static_assert(sizeof(plant_state) == PLANT_STATE_DIM * sizeof(double), "plant_state must be a packed vector of doubles");

void plant_init(plant *pl, const plant_params *p, const plant_state *s0)
{
    pl->p = *p;
    pl->s = *s0;
    pl->s.q = quat_normalize(pl->s.q);
    pl->t = 0.0;
    pl->pad_cache_t = -1.0;
    pl->wind_mps = v3_make(0.0, 0.0, 0.0);
    pl->disturbance_moment_b = v3_make(0.0, 0.0, 0.0);
    for (int i = 0; i < p->rotor_count; i++) {
        pl->lever[i] = v3_cross(p->rotor[i].position_m, p->rotor[i].axis);
        pl->height_min[i] = plant_rotor_height_min(p, i);
    }
    const double quarter_r = p->ge_radius_m / 4.0;
    pl->ge_c = p->ge_rho * quarter_r * quarter_r;
    for (int i = 0; i < PLANT_MAX_ROTORS; i++) {
        pl->u_cmd[i] = pl->s.u[i];
    }
    /* velocity input: hovering, no command, at the initial heading */
    pl->velocity_cmd_mps = v3_make(0.0, 0.0, 0.0);
    pl->yaw_rate_cmd_radps = 0.0;
    pl->velocity_motors_on = true;
    double roll, pitch;
    quat_to_rpy(pl->s.q, &roll, &pitch, &pl->yaw_rad);
    if (p->velocity_input) {
        pl->s.q = attitude_of_thrust(velocity_thrust_w(pl, &pl->s), pl->yaw_rad);
        pl->s.w = v3_make(0.0, 0.0, 0.0);
    }
}

void plant_set_command(plant *pl, const double *u_cmd, int count)
{
    for (int i = 0; i < pl->p.rotor_count; i++) {
        double u = i < count ? u_cmd[i] : 0.0;
        if (!(u > 0.0)) {
            u = 0.0; /* motor off (and NaN: off) */
        } else {
            const double lo = pl->p.rotor[i].speed_min;
            u = u < lo ? lo : (u > 1.0 ? 1.0 : u);
        }
        pl->u_cmd[i] = u;
        if (pl->p.rotor[i].tau_s <= 0.0) {
            pl->s.u[i] = u; /* no lag: the speed is the command */
        }
    }
}

void plant_step(plant *pl, double h)
{
    /* classical RK4; the pad is evaluated at t, t + h/2 and t + h, and the
     * last is kept for the next step's start */
    const double t = pl->t;
    pad_state pad0, pad_mid, pad_end;
    if (pl->pad_cache_t == t) {
        pad0 = pl->pad_cache;
    } else {
        pad_eval(&pl->p.pad, t, &pad0);
    }
    pad_eval(&pl->p.pad, t + 0.5 * h, &pad_mid);
    pad_eval(&pl->p.pad, t + h, &pad_end);
    /* the mass target mu(t) is held over the step at its value at the start
     * (mass steps fall on step boundaries: no stage sees the next one early) */
    const double mu = plant_mass_target(&pl->p, t + 1e-9);
    const plant_state x0 = pl->s;
    plant_state k1, k2, k3, k4, xt;
    derivative(pl, &pad0, mu, &x0, &k1, NULL);
    for (int j = 0; j < PLANT_STATE_DIM; j++) {
        xt.x[j] = x0.x[j] + 0.5 * h * k1.x[j];
    }
    derivative(pl, &pad_mid, mu, &xt, &k2, NULL);
    for (int j = 0; j < PLANT_STATE_DIM; j++) {
        xt.x[j] = x0.x[j] + 0.5 * h * k2.x[j];
    }
    derivative(pl, &pad_mid, mu, &xt, &k3, NULL);
    for (int j = 0; j < PLANT_STATE_DIM; j++) {
        xt.x[j] = x0.x[j] + h * k3.x[j];
    }
    derivative(pl, &pad_end, mu, &xt, &k4, NULL);
    const double h6 = h / 6.0;
    for (int j = 0; j < PLANT_STATE_DIM; j++) {
        pl->s.x[j] = x0.x[j] + h6 * (k1.x[j] + 2.0 * (k2.x[j] + k3.x[j]) + k4.x[j]);
    }
    pl->s.q = quat_normalize(pl->s.q);
    if (pl->p.velocity_input) {
        /* the heading the attitude loop aims at, held over the next step */
        pl->yaw_rad = remainder(pl->yaw_rad + h * pl->yaw_rate_cmd_radps, 2.0 * 3.14159265358979323846);
    }
    pl->t = t + h;
    pl->pad_cache_t = pl->t;
    pl->pad_cache = pad_end;
}

void plant_diagnose(const plant *pl, plant_diag *d)
{
    plant_state ds;
    pad_state pad;
    pad_eval(&pl->p.pad, pl->t, &pad);
    derivative(pl, &pad, plant_mass_target(&pl->p, pl->t + 1e-9), &pl->s, &ds, d);
}

double plant_gear_clearance(const plant *pl, pad_state *pad)
{
    pad_state now = pl->pad_cache;
    if (pl->pad_cache_t != pl->t) {
        pad_eval(&pl->p.pad, pl->t, &now);
    }
    double r[3][3];
    quat_to_matrix(pl->s.q, r);
    double clearance = (double)INFINITY;
    for (int f = 0; f < pl->p.foot_count; f++) {
        const v3 arm_w = mat_apply(r, pl->p.foot_m[f]);
        const double height = pad_tilts(&pl->p.pad) ? pad_height_of(&now, v3_add(pl->s.p, arm_w))
                                                    : pl->s.p.z + arm_w.z - now.z_m;
        clearance = height < clearance ? height : clearance;
    }
    if (pad != NULL) {
        *pad = now;
    }
    return clearance;
}

double plant_hover_speed(const plant *pl)
{
    const plant_params *p = &pl->p;
    plant probe = *pl;
    const double weight = pl->s.m * p->gravity_mps2;
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < p->rotor_count; i++) {
        probe.s.u[i] = 1.0;
    }
    plant_diag d;
    plant_diagnose(&probe, &d);
    if (d.force_b.z < weight) {
        return -1.0;
    }
    for (int iter = 0; iter < 60; iter++) {
        const double mid = 0.5 * (lo + hi);
        for (int i = 0; i < p->rotor_count; i++) {
            probe.s.u[i] = mid;
        }
        plant_diagnose(&probe, &d);
        if (d.force_b.z < weight) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

double plant_energy(const plant *pl)
{
    const plant_state *s = &pl->s;
    const v3 inertia = plant_inertia(&pl->p, s->m);
    return 0.5 * s->m * v3_dot(s->v, s->v) + 0.5 * v3_dot(v3_mul(inertia, s->w), s->w) +
           s->m * pl->p.gravity_mps2 * s->p.z;
}

v3 plant_angular_momentum_world(const plant *pl)
{
    double r[3][3];
    quat_to_matrix(pl->s.q, r);
    return mat_apply(r, v3_mul(plant_inertia(&pl->p, pl->s.m), pl->s.w));
}

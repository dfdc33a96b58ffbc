/* cf_test_plant.c - the vehicle of the host flows (cf_test_plant.h). */
#include "cf_test_plant.h"

#include <math.h>
#include <string.h>

void plant_at(plant *pl, double x, double y, double z, double yaw_rad)
{
    memset(pl, 0, sizeof *pl);
    pl->p[0] = x;
    pl->p[1] = y;
    pl->p[2] = z;
    pl->q[0] = cos(yaw_rad / 2);
    pl->q[3] = sin(yaw_rad / 2);
    pl->f_body_z = PLANT_G;
    pl->mass_kg = PLANT_MASS_KG;
    pl->inertia[0] = pl->inertia[1] = 1.66e-5;
    pl->inertia[2] = 2.93e-5;
}

/* body z axis in the world: the third column of R(q) */
void plant_body_z(const plant *pl, double e[3])
{
    const double w = pl->q[0], x = pl->q[1], y = pl->q[2], z = pl->q[3];
    e[0] = 2 * (x * z + w * y);
    e[1] = 2 * (y * z - w * x);
    e[2] = 1 - 2 * (x * x + y * y);
}

double plant_yaw_rad(const plant *pl)
{
    const double w = pl->q[0], x = pl->q[1], y = pl->q[2], z = pl->q[3];
    return atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

void plant_step(plant *pl, const cf_force_torque *ft, double dt)
{
    double e[3];
    plant_body_z(pl, e);
    const double a = (double)ft->thrust_n / pl->mass_kg;
    pl->f_body_z = a;
    for (int k = 0; k < 3; k++) {
        pl->v[k] += (a * e[k] - (k == 2 ? PLANT_G : 0.0)) * dt;
        pl->p[k] += pl->v[k] * dt;
    }
    if (pl->p[2] <= 0.0) {
        /* on the ground: held there, level, still */
        pl->p[2] = 0.0;
        if (pl->v[2] < 0.0) {
            pl->v[0] = pl->v[1] = pl->v[2] = 0.0;
        }
        pl->f_body_z = PLANT_G;
    }
    const double *J = pl->inertia;
    double wdot[3];
    const double Jw[3] = {J[0] * pl->w[0], J[1] * pl->w[1], J[2] * pl->w[2]};
    const double gyro[3] = {pl->w[1] * Jw[2] - pl->w[2] * Jw[1], pl->w[2] * Jw[0] - pl->w[0] * Jw[2],
                            pl->w[0] * Jw[1] - pl->w[1] * Jw[0]};
    for (int k = 0; k < 3; k++) {
        wdot[k] = ((double)ft->torque_nm[k] - gyro[k]) / J[k];
    }
    for (int k = 0; k < 3; k++) {
        pl->w[k] += wdot[k] * dt;
    }
    const double *q = pl->q, *w = pl->w;
    const double dq[4] = {-0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]), 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]),
                          0.5 * (q[0] * w[1] - q[1] * w[2] + q[3] * w[0]), 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0])};
    double n = 0.0;
    for (int k = 0; k < 4; k++) {
        pl->q[k] += dq[k] * dt;
        n += pl->q[k] * pl->q[k];
    }
    n = sqrt(n);
    for (int k = 0; k < 4; k++) {
        pl->q[k] /= n;
    }
}

/* A smooth move from a to b over t_s (a quintic, zero speed and acceleration at both ends), at time t. */
void smooth(double a, double b, double t_s, double t, double *p, double *v, double *acc)
{
    const double u = t <= 0 ? 0 : (t >= t_s ? 1 : t / t_s);
    const double s5 = u * u * u * (10 - 15 * u + 6 * u * u);
    const double d5 = 30 * u * u * (1 - u) * (1 - u) / t_s;
    const double dd5 = 60 * u * (1 - 3 * u + 2 * u * u) / (t_s * t_s);
    *p = a + (b - a) * s5;
    *v = (b - a) * d5;
    *acc = (b - a) * dd5;
}


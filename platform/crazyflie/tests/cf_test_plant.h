/* cf_test_plant.h - the vehicle of the host flows (test_cf_convert.c,
 * test_cf_glue.c): a rigid body under the app's body thrust and moments. */
#ifndef CF_TEST_PLANT_H
#define CF_TEST_PLANT_H

#include "cf_convert.h"

/* A Crazyflie for the flows: a rigid body under the app's body thrust and
 * moments (what the firmware's mixer makes of controlModeForceTorque), the
 * ground at z = 0, stepped at the stabilizer's 1 kHz; its mass is the cf2's
 * CF_MASS, heavier than the library's nominal 27 g. */
#define PLANT_MASS_KG 0.029
#define PLANT_G 9.81

typedef struct plant {
    double p[3], v[3];
    double q[4]; /* w, x, y, z: body -> world */
    double w[3]; /* body rate, rad/s */
    double f_body_z; /* specific force along body z, m/s^2 (the accelerometer) */
    double mass_kg;
    double inertia[3]; /* kg m^2 */
} plant;

void plant_at(plant *pl, double x, double y, double z, double yaw_rad);
/* body z axis in the world: the third column of R(q) */
void plant_body_z(const plant *pl, double e[3]);
double plant_yaw_rad(const plant *pl);
/* dt of flight under the body thrust and moments ft */
void plant_step(plant *pl, const cf_force_torque *ft, double dt);
/* A smooth move from a to b over t_s (a quintic, zero speed and acceleration at both ends), at time t. */
void smooth(double a, double b, double t_s, double t, double *p, double *v, double *acc);

#endif

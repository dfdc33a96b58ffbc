/*
 * vmath.h - the plant's own vector and quaternion routines, in double.
 *
 * Deliberately independent of firmware/ (fc/vec3.h, fc/quat.h): a convention
 * error in one cannot hide in both. Hamilton quaternions, scalar first,
 * q = body -> world: v_w = q (x) [0, v_b] (x) q*, q' = 1/2 q (x) [0, w_b].
 */
#ifndef SIM_VMATH_H
#define SIM_VMATH_H

#include <math.h>

typedef struct v3 {
    double x, y, z;
} v3;

typedef struct quat {
    double w, x, y, z;
} quat;

static inline v3 v3_make(double x, double y, double z)
{
    const v3 r = {x, y, z};
    return r;
}
static inline v3 v3_add(v3 a, v3 b) { return v3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline v3 v3_sub(v3 a, v3 b) { return v3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline v3 v3_scale(v3 a, double s) { return v3_make(a.x * s, a.y * s, a.z * s); }
static inline double v3_dot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double v3_norm(v3 a) { return sqrt(v3_dot(a, a)); }
static inline v3 v3_cross(v3 a, v3 b)
{
    return v3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
/* a + s b */
static inline v3 v3_axpy(v3 a, double s, v3 b) { return v3_make(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z); }
static inline v3 v3_mul(v3 a, v3 b) { return v3_make(a.x * b.x, a.y * b.y, a.z * b.z); }

static inline quat quat_make(double w, double x, double y, double z)
{
    const quat q = {w, x, y, z};
    return q;
}
static inline quat quat_identity(void) { return quat_make(1.0, 0.0, 0.0, 0.0); }

/* Hamilton product a (x) b. */
static inline quat quat_mul(quat a, quat b)
{
    return quat_make(a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                     a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w);
}
static inline double quat_norm(quat q) { return sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z); }
static inline quat quat_normalize(quat q)
{
    const double n = quat_norm(q);
    return n > 0.0 ? quat_make(q.w / n, q.x / n, q.y / n, q.z / n) : quat_identity();
}

/* Rotation matrix of q (body -> world), row-major r[3][3]. */
static inline void quat_to_matrix(quat q, double r[3][3])
{
    const double ww = q.w * q.w, xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    const double xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z, wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    r[0][0] = ww + xx - yy - zz;
    r[0][1] = 2.0 * (xy - wz);
    r[0][2] = 2.0 * (xz + wy);
    r[1][0] = 2.0 * (xy + wz);
    r[1][1] = ww - xx + yy - zz;
    r[1][2] = 2.0 * (yz - wx);
    r[2][0] = 2.0 * (xz - wy);
    r[2][1] = 2.0 * (yz + wx);
    r[2][2] = ww - xx - yy + zz;
}
static inline v3 mat_apply(const double r[3][3], v3 v)
{
    return v3_make(r[0][0] * v.x + r[0][1] * v.y + r[0][2] * v.z, r[1][0] * v.x + r[1][1] * v.y + r[1][2] * v.z,
                   r[2][0] * v.x + r[2][1] * v.y + r[2][2] * v.z);
}
static inline v3 mat_apply_t(const double r[3][3], v3 v)
{
    return v3_make(r[0][0] * v.x + r[1][0] * v.y + r[2][0] * v.z, r[0][1] * v.x + r[1][1] * v.y + r[2][1] * v.z,
                   r[0][2] * v.x + r[1][2] * v.y + r[2][2] * v.z);
}

/* ZYX (yaw, pitch, roll) angles of q, radians. */
static inline void quat_to_rpy(quat q, double *roll, double *pitch, double *yaw)
{
    *roll = atan2(2.0 * (q.w * q.x + q.y * q.z), 1.0 - 2.0 * (q.x * q.x + q.y * q.y));
    const double s = 2.0 * (q.w * q.y - q.z * q.x);
    *pitch = asin(s > 1.0 ? 1.0 : (s < -1.0 ? -1.0 : s));
    *yaw = atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}
static inline quat quat_from_rpy(double roll, double pitch, double yaw)
{
    const double cr = cos(0.5 * roll), sr = sin(0.5 * roll), cp = cos(0.5 * pitch), sp = sin(0.5 * pitch);
    const double cy = cos(0.5 * yaw), sy = sin(0.5 * yaw);
    return quat_make(cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy);
}
/* Rotation by angle about a unit axis. */
static inline quat quat_from_axis_angle(v3 axis, double angle)
{
    const double s = sin(0.5 * angle);
    return quat_make(cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s);
}

#endif /* SIM_VMATH_H */

/* sensors.c - sampled, noisy, biased, quantised and delayed measurements (sensors.h). */
#include "sensors.h"

#include <math.h>
#include <string.h>

/* Stream numbers of the channels (the run seed's streams 0..99 are the sensors'). */
enum { STREAM_IMU = 1, STREAM_POSITION = 2, STREAM_ALTITUDE = 3, STREAM_ATTITUDE = 4, STREAM_HEADING = 5 };

/* Half a plant step is far below any sample period: times closer than this are equal. */
#define TIME_EPS 1e-9

static double period_of(double rate_hz, double controller_dt_s)
{
    return rate_hz > 0.0 ? 1.0 / rate_hz : controller_dt_s;
}

const char *sensors_check(const sensor_params *p, double controller_dt_s)
{
    const double rates[] = {p->imu.rate_hz, p->position.rate_hz, p->altitude.rate_hz, p->attitude.rate_hz,
                            p->heading.rate_hz};
    const double delays[] = {p->imu.delay_s, p->position.delay_s, p->altitude.delay_s, p->attitude.delay_s,
                             p->heading.delay_s};
    for (int i = 0; i < 5; i++) {
        if (!(rates[i] >= 0.0) || !(delays[i] >= 0.0)) {
            return "sensor rates and delays must be non-negative";
        }
        const double period = period_of(rates[i], controller_dt_s);
        if (delays[i] / period > SENSOR_RING - 4) {
            return "sensor delay too long for its rate (more than 124 samples in flight)";
        }
    }
    return NULL;
}

static void channel_init(sensor_channel *c, int dim, double period_s, double delay_s)
{
    memset(c, 0, sizeof *c);
    c->dim = dim;
    c->period_s = period_s;
    c->delay_s = delay_s;
    c->next_t = 0.0;
}

static void channel_push(sensor_channel *c, double t, const double *v)
{
    c->head = (c->head + 1) % SENSOR_RING;
    c->t[c->head] = t;
    for (int i = 0; i < c->dim; i++) {
        c->value[c->head][i] = v[i];
    }
    if (c->count < SENSOR_RING) {
        c->count++;
    }
}

/* The ring index of the newest sample taken at or before t - delay (the oldest one if none is). */
static int channel_index(const sensor_channel *c, double t)
{
    int idx = c->head;
    for (int k = 0; k < c->count; k++) {
        if (c->t[idx] + c->delay_s <= t + TIME_EPS) {
            return idx;
        }
        if (k + 1 < c->count) {
            idx = (idx + SENSOR_RING - 1) % SENSOR_RING;
        }
    }
    return idx;
}

static const double *channel_read(const sensor_channel *c, double t)
{
    return c->value[channel_index(c, t)];
}

static bool channel_due(sensor_channel *c, double t)
{
    if (t + TIME_EPS < c->next_t) {
        return false;
    }
    /* the next sample on the grid of the period (no drift over long runs) */
    const double n = floor((t + TIME_EPS) / c->period_s) + 1.0;
    c->next_t = n * c->period_s;
    return true;
}

static double quantise(double x, double lsb)
{
    return lsb > 0.0 ? lsb * nearbyint(x / lsb) : x;
}

void sensors_init(sensors *s, const sensor_params *p, double controller_dt_s, uint64_t seed)
{
    memset(s, 0, sizeof *s);
    s->p = *p;
    channel_init(&s->imu, 6, period_of(p->imu.rate_hz, controller_dt_s), p->imu.delay_s);
    channel_init(&s->position, 6, period_of(p->position.rate_hz, controller_dt_s), p->position.delay_s);
    channel_init(&s->altitude, 1, period_of(p->altitude.rate_hz, controller_dt_s), p->altitude.delay_s);
    channel_init(&s->attitude, 4, period_of(p->attitude.rate_hz, controller_dt_s), p->attitude.delay_s);
    channel_init(&s->heading, 1, period_of(p->heading.rate_hz, controller_dt_s), p->heading.delay_s);
    rng_seed(&s->r_imu, seed, STREAM_IMU);
    rng_seed(&s->r_position, seed, STREAM_POSITION);
    rng_seed(&s->r_altitude, seed, STREAM_ALTITUDE);
    rng_seed(&s->r_attitude, seed, STREAM_ATTITUDE);
    rng_seed(&s->r_heading, seed, STREAM_HEADING);
    /* the random part of the biases, drawn once per run */
    const double gb = p->imu.gyro_bias_std_radps, ab = p->imu.accel_bias_std_mps2;
    s->gyro_bias = v3_add(p->imu.gyro_bias_radps,
                          v3_make(gb * rng_normal(&s->r_imu), gb * rng_normal(&s->r_imu), gb * rng_normal(&s->r_imu)));
    s->accel_bias = v3_add(p->imu.accel_bias_mps2,
                           v3_make(ab * rng_normal(&s->r_imu), ab * rng_normal(&s->r_imu), ab * rng_normal(&s->r_imu)));
}

void sensors_sample(sensors *s, const plant *pl, double t)
{
    const double scale = s->p.noise_scale;
    if (channel_due(&s->imu, t)) {
        plant_diag d;
        plant_diagnose(pl, &d);
        const imu_params *ip = &s->p.imu;
        const double gn = scale * ip->gyro_noise_radps, an = scale * ip->accel_noise_mps2;
        const v3 gyro = v3_add(pl->s.w, s->gyro_bias), accel = v3_add(d.specific_force_b, s->accel_bias);
        const double v[6] = {
            quantise(gyro.x + gn * rng_normal(&s->r_imu), ip->gyro_lsb_radps),
            quantise(gyro.y + gn * rng_normal(&s->r_imu), ip->gyro_lsb_radps),
            quantise(gyro.z + gn * rng_normal(&s->r_imu), ip->gyro_lsb_radps),
            quantise(accel.x + an * rng_normal(&s->r_imu), ip->accel_lsb_mps2),
            quantise(accel.y + an * rng_normal(&s->r_imu), ip->accel_lsb_mps2),
            quantise(accel.z + an * rng_normal(&s->r_imu), ip->accel_lsb_mps2),
        };
        channel_push(&s->imu, t, v);
    }
    if (channel_due(&s->position, t)) {
        const position_params *pp = &s->p.position;
        const double pn = scale * pp->noise_m, vn = scale * pp->velocity_noise_mps;
        const double v[6] = {
            quantise(pl->s.p.x + pn * rng_normal(&s->r_position), pp->lsb_m),
            quantise(pl->s.p.y + pn * rng_normal(&s->r_position), pp->lsb_m),
            quantise(pl->s.p.z + pn * rng_normal(&s->r_position), pp->lsb_m),
            quantise(pl->s.v.x + vn * rng_normal(&s->r_position), pp->velocity_lsb_mps),
            quantise(pl->s.v.y + vn * rng_normal(&s->r_position), pp->velocity_lsb_mps),
            quantise(pl->s.v.z + vn * rng_normal(&s->r_position), pp->velocity_lsb_mps),
        };
        channel_push(&s->position, t, v);
    }
    if (s->p.altitude.source != ALTITUDE_FROM_POSITION && channel_due(&s->altitude, t)) {
        const altitude_params *ap = &s->p.altitude;
        double value;
        if (ap->source == ALTITUDE_RANGE) {
            /* distance from the CG along body -z to the pad's plane */
            pad_state pad;
            pad_eval(&pl->p.pad, t, &pad);
            double r33 = 1.0 - 2.0 * (pl->s.q.x * pl->s.q.x + pl->s.q.y * pl->s.q.y);
            double height = pl->s.p.z - pad.z_m;
            if (pad_tilts(&pl->p.pad)) {
                /* a rolling deck: the plane's distance along n over cos(body z, n) */
                double r[3][3];
                quat_to_matrix(pl->s.q, r);
                r33 = v3_dot(v3_make(r[0][2], r[1][2], r[2][2]), pad_normal(&pad));
                height = pad_height_of(&pad, pl->s.p);
            }
            value = r33 > 0.05 ? height / r33 : ap->range_max_m;
            if (value > ap->range_max_m || value < 0.0) {
                value = ap->range_max_m;
            }
        } else {
            value = pl->s.p.z;
        }
        value = quantise(value + scale * ap->noise_m * rng_normal(&s->r_altitude), ap->lsb_m);
        channel_push(&s->altitude, t, &value);
    }
    if (channel_due(&s->attitude, t)) {
        const double n = scale * s->p.attitude.noise_rad;
        quat q = pl->s.q;
        if (n > 0.0) {
            const v3 e = v3_make(n * rng_normal(&s->r_attitude), n * rng_normal(&s->r_attitude),
                                 n * rng_normal(&s->r_attitude));
            const double angle = v3_norm(e);
            if (angle > 0.0) {
                q = quat_mul(q, quat_from_axis_angle(v3_scale(e, 1.0 / angle), angle));
            }
        }
        const double v[4] = {q.w, q.x, q.y, q.z};
        channel_push(&s->attitude, t, v);
    }
    if (s->p.heading.enabled && channel_due(&s->heading, t)) {
        const quat q = pl->s.q;
        /* the yaw of the body x axis: atan2 of the first column of R(q) */
        const double yaw = atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
        const double measured = yaw + s->p.heading.bias_rad + scale * s->p.heading.noise_rad * rng_normal(&s->r_heading);
        const double wrapped = atan2(sin(measured), cos(measured));
        channel_push(&s->heading, t, &wrapped);
    }
}

void sensors_read(const sensors *s, double t, sensor_readout *out)
{
    const double *imu = channel_read(&s->imu, t);
    out->gyro_radps = v3_make(imu[0], imu[1], imu[2]);
    out->accel_mps2 = v3_make(imu[3], imu[4], imu[5]);
    const double *pos = channel_read(&s->position, t);
    out->position_m = v3_make(pos[0], pos[1], pos[2]);
    out->velocity_mps = v3_make(pos[3], pos[4], pos[5]);
    out->has_altitude = s->p.altitude.source != ALTITUDE_FROM_POSITION;
    out->altitude_is_range = s->p.altitude.source == ALTITUDE_RANGE;
    out->altitude_m = out->has_altitude ? channel_read(&s->altitude, t)[0] : pos[2];
    out->altitude_sample_t = out->has_altitude && s->altitude.count > 0 ? s->altitude.t[channel_index(&s->altitude, t)]
                                                                          : (double)NAN;
    const double *att = channel_read(&s->attitude, t);
    out->attitude = quat_make(att[0], att[1], att[2], att[3]);
    /* the newest heading sample delivered by t, if one is */
    const int heading = channel_index(&s->heading, t);
    out->has_heading = s->p.heading.enabled && s->heading.count > 0 &&
                       s->heading.t[heading] + s->heading.delay_s <= t + TIME_EPS;
    out->heading_rad = out->has_heading ? s->heading.value[heading][0] : 0.0;
    out->heading_sample_t = out->has_heading ? s->heading.t[heading] : (double)NAN;
}

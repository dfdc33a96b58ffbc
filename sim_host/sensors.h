/*
 * sensors.h - what the flight software gets to see of the plant.
 *
 * Channels: IMU (gyro and accelerometer, body frame), position and velocity
 * (world, like a motion-capture system or an onboard estimator), altitude
 * (absolute, or range to the pad along body -z), attitude (for the platforms
 * that hand the firmware their own estimate), heading (a measured yaw, as a
 * motion-capture system, a lighthouse deck or a compass gives it; off unless
 * enabled). Each channel samples the plant at
 * its own rate (0: the controller's rate), adds bias and white noise, quantises
 * to its LSB, and is delivered delay_s after it was taken (a ring of samples).
 * Noise is drawn from per-channel seeded streams: a run is reproducible from
 * its seed.
 */
#ifndef SIM_SENSORS_H
#define SIM_SENSORS_H

#include <stdbool.h>
#include <stdint.h>

#include "plant.h"
#include "rng.h"

typedef struct imu_params {
    double rate_hz, delay_s;
    double gyro_noise_radps;   /* std per sample */
    double gyro_lsb_radps;     /* 0: not quantised */
    v3 gyro_bias_radps;        /* fixed part */
    double gyro_bias_std_radps; /* random part, drawn per run */
    double accel_noise_mps2, accel_lsb_mps2;
    v3 accel_bias_mps2;
    double accel_bias_std_mps2;
} imu_params;

typedef struct position_params {
    double rate_hz, delay_s;
    double noise_m, lsb_m;
    double velocity_noise_mps, velocity_lsb_mps;
} position_params;

typedef enum altitude_source {
    ALTITUDE_FROM_POSITION = 0, /* z of the position channel */
    ALTITUDE_ABSOLUTE,          /* a separate absolute altitude (barometer-like, with its own noise) */
    ALTITUDE_RANGE              /* range to the pad along body -z (ToF / ultrasonic), turned into z by the platform */
} altitude_source;

typedef struct altitude_params {
    altitude_source source;
    double rate_hz, delay_s;
    double noise_m, lsb_m;
    double range_max_m;        /* range: beyond this the reading saturates */
} altitude_params;

typedef struct attitude_sensor_params {
    double rate_hz, delay_s;
    double noise_rad;          /* std of a small random rotation per axis */
} attitude_sensor_params;

typedef struct heading_sensor_params {
    bool enabled;
    double rate_hz, delay_s;
    double noise_rad;          /* std per sample */
    double bias_rad;           /* a constant offset (a compass's declination error) */
} heading_sensor_params;

typedef struct sensor_params {
    imu_params imu;
    position_params position;
    altitude_params altitude;
    attitude_sensor_params attitude;
    heading_sensor_params heading;
    double noise_scale;        /* multiplies every noise std (Monte-Carlo) */
} sensor_params;

#define SENSOR_RING 128
#define SENSOR_DIM 6

typedef struct sensor_channel {
    double period_s, delay_s, next_t;
    int dim;
    int head, count;           /* ring of the newest samples */
    double t[SENSOR_RING];
    double value[SENSOR_RING][SENSOR_DIM];
} sensor_channel;

typedef struct sensors {
    sensor_params p;
    sensor_channel imu, position, altitude, attitude, heading;
    rng r_imu, r_position, r_altitude, r_attitude, r_heading;
    v3 gyro_bias, accel_bias;  /* fixed + drawn */
} sensors;

typedef struct sensor_readout {
    v3 gyro_radps, accel_mps2;
    v3 position_m, velocity_mps;
    double altitude_m;         /* absolute z, or the range when altitude_is_range */
    bool altitude_is_range;
    bool has_altitude;         /* a separate altitude channel exists */
    double altitude_sample_t;  /* when the altitude sample read was taken (a new one: a fresh sample) */
    quat attitude;
    bool has_heading;          /* the heading channel is enabled */
    double heading_rad;        /* yaw in [-pi, pi] */
    double heading_sample_t;   /* when the heading sample read was taken (a new one: a fresh sample) */
} sensor_readout;

/* NULL if the parameters are usable, else a reason. */
const char *sensors_check(const sensor_params *p, double controller_dt_s);

void sensors_init(sensors *s, const sensor_params *p, double controller_dt_s, uint64_t seed);

/* Takes the samples that are due at time t (call at every plant step, before
 * the step; the plant's state is the one at t). */
void sensors_sample(sensors *s, const plant *pl, double t);

/* What the flight software reads at time t. */
void sensors_read(const sensors *s, double t, sensor_readout *out);

#endif /* SIM_SENSORS_H */

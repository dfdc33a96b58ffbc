/* stabilizer_types.h - the firmware's types the glue reads and writes,
 * declared as crazyflie-firmware declares them (same members, order and
 * types), for a host build without a firmware checkout. With CRAZYFLIE_BASE
 * the firmware's own header is used instead. */
#ifndef CF_TEST_STABILIZER_TYPES_H
#define CF_TEST_STABILIZER_TYPES_H

#include <stdbool.h>
#include <stdint.h>

typedef uint32_t stabilizerStep_t;

typedef union {
    struct {
        float x;
        float y;
        float z;
    };
    float axis[3];
} Axis3f;

typedef struct attitude_s {
    uint32_t timestamp;
    float roll;
    float pitch;
    float yaw;
} attitude_t;

struct vec3_s {
    uint32_t timestamp;
    float x;
    float y;
    float z;
};
typedef struct vec3_s point_t;
typedef struct vec3_s velocity_t;
typedef struct vec3_s acc_t;
typedef struct vec3_s jerk_t;

typedef struct quaternion_s {
    union {
        struct {
            float q0;
            float q1;
            float q2;
            float q3;
        };
        struct {
            float x;
            float y;
            float z;
            float w;
        };
    };
} quaternion_t;

typedef struct baro_s {
    float pressure;
    float temperature;
    float asl;
} baro_t;

typedef struct sensorData_s {
    Axis3f acc;  /* G */
    Axis3f gyro; /* deg/s */
    Axis3f mag;
    baro_t baro;
    uint64_t interruptTimestamp;
} sensorData_t;

typedef struct state_s {
    attitude_t attitude; /* deg, legacy: pitch inverted */
    quaternion_t attitudeQuaternion;
    point_t position;
    velocity_t velocity;
    acc_t acc;
} state_t;

#define STABILIZER_NR_OF_MOTORS 4

typedef enum control_mode_e {
    controlModeLegacy = 0,
    controlModeForceTorque = 1,
    controlModeForce = 2,
} control_mode_t;

typedef struct control_s {
    union {
        struct {
            int16_t roll;
            int16_t pitch;
            int16_t yaw;
            float thrust;
        };
        struct {
            float thrustSi;
            union {
                float torque[3];
                struct {
                    float torqueX;
                    float torqueY;
                    float torqueZ;
                };
            };
        };
        float normalizedForces[STABILIZER_NR_OF_MOTORS];
    };
    control_mode_t controlMode;
} control_t;

typedef enum mode_e { modeDisable = 0, modeAbs, modeVelocity } stab_mode_t;

typedef struct {
    stab_mode_t x;
    stab_mode_t y;
    stab_mode_t z;
    stab_mode_t roll;
    stab_mode_t pitch;
    stab_mode_t yaw;
    stab_mode_t quat;
} setpoint_mode_t;

typedef struct setpoint_s {
    uint32_t timestamp;
    attitude_t attitude;
    attitude_t attitudeRate;
    quaternion_t attitudeQuaternion;
    float thrust;
    point_t position;
    velocity_t velocity;
    acc_t acceleration;
    jerk_t jerk;
    bool velocity_body;
    setpoint_mode_t mode;
} setpoint_t;

#define RATE_1000_HZ 1000
#define RATE_500_HZ 500
#define RATE_MAIN_LOOP RATE_1000_HZ
#define ATTITUDE_RATE RATE_500_HZ

#endif

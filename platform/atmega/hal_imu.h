/*
 * hal_imu.h - MPU-6050/6000-class IMU on TWI (I2C) at 400 kHz.
 *
 * Wiring (Arduino Mega): SDA = PD1 (D20), SCL = PD0 (D21), AD0 low (address
 * 0x68), 3.3 V breakout with its own pull-ups (the internal 5 V pull-ups stay
 * off). Mount the chip with its X arrow forward and Y to the left: the body
 * frame is FLU and the chip's Z then points up, so at rest the accelerometer
 * reads (0, 0, +g), the specific force fc_imu_sample expects.
 *
 * Configuration: clock from the X gyro PLL, sample rate 1 kHz, DLPF 44 Hz,
 * gyro +-2000 deg/s (16.4 LSB per deg/s), accel +-8 g (4096 LSB per g).
 * One read is a 14-byte burst from ACCEL_XOUT_H (accel, temperature, gyro):
 * about 0.45 ms on the bus at 400 kHz, blocking.
 *
 * A missing or stuck device never hangs the loop: every TWI wait times out
 * (100 us per byte), a NACK ends the transfer at once, and after three
 * failed reads in a row the device is treated as absent and probed again
 * only every HAL_IMU_RETRY_READS calls, so an absent IMU costs one START and
 * one address byte per retry. The caller gets false and feeds the
 * controller the at-rest sample (hal_imu_at_rest).
 */
#ifndef FC_ATMEGA_HAL_IMU_H
#define FC_ATMEGA_HAL_IMU_H

#include <stdbool.h>
#include <stdint.h>

#include "fc/attitude_estimator.h"

#define HAL_IMU_ADDRESS 0x68u
#define HAL_IMU_TWI_HZ 400000UL
#define HAL_IMU_RETRY_READS 100u

typedef struct hal_imu_raw {
    int16_t accel[3]; /* chip axes, LSB */
    int16_t gyro[3];
} hal_imu_raw;

/* Sets up TWI and probes and configures the device; false if it is absent
 * (the reads then keep probing it now and then). */
bool hal_imu_init(void);

/* One burst read; false on a missing device, a NACK or a timeout. */
bool hal_imu_read(hal_imu_raw *raw);

/* Raw counts to SI units in the backend's formats (RATE rad/s, ACCEL m/s2),
 * integer arithmetic with FC_C constants in fixed. */
void hal_imu_to_sample(const hal_imu_raw *raw, fc_imu_sample *sample);

/* Level and at rest: no rotation, specific force (0, 0, +9.81). */
void hal_imu_at_rest(fc_imu_sample *sample);

#endif /* FC_ATMEGA_HAL_IMU_H */

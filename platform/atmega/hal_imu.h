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
 * One read is a 14-byte burst from ACCEL_XOUT_H (accel, temperature, gyro),
 * about 0.4 ms on the bus at 400 kHz. It runs in the background, one step of
 * a state machine per TWI interrupt: the loop starts it HAL_IMU_READ_LEAD_US
 * before its tick (hal_imu_start_read, from a timer interrupt) and takes the
 * finished sample at the tick (hal_imu_read), so the loop never waits on
 * the bus and the sample is at most the lead old.
 *
 * A missing or stuck device never hangs the loop: a NACK or an unexpected
 * status ends the burst at once, a burst still on the bus at the tick is
 * abandoned and the TWI hardware released, and after three failed reads in
 * a row the device is treated as absent. It is then probed again (polled,
 * every TWI wait bounded: 100 us per byte) only every HAL_IMU_RETRY_READS
 * calls, so an absent IMU costs one START and one address byte per retry.
 * The caller gets false and feeds the controller the at-rest sample
 * (hal_imu_at_rest).
 */
#ifndef FC_ATMEGA_HAL_IMU_H
#define FC_ATMEGA_HAL_IMU_H

#include <stdbool.h>
#include <stdint.h>

#include "fc/attitude_estimator.h"

#define HAL_IMU_ADDRESS 0x68u
#define HAL_IMU_TWI_HZ 400000UL
#define HAL_IMU_RETRY_READS 100u
#define HAL_IMU_BURST_BYTES 14u
/* the burst's start ahead of the loop's tick: 17 bytes of 9 SCL periods at
 * 400 kHz, the START, repeated START and STOP, and room for the latency of
 * its interrupts behind others */
#define HAL_IMU_READ_LEAD_US 600UL

typedef struct hal_imu_raw {
    int16_t accel[3]; /* chip axes, LSB */
    int16_t gyro[3];
} hal_imu_raw;

/* Sets up TWI and probes and configures the device; false if it is absent
 * (the reads then keep probing it now and then). */
bool hal_imu_init(void);

/* Starts the burst read in the background; nothing while the device is
 * absent or a burst is still under way. Safe from an interrupt. */
void hal_imu_start_read(void);

/* The burst started last: true and its counts when it finished; false on a
 * missing device, a NACK, a burst still on the bus (abandoned) or none
 * started. While the device is absent, every HAL_IMU_RETRY_READS calls
 * probe it (polled). */
bool hal_imu_read(hal_imu_raw *raw);

/* Raw counts to SI units in the backend's formats (RATE rad/s, ACCEL m/s2),
 * integer arithmetic with FC_C constants in fixed. */
void hal_imu_to_sample(const hal_imu_raw *raw, fc_imu_sample *sample);

/* Level and at rest: no rotation, specific force (0, 0, +9.81). */
void hal_imu_at_rest(fc_imu_sample *sample);

#endif /* FC_ATMEGA_HAL_IMU_H */

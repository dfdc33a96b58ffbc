/*
 * telemetry.h - the ATmega image's telemetry frame on USART0.
 *
 * Shared by the image (main.c) and the simavr test on the host
 * (tools/simavr/avr_loop_test.c), which parses frames by the byte offsets below: no
 * packed structs, so the layout is the same on both sides. Multi-byte fields
 * are little-endian (AVR's own order).
 *
 *   off size field
 *    0   1   sync 0xFC
 *    1   1   sync 0x5A
 *    2   1   length of what follows up to (not including) the CRC: 51
 *    3   1   version (1)
 *    4   4   loop counter: control steps since the loop started
 *    8   2   loop rate, Hz
 *   10   2   deadline overruns since start (iterations whose work took
 *            longer than the period, plus ticks missed)
 *   12   4   worst cycles of one iteration's work since start (tick to end of
 *            the work: IMU read, controller step, ESC write, telemetry)
 *   16   4   worst cycles of one iteration's work in this frame's window
 *   20   4   fewest cycles of one fc_controller_step call in the window
 *   24   4   most cycles of one fc_controller_step call in the window
 *   28   4   cycles of the controller's setup at boot: copying the
 *            build-time snapshot (fc_controller_init without simavr)
 *   32   2   fc_step_status of the last step (fc/status.h)
 *   34   1   platform status bits (TM_STATUS_*)
 *   35   1   rotor count
 *   36   4   thrust demanded, mN (signed)
 *   40  12   ESC pulses, us, six channels (1000 = motor off)
 *   52   2   IMU read failures since start
 *   54   1   CRC-8 (polynomial 0x07, initial 0) of bytes 2..53
 *
 * The window is the loops since the previous frame (TM_FRAME_LOOPS of them
 * at the loop rates used). 55 bytes at 115200 baud take 4.7 ms on the wire.
 */
#ifndef FC_ATMEGA_TELEMETRY_H
#define FC_ATMEGA_TELEMETRY_H

#define TM_SYNC0 0xFCu
#define TM_SYNC1 0x5Au
#define TM_VERSION 1u
#define TM_FRAME_SIZE 55u
#define TM_LENGTH (TM_FRAME_SIZE - 4u) /* bytes 3 .. 53 */

#define TM_OFF_SYNC0 0
#define TM_OFF_SYNC1 1
#define TM_OFF_LENGTH 2
#define TM_OFF_VERSION 3
#define TM_OFF_LOOP_COUNT 4
#define TM_OFF_LOOP_HZ 8
#define TM_OFF_OVERRUNS 10
#define TM_OFF_LOOP_CYCLES_WORST 12
#define TM_OFF_LOOP_CYCLES_WINDOW 16
#define TM_OFF_STEP_CYCLES_MIN 20
#define TM_OFF_STEP_CYCLES_MAX 24
#define TM_OFF_INIT_CYCLES 28
#define TM_OFF_FC_STATUS 32
#define TM_OFF_STATUS 34
#define TM_OFF_ROTOR_COUNT 35
#define TM_OFF_THRUST_MN 36
#define TM_OFF_ESC_US 40
#define TM_ESC_CHANNELS 6
#define TM_OFF_IMU_ERRORS 52
#define TM_OFF_CRC 54

/* platform status bits (byte 34) */
#define TM_STATUS_IMU_ERROR (1u << 0)   /* the last IMU read failed: the controller got the
                                         * at-rest sample (level, no rotation) */
#define TM_STATUS_ARMED (1u << 1)       /* armed over the UART and by the controller's checks */
#define TM_STATUS_MOTORS_ON (1u << 2)   /* the controller drives the motors */
#define TM_STATUS_FIXED (1u << 3)       /* fixed-point backend (else float) */
#define TM_STATUS_INIT_FAILED (1u << 4) /* fc_controller_init did not return FC_INIT_OK (at
                                         * boot without the snapshot; with it, at build time: the
                                         * build fails) */
#define TM_STATUS_TX_DROPPED (1u << 5)  /* a frame found the TX buffer full and was dropped */
#define TM_STATUS_SIMAVR (1u << 6)      /* the build with simavr's .mmcu section */
#define TM_STATUS_OVERRUN (1u << 7)     /* an overrun happened in this window */

/* Commands to the image on USART0 RX: four bytes each. */
#define TM_CMD_ARM "ARM1"
#define TM_CMD_DISARM "ARM0"

#endif /* FC_ATMEGA_TELEMETRY_H */

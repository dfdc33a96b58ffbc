/* hal_imu.c - MPU-6050 over TWI (hal_imu.h): set up polled, with timeouts;
 * the burst read driven by the TWI interrupt. */
#include "hal_imu.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/twi.h>

#include "fc/scalar.h"
#include "hal_clock.h"

/* registers */
#define MPU_SMPLRT_DIV 0x19u
#define MPU_CONFIG 0x1Au
#define MPU_GYRO_CONFIG 0x1Bu
#define MPU_ACCEL_CONFIG 0x1Cu
#define MPU_ACCEL_XOUT_H 0x3Bu
#define MPU_PWR_MGMT_1 0x6Bu
#define MPU_WHO_AM_I 0x75u

/* a byte is 9 SCL periods (22.5 us at 400 kHz); allow some clock stretching */
#define TWI_TIMEOUT_CYCLES ((uint32_t)(F_CPU / 10000UL)) /* 100 us */
#define FAILS_BEFORE_ABSENT 3u

/* scale factors: one LSB in the backend's format */
#define GYRO_LSB_RADPS FC_C(1.06422515e-3f, RATE)  /* (pi / 180) / 16.4 */
#define ACCEL_LSB_MPS2 FC_C(2.39420166e-3f, ACCEL) /* 9.80665 / 4096 */

static bool s_present;
static uint8_t s_fails;
static uint8_t s_retry_countdown;

/* ---- TWI master, polled, every wait bounded (set-up and probes) -------- */

static bool twi_wait(void)
{
    const uint32_t start = hal_clock_cycles();
    while ((TWCR & _BV(TWINT)) == 0u) {
        if (hal_clock_cycles() - start > TWI_TIMEOUT_CYCLES) {
            /* bus stuck (SCL held, no device clocking): release the
             * hardware so the next transfer starts clean */
            TWCR = 0u;
            TWCR = _BV(TWEN);
            return false;
        }
    }
    return true;
}

static void twi_stop(void)
{
    TWCR = _BV(TWINT) | _BV(TWEN) | _BV(TWSTO);
    /* STOP completes on its own in a few us; the next START waits for it */
}

static bool twi_start(uint8_t address_rw)
{
    TWCR = _BV(TWINT) | _BV(TWSTA) | _BV(TWEN);
    if (!twi_wait()) {
        return false;
    }
    const uint8_t st = TW_STATUS;
    if (st != TW_START && st != TW_REP_START) {
        return false;
    }
    TWDR = address_rw;
    TWCR = _BV(TWINT) | _BV(TWEN);
    if (!twi_wait()) {
        return false;
    }
    const uint8_t st2 = TW_STATUS;
    if ((address_rw & 1u) != 0u) {
        return st2 == TW_MR_SLA_ACK;
    }
    /* SLA+W acknowledged. simavr 1.6 reports 0x28 (data ACK) here instead of
     * 0x18; on the chip 0x28 cannot follow an address byte, and it means an
     * ACK all the same. */
    return st2 == TW_MT_SLA_ACK || st2 == TW_MT_DATA_ACK;
}

static bool twi_write(uint8_t byte)
{
    TWDR = byte;
    TWCR = _BV(TWINT) | _BV(TWEN);
    return twi_wait() && TW_STATUS == TW_MT_DATA_ACK;
}

static bool twi_read(uint8_t *byte, bool ack)
{
    TWCR = (uint8_t)(_BV(TWINT) | _BV(TWEN) | (ack ? _BV(TWEA) : 0u));
    if (!twi_wait()) {
        return false;
    }
    *byte = TWDR;
    return TW_STATUS == (ack ? TW_MR_DATA_ACK : TW_MR_DATA_NACK);
}

static bool mpu_write_reg(uint8_t reg, uint8_t value)
{
    const bool ok = twi_start((uint8_t)(HAL_IMU_ADDRESS << 1)) && twi_write(reg) && twi_write(value);
    twi_stop();
    return ok;
}

static bool mpu_read(uint8_t reg, uint8_t *buf, uint8_t n)
{
    bool ok = twi_start((uint8_t)(HAL_IMU_ADDRESS << 1)) && twi_write(reg) &&
              twi_start((uint8_t)((HAL_IMU_ADDRESS << 1) | 1u));
    for (uint8_t i = 0u; ok && i < n; i++) {
        ok = twi_read(&buf[i], i + 1u < n);
    }
    twi_stop();
    return ok;
}

/* ---- device ------------------------------------------------------------ */

static bool mpu_configure(void)
{
    uint8_t who = 0u;
    if (!mpu_write_reg(MPU_PWR_MGMT_1, 0x01u)) { /* awake, clock from the X gyro PLL */
        return false;
    }
    if (!mpu_read(MPU_WHO_AM_I, &who, 1u)) {
        return false;
    }
    /* MPU-6050/6000 0x68; register-compatible 6500 0x70, 9250 0x71, 9255 0x73 */
    if (who != 0x68u && who != 0x70u && who != 0x71u && who != 0x73u) {
        return false;
    }
    return mpu_write_reg(MPU_SMPLRT_DIV, 0x00u) &&   /* 1 kHz with the DLPF on */
           mpu_write_reg(MPU_CONFIG, 0x03u) &&       /* DLPF 44 Hz accel / 42 Hz gyro */
           mpu_write_reg(MPU_GYRO_CONFIG, 0x18u) &&  /* +-2000 deg/s */
           mpu_write_reg(MPU_ACCEL_CONFIG, 0x10u);   /* +-8 g */
}

bool hal_imu_init(void)
{
    /* SCL = F_CPU / (16 + 2 TWBR 4^TWPS): TWBR 12, prescaler 1 -> 400 kHz */
    TWSR = 0u;
    TWBR = (uint8_t)((F_CPU / HAL_IMU_TWI_HZ - 16UL) / 2UL);
    TWCR = _BV(TWEN);
    s_present = mpu_configure();
    s_fails = 0u;
    s_retry_countdown = HAL_IMU_RETRY_READS;
    return s_present;
}

/* ---- the burst read, driven by the TWI interrupt ------------------------ */

/* The transfer: START, SLA+W, the register, repeated START, SLA+R, then the
 * HAL_IMU_BURST_BYTES data bytes, ACK on each but the last, and STOP. Each
 * TWI event (TWINT) runs one step of this state machine in TWI_vect; no step
 * waits on the bus. */
typedef enum burst_phase {
    PHASE_START,   /* START sent */
    PHASE_SLA_W,   /* SLA+W sent */
    PHASE_REGISTER, /* the register sent */
    PHASE_RESTART, /* repeated START sent */
    PHASE_SLA_R,   /* SLA+R sent */
    PHASE_DATA,    /* a data byte on its way */
} burst_phase;

typedef enum burst_state {
    BURST_IDLE,   /* nothing started since the last take */
    BURST_BUSY,   /* on the bus */
    BURST_DONE,   /* every byte in s_burst_bytes */
    BURST_FAILED, /* a NACK or an unexpected status: STOP sent */
} burst_state;

static volatile uint8_t s_burst_state = BURST_IDLE; /* burst_state */
static uint8_t s_burst_phase;                       /* burst_phase, the ISR's own */
static uint8_t s_burst_count;                       /* data bytes in, the ISR's own */
static uint8_t s_burst_bytes[HAL_IMU_BURST_BYTES];  /* the ISR's until BURST_DONE */

/* TWCR for the next event with the interrupt on */
#define TWCR_NEXT (_BV(TWINT) | _BV(TWEN) | _BV(TWIE))

static void burst_end(uint8_t state)
{
    TWCR = _BV(TWINT) | _BV(TWEN) | _BV(TWSTO); /* STOP, the interrupt off */
    s_burst_state = state;
}

/* The read asks for ACK on every byte but the last. */
static void burst_next_data(void)
{
    TWCR = (uint8_t)(TWCR_NEXT | (s_burst_count + 1u < HAL_IMU_BURST_BYTES ? _BV(TWEA) : 0u));
}

ISR(TWI_vect)
{
    const uint8_t st = TW_STATUS;
    switch (s_burst_phase) {
    case PHASE_START:
        if (st != TW_START) {
            break;
        }
        TWDR = (uint8_t)(HAL_IMU_ADDRESS << 1);
        s_burst_phase = PHASE_SLA_W;
        TWCR = TWCR_NEXT;
        return;
    case PHASE_SLA_W:
        /* simavr 1.6 reports 0x28 here for 0x18: the same ACK (twi_start) */
        if (st != TW_MT_SLA_ACK && st != TW_MT_DATA_ACK) {
            break;
        }
        TWDR = MPU_ACCEL_XOUT_H;
        s_burst_phase = PHASE_REGISTER;
        TWCR = TWCR_NEXT;
        return;
    case PHASE_REGISTER:
        if (st != TW_MT_DATA_ACK) {
            break;
        }
        s_burst_phase = PHASE_RESTART;
        TWCR = TWCR_NEXT | _BV(TWSTA);
        return;
    case PHASE_RESTART:
        if (st != TW_REP_START) {
            break;
        }
        TWDR = (uint8_t)((HAL_IMU_ADDRESS << 1) | 1u);
        s_burst_phase = PHASE_SLA_R;
        TWCR = TWCR_NEXT;
        return;
    case PHASE_SLA_R:
        if (st != TW_MR_SLA_ACK) {
            break;
        }
        s_burst_phase = PHASE_DATA;
        burst_next_data();
        return;
    case PHASE_DATA: {
        const bool last = s_burst_count + 1u >= HAL_IMU_BURST_BYTES;
        if (st != (last ? TW_MR_DATA_NACK : TW_MR_DATA_ACK)) {
            break;
        }
        s_burst_bytes[s_burst_count++] = TWDR;
        if (last) {
            burst_end(BURST_DONE);
        } else {
            burst_next_data();
        }
        return;
    }
    default:
        break;
    }
    burst_end(BURST_FAILED);
}

void hal_imu_start_read(void)
{
    if (!s_present || s_burst_state == BURST_BUSY) {
        return; /* absent: hal_imu_read probes it; busy: hal_imu_read ends it */
    }
    s_burst_phase = PHASE_START;
    s_burst_count = 0u;
    s_burst_state = BURST_BUSY;
    TWCR = TWCR_NEXT | _BV(TWSTA);
}

/* The burst's outcome, and the bus left idle for the next one. A transfer
 * still on the bus has overrun its lead (SCL held, the device stretching
 * the clock): the hardware is released, as twi_wait does. */
static burst_state burst_take(hal_imu_raw *raw)
{
    const uint8_t sreg = SREG;
    __asm__ __volatile__("cli" ::: "memory");
    const burst_state state = (burst_state)s_burst_state;
    if (state == BURST_BUSY) {
        TWCR = 0u;
        TWCR = _BV(TWEN);
    }
    s_burst_state = BURST_IDLE;
    SREG = sreg;
    if (state == BURST_DONE) {
        for (uint8_t i = 0u; i < 3u; i++) {
            raw->accel[i] = (int16_t)(((uint16_t)s_burst_bytes[2u * i] << 8) | s_burst_bytes[2u * i + 1u]);
            raw->gyro[i] = (int16_t)(((uint16_t)s_burst_bytes[8u + 2u * i] << 8) | s_burst_bytes[9u + 2u * i]);
        }
    }
    return state;
}

bool hal_imu_read(hal_imu_raw *raw)
{
    if (!s_present) {
        if (--s_retry_countdown != 0u) {
            return false;
        }
        s_retry_countdown = HAL_IMU_RETRY_READS;
        /* polled, with the TWI interrupt off: no burst starts while absent */
        s_present = mpu_configure();
        s_fails = 0u;
        return false; /* the first burst starts at the next lead */
    }
    const burst_state state = burst_take(raw);
    if (state == BURST_DONE) {
        s_fails = 0u;
        return true;
    }
    if (state != BURST_IDLE && ++s_fails >= FAILS_BEFORE_ABSENT) {
        s_present = false;
        s_retry_countdown = HAL_IMU_RETRY_READS;
    }
    return false;
}

/* Chip axes = body axes (FLU) with the mounting of hal_imu.h. In fixed a
 * count times the LSB constant is an int32 product: at most 32768 * 17855
 * (gyro, RATE Q24) and 32768 * 10042 (accel, ACCEL Q22), below 2^31. */
void hal_imu_to_sample(const hal_imu_raw *raw, fc_imu_sample *sample)
{
    sample->gyro_radps.x = (fc_real)raw->gyro[0] * GYRO_LSB_RADPS;
    sample->gyro_radps.y = (fc_real)raw->gyro[1] * GYRO_LSB_RADPS;
    sample->gyro_radps.z = (fc_real)raw->gyro[2] * GYRO_LSB_RADPS;
    sample->accel_mps2.x = (fc_real)raw->accel[0] * ACCEL_LSB_MPS2;
    sample->accel_mps2.y = (fc_real)raw->accel[1] * ACCEL_LSB_MPS2;
    sample->accel_mps2.z = (fc_real)raw->accel[2] * ACCEL_LSB_MPS2;
}

void hal_imu_at_rest(fc_imu_sample *sample)
{
    sample->gyro_radps.x = FC_INT(0, RATE);
    sample->gyro_radps.y = FC_INT(0, RATE);
    sample->gyro_radps.z = FC_INT(0, RATE);
    sample->accel_mps2.x = FC_INT(0, ACCEL);
    sample->accel_mps2.y = FC_INT(0, ACCEL);
    sample->accel_mps2.z = FC_C(9.81f, ACCEL);
}

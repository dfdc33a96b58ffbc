/*
 * main.c - the ATmega2560 flight-control image: a timer-driven fixed-step loop
 * around fc_controller_step.
 *
 *   Timer1 (CTC)   the loop tick at FC_ATMEGA_LOOP_HZ (compare A): its interrupt
 *                  stamps the time and counts the tick; the loop sleeps (idle,
 *                  interrupts on) until the next one. Compare B, the IMU
 *                  read's lead ahead of the tick, starts the burst read
 *   TWI            MPU-6050, the burst driven by its interrupt (hal_imu.h)
 *   Timer3         free-running at clk/1: the cycle counter (hal_clock.h)
 *   Timer4/Timer5  ESC PWM (hal_esc.h)
 *   USART0         telemetry out, arm/disarm commands in (hal_uart.h, telemetry.h)
 *
 * One iteration: take the IMU sample read since compare B, build fc_controller_inputs, fc_controller_step,
 * write the ESCs, and every TM_FRAME_LOOPS iterations queue a telemetry frame.
 * The watchdog (250 ms, from the first iteration on) resets the chip if the
 * loop stops; after any reset the ESCs see 1000 us again from hal_esc_init.
 * The work is timed from the tick to its end; longer than the period is a
 * deadline overrun (counted, with ticks that were missed altogether). The
 * controller step alone is timed too (the benchmark figure).
 *
 * The library is called through its entry point only (fc/controller.h):
 * fc_controller_step on a controller that fc_controller_init set up for the
 * build's parameters (controller_setup.h). The image holds that controller
 * as a snapshot made at build time (controller_snapshot.h) and copies it
 * from flash at boot, so it links none of the init code; a build without
 * simavr (no snapshot) runs fc_controller_init at boot instead. No
 * soft-float in the fixed image: constants are FC_C/FC_INT, conversions to
 * us and mN are integer arithmetic.
 *
 * Arming: the image starts disarmed (command DISARM, ESCs at 1000 us) and arms
 * on "ARM1" over USART0 ("ARM0" disarms), once the controller's own arming
 * checks pass (the attitude filter aligned: 2 s; telemetry's armed
 * bit is the controller's). It refuses to arm while the IMU
 * read fails and disarms after 0.1 s of IMU loss; while the IMU is missing
 * the controller keeps stepping on the at-rest sample (hal_imu_at_rest), so
 * the estimator stays defined and the loop keeps its rate. There is no
 * navigation HAL yet: position, velocity and the pad are held at placeholders
 * (hover at the reference's start over a still pad), so an armed image is a
 * bench run with the propellers off until a position source exists.
 *
 * FC_ATMEGA_SIMAVR=1 (fc-atmega-sim.elf) only adds simavr's .mmcu section
 * (MCU and F_CPU, so plain `simavr fc-atmega-sim.elf` runs it, and a console
 * register that prints the boot lines); the code is the same. The flight
 * image fc-atmega.elf has no trace of simavr.
 */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <avr/wdt.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>
#include <util/crc16.h>

#include "controller_setup.h"
#include "fc/controller.h"
#include "hal_clock.h"
#include "hal_esc.h"
#include "hal_imu.h"
#include "hal_uart.h"
#include "telemetry.h"

/* ---- build configuration ------------------------------------------------ */

#ifndef FC_ATMEGA_SIMAVR
#define FC_ATMEGA_SIMAVR 0
#endif

/* 1: the controller comes from the build-time snapshot (CMakeLists.txt sets
 * it when simavr is there to make one) */
#ifndef FC_ATMEGA_SNAPSHOT
#define FC_ATMEGA_SNAPSHOT 0
#endif
#if FC_ATMEGA_SNAPSHOT
#include "controller_snapshot.h"
#endif

#define PERIOD_CYCLES (F_CPU / FC_ATMEGA_LOOP_HZ)
#if PERIOD_CYCLES <= 65536UL
#define TIMER1_PRESCALER 1UL
#define TIMER1_CS _BV(CS10)
#elif PERIOD_CYCLES <= 8UL * 65536UL
#define TIMER1_PRESCALER 8UL
#define TIMER1_CS _BV(CS11)
#elif PERIOD_CYCLES <= 64UL * 65536UL
#define TIMER1_PRESCALER 64UL
#define TIMER1_CS (_BV(CS11) | _BV(CS10))
#else
#error "FC_ATMEGA_LOOP_HZ below 4 Hz: Timer1 cannot count the period"
#endif
#if F_CPU % (FC_ATMEGA_LOOP_HZ * TIMER1_PRESCALER) != 0
#error "FC_ATMEGA_LOOP_HZ must divide F_CPU / prescaler exactly: dt must be exact"
#endif
/* the IMU burst's start, in Timer1 counts before the tick */
#define IMU_LEAD_COUNTS (HAL_IMU_READ_LEAD_US * (F_CPU / 1000000UL) / TIMER1_PRESCALER)
#if IMU_LEAD_COUNTS * 2UL >= PERIOD_CYCLES / TIMER1_PRESCALER
#error "FC_ATMEGA_LOOP_HZ too high: the IMU read's lead would take half the period"
#endif

/* a telemetry frame every ceil(rate / 20) loops: at most 20 frames/s */
#define TM_FRAME_LOOPS ((FC_ATMEGA_LOOP_HZ + 19) / 20)
/* disarm after 0.1 s without the IMU */
#define IMU_LOSS_DISARM_LOOPS ((FC_ATMEGA_LOOP_HZ + 9) / 10)

#if FC_ATMEGA_SIMAVR
#include "avr_mcu_section.h"
AVR_MCU(F_CPU, "atmega2560");
AVR_MCU_SIMAVR_CONSOLE(&GPIOR0);
#endif

/* ---- state (platform code may have globals; the library has none) ------ */

static fc_controller g_ctl; /* every module's state, the allocation for 8 rotors */
static fc_controller_inputs g_in;
static fc_controller_outputs g_out;

static volatile uint16_t s_ticks;       /* Timer1 compare matches */
static volatile uint32_t s_tick_cycles; /* hal_clock at the latest one */

ISR(TIMER1_COMPA_vect)
{
    s_tick_cycles = hal_clock_cycles();
    s_ticks++;
}

/* the IMU's lead before the tick: its burst finishes by the tick */
ISR(TIMER1_COMPB_vect)
{
    hal_imu_start_read();
}

/* Before anything else (.init3, ahead of .data/.bss setup): a watchdog reset
 * leaves the watchdog running, so it is switched off here or it would reset
 * again during the boot (fc_controller_init, in a build without the
 * snapshot). */
void early_watchdog_off(void) __attribute__((naked, used, section(".init3")));
void early_watchdog_off(void)
{
    MCUSR = 0u;
    wdt_disable();
}

static void loop_timer_start(void)
{
    TCCR1A = 0u;
    TCCR1B = 0u;
    TCNT1 = 0u;
    OCR1A = (uint16_t)(PERIOD_CYCLES / TIMER1_PRESCALER - 1UL);
    OCR1B = (uint16_t)(PERIOD_CYCLES / TIMER1_PRESCALER - 1UL - IMU_LEAD_COUNTS);
    TIFR1 = _BV(OCF1A) | _BV(OCF1B);
    TIMSK1 = _BV(OCIE1A) | _BV(OCIE1B);
    TCCR1B = _BV(WGM12) | TIMER1_CS; /* CTC, TOP = OCR1A */
}

/* Sleep (idle: timers and the UART keep running) until the tick count moves
 * on from last; returns the new count. sei; sleep runs the sleep before any
 * interrupt, so a tick cannot slip in between the test and the sleep. */
static uint16_t wait_tick(uint16_t last)
{
    for (;;) {
        cli();
        const uint16_t now = s_ticks;
        if (now != last) {
            sei();
            return now;
        }
        sleep_enable();
        sei();
        sleep_cpu();
        sleep_disable();
    }
}

static void console_line(const char *s)
{
#if FC_ATMEGA_SIMAVR
    for (const char *c = s; *c != '\0'; c++) {
        GPIOR0 = (uint8_t)*c;
    }
    GPIOR0 = '\r';
#else
    (void)s;
#endif
}

/* ---- conversions (integer in fixed: no soft-float) ----------------------- */

/* Normalised rotor speed (UNIT, 0..1) to an ESC pulse of 1000..2000 us. */
static uint16_t speed_to_us(fc_real speed)
{
#if FC_NUMERIC_FIXED
    if (speed <= 0) {
        return HAL_ESC_US_OFF;
    }
    if (speed >= FC_INT(1, UNIT)) {
        return HAL_ESC_US_MAX;
    }
    /* Q30 -> Q16, times 1000 us: at most 65536 * 1000 < 2^32 */
    const uint32_t q16 = (uint32_t)speed >> (FC_UNIT_FRAC - 16);
    return (uint16_t)(HAL_ESC_US_OFF + (uint16_t)((q16 * 1000UL + 32768UL) >> 16));
#else
    if (!(speed > 0.0f)) { /* also NaN */
        return HAL_ESC_US_OFF;
    }
    if (speed >= 1.0f) {
        return HAL_ESC_US_MAX;
    }
    return (uint16_t)(HAL_ESC_US_OFF + (uint16_t)(speed * 1000.0f + 0.5f));
#endif
}

/* FORCE to mN for telemetry. */
static int32_t force_to_mn(fc_real force)
{
#if FC_NUMERIC_FIXED
    /* Q20 * 1000 / 2^20 = (x / 2^7) * 125 / 2^10; |x / 2^7| < 2^24 keeps it in int32 */
    return ((force >> 7) * 125L) >> 10;
#else
    if (!(force > -1.0e6f && force < 1.0e6f)) {
        return 0;
    }
    return (int32_t)(force * 1000.0f);
#endif
}

/* ---- telemetry ----------------------------------------------------------- */

typedef struct loop_stats {
    uint32_t loops;
    uint16_t overruns;
    uint16_t imu_errors;
    uint32_t loop_cycles_worst;  /* since start */
    uint32_t loop_cycles_window; /* since the last frame */
    uint32_t step_cycles_min;    /* window */
    uint32_t step_cycles_max;    /* window */
    uint32_t init_cycles;
    bool overrun_in_window;
    bool tx_dropped;
} loop_stats;

static void put16(uint8_t *f, uint8_t off, uint16_t v)
{
    f[off] = (uint8_t)v;
    f[off + 1u] = (uint8_t)(v >> 8);
}

static void put32(uint8_t *f, uint8_t off, uint32_t v)
{
    put16(f, off, (uint16_t)v);
    put16(f, (uint8_t)(off + 2u), (uint16_t)(v >> 16));
}

static void window_reset(loop_stats *s)
{
    s->loop_cycles_window = 0u;
    s->step_cycles_min = UINT32_MAX;
    s->step_cycles_max = 0u;
    s->overrun_in_window = false;
}

static void send_frame(loop_stats *s, fc_step_status fc_status, uint8_t status, const uint16_t *esc_us)
{
    uint8_t f[TM_FRAME_SIZE];
    f[TM_OFF_SYNC0] = TM_SYNC0;
    f[TM_OFF_SYNC1] = TM_SYNC1;
    f[TM_OFF_LENGTH] = TM_LENGTH;
    f[TM_OFF_VERSION] = TM_VERSION;
    put32(f, TM_OFF_LOOP_COUNT, s->loops);
    put16(f, TM_OFF_LOOP_HZ, FC_ATMEGA_LOOP_HZ);
    put16(f, TM_OFF_OVERRUNS, s->overruns);
    put32(f, TM_OFF_LOOP_CYCLES_WORST, s->loop_cycles_worst);
    put32(f, TM_OFF_LOOP_CYCLES_WINDOW, s->loop_cycles_window);
    put32(f, TM_OFF_STEP_CYCLES_MIN, s->step_cycles_min);
    put32(f, TM_OFF_STEP_CYCLES_MAX, s->step_cycles_max);
    put32(f, TM_OFF_INIT_CYCLES, s->init_cycles);
    put16(f, TM_OFF_FC_STATUS, fc_status);
    if (s->overrun_in_window) {
        status |= TM_STATUS_OVERRUN;
    }
    if (s->tx_dropped) {
        status |= TM_STATUS_TX_DROPPED;
    }
    f[TM_OFF_STATUS] = status;
    f[TM_OFF_ROTOR_COUNT] = g_out.rotor_count;
    put32(f, TM_OFF_THRUST_MN, (uint32_t)force_to_mn(g_out.thrust_n));
    for (uint8_t ch = 0u; ch < TM_ESC_CHANNELS; ch++) {
        put16(f, (uint8_t)(TM_OFF_ESC_US + 2u * ch), esc_us[ch]);
    }
    put16(f, TM_OFF_IMU_ERRORS, s->imu_errors);
    uint8_t crc = 0u;
    for (uint8_t i = TM_OFF_LENGTH; i < TM_OFF_CRC; i++) {
        crc = _crc8_ccitt_update(crc, f[i]);
    }
    f[TM_OFF_CRC] = crc;
    if (!hal_uart_write(f, TM_FRAME_SIZE)) {
        s->tx_dropped = true; /* never wait: the deadline comes first */
    }
    window_reset(s);
}

/* ---- setup ----------------------------------------------------------------- */

#if FC_ATMEGA_SNAPSHOT
/* g_ctl from the snapshot's records (controller_snapshot.h): zero, then each
 * record's bytes after its zeros. An empty record, or one that would run
 * past g_ctl, ends the copy (avr_snapshot writes none such;
 * atmega.snapshot_boot checks the result byte for byte). */
static void controller_from_snapshot(void)
{
    uint8_t *const ctl = (uint8_t *)&g_ctl;
    memset(ctl, 0, sizeof g_ctl);
    const uint8_t *rec = fc_atmega_controller_snapshot;
    uint16_t at = 0u;
    while (at < sizeof g_ctl) {
        const uint8_t skip = pgm_read_byte(rec);
        const uint8_t n = pgm_read_byte(rec + 1);
        rec += 2;
        if ((skip | n) == 0u || skip > sizeof g_ctl - at || n > sizeof g_ctl - at - skip) {
            break;
        }
        at = (uint16_t)(at + skip);
        memcpy_P(ctl + at, rec, n);
        at = (uint16_t)(at + n);
        rec += n;
    }
}
#endif

/* g_ctl as fc_controller_init leaves it for the build's parameters. With the
 * snapshot: from flash; its init ran at build time, and one that failed
 * failed the build (avr_snapshot), so the result is FC_INIT_OK. Without:
 * fc_controller_init here, the parameters on this frame only (init copies
 * them into g_ctl), so they take no RAM once the loop runs. */
static __attribute__((noinline)) fc_init_result controller_setup(void)
{
#if FC_ATMEGA_SNAPSHOT
    controller_from_snapshot();
    return FC_INIT_OK;
#else
    fc_controller_params p;
    fc_atmega_params(&p);
    return fc_controller_init(&g_ctl, &p);
#endif
}

/* Placeholders until a navigation HAL exists: hover at the reference's start
 * (1 m + the 0.18 m gear height) straight above a pad that does not move. */
static void inputs_setup(fc_controller_inputs *in)
{
    in->attitude_external = fc_quat_make(FC_INT(1, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT));
    in->position_m = fc_vec3_make(FC_INT(0, LENGTH), FC_INT(0, LENGTH), FC_C(1.18f, LENGTH));
    in->velocity_mps = fc_vec3_make(FC_INT(0, VEL), FC_INT(0, VEL), FC_INT(0, VEL));
    in->pad.z_m = FC_INT(0, LENGTH);
    in->pad.vz_mps = FC_INT(0, VEL);
    in->pad.az_mps2 = FC_INT(0, ACCEL);
    in->position_setpoint_m = fc_vec3_make(FC_INT(0, LENGTH), FC_INT(0, LENGTH), FC_INT(0, LENGTH));
    in->yaw_setpoint_rad = FC_INT(0, ANGLE);
    in->command = FC_COMMAND_DISARM;
    hal_imu_at_rest(&in->imu);
}

int main(void)
{
    hal_clock_init();
    hal_esc_init(); /* ESCs see 1000 us from here on */
    hal_uart_init();
    set_sleep_mode(SLEEP_MODE_IDLE);
    sei();

#if FC_NUMERIC_FIXED
    static const char banner[] = "fc-atmega: fixed";
#else
    static const char banner[] = "fc-atmega: float";
#endif
    console_line(banner);
    hal_uart_write_string_blocking(banner);
    hal_uart_write_string_blocking("\r\n");

    bool imu_ok = hal_imu_init();

    loop_stats stats = {0};
    window_reset(&stats);
    const uint32_t init_start = hal_clock_cycles();
    const fc_init_result init = controller_setup();
    stats.init_cycles = hal_clock_cycles() - init_start;
    inputs_setup(&g_in);
    console_line(init == FC_INIT_OK ? "controller ready" : "controller init FAILED");

    const uint8_t status_const = (uint8_t)((FC_NUMERIC_FIXED ? TM_STATUS_FIXED : 0u) |
                                           (FC_ATMEGA_SIMAVR ? TM_STATUS_SIMAVR : 0u) |
                                           (init != FC_INIT_OK ? TM_STATUS_INIT_FAILED : 0u));
    bool armed = false;
    uint16_t imu_fail_streak = 0u;
    uint16_t esc_us[TM_ESC_CHANNELS];
    fc_step_status fc_status = FC_STEP_OK;
    uint8_t frame_countdown = TM_FRAME_LOOPS;

    loop_timer_start();
    wdt_enable(WDTO_250MS);
    uint16_t seen = 0u;
    for (;;) {
        const uint16_t now = wait_tick(seen);
        wdt_reset();
        const uint16_t elapsed = (uint16_t)(now - seen);
        seen = now;
        cli();
        const uint32_t tick_cycles = s_tick_cycles;
        sei();
        if (elapsed > 1u) {
            /* ticks that found the previous iteration still working */
            stats.overruns = (uint16_t)(stats.overruns + (elapsed - 1u));
            stats.overrun_in_window = true;
        }

        /* sensors */
        hal_imu_raw raw;
        imu_ok = hal_imu_read(&raw);
        if (imu_ok) {
            hal_imu_to_sample(&raw, &g_in.imu);
            imu_fail_streak = 0u;
        } else {
            hal_imu_at_rest(&g_in.imu);
            stats.imu_errors++;
            if (imu_fail_streak < UINT16_MAX) {
                imu_fail_streak++;
            }
        }

        /* command */
        const hal_uart_command cmd = hal_uart_take_command();
        if (cmd == HAL_UART_CMD_ARM && init == FC_INIT_OK && imu_ok) {
            armed = true;
        } else if (cmd == HAL_UART_CMD_DISARM) {
            armed = false;
        }
        if (imu_fail_streak >= IMU_LOSS_DISARM_LOOPS) {
            armed = false;
        }
        g_in.command = armed ? FC_COMMAND_TRACK_PAD : FC_COMMAND_DISARM;

        /* control */
        const uint32_t step_start = hal_clock_cycles();
        fc_status = fc_controller_step(&g_ctl, &g_in, &g_out);
        const uint32_t step_cycles = hal_clock_cycles() - step_start;

        /* actuators */
        for (uint8_t ch = 0u; ch < TM_ESC_CHANNELS; ch++) {
            const bool driven = armed && g_out.motors_on && ch < g_out.rotor_count;
            esc_us[ch] = driven ? speed_to_us(g_out.rotor_speed[ch]) : HAL_ESC_US_OFF;
            hal_esc_write_us(ch, esc_us[ch]);
        }

        /* bookkeeping and telemetry */
        stats.loops++;
        if (step_cycles < stats.step_cycles_min) {
            stats.step_cycles_min = step_cycles;
        }
        if (step_cycles > stats.step_cycles_max) {
            stats.step_cycles_max = step_cycles;
        }
        if (--frame_countdown == 0u) {
            frame_countdown = TM_FRAME_LOOPS;
            const uint8_t status = (uint8_t)(status_const | (imu_ok ? 0u : TM_STATUS_IMU_ERROR) |
                                             (armed && g_out.telemetry.armed ? TM_STATUS_ARMED : 0u) |
                                             (armed && g_out.motors_on ? TM_STATUS_MOTORS_ON : 0u));
            send_frame(&stats, fc_status, status, esc_us);
        }

        /* deadline: the work, tick to here, against the period */
        const uint32_t work = hal_clock_cycles() - tick_cycles;
        if (work > PERIOD_CYCLES) {
            stats.overruns++;
            stats.overrun_in_window = true;
        }
        if (work > stats.loop_cycles_worst) {
            stats.loop_cycles_worst = work;
        }
        if (work > stats.loop_cycles_window) {
            stats.loop_cycles_window = work;
        }
    }
}

/*
 * avr_loop_test.c - runs the ATmega image in simavr and checks its loop.
 *
 * A host program linked with libsimavr and libelf. It loads the ELF into an
 * ATmega2560 at 16 MHz (from the ELF's .mmcu section when there is one, else
 * from --mcu/--freq), runs it for --seconds of simulated time one instruction
 * at a time (simavr's real-time sleep switched off), and
 *   - captures USART0 output (UART_IRQ_OUTPUT) and parses the telemetry
 *     frames of telemetry.h (sync, length, CRC-8), stamping each with the
 *     simulated cycle of its last byte;
 *   - with --arm, sends "ARM1" into USART0 (UART_IRQ_INPUT) once the first
 *     frame has arrived;
 *   - with --imu, puts a virtual MPU-6050 on the TWI bus (address 0x68, a
 *     moving sample); --imu-off-at S makes it stop answering at S seconds;
 *   - times every call of fc_controller_step (and of each --time NAME) from
 *     outside: the address comes from the ELF's symbol table; a call starts
 *     when the PC reaches it and ends when the PC reaches the return address
 *     pushed by the CALL with the stack pointer back above it (interrupts
 *     taken inside count, as on the chip);
 *   - tracks the lowest stack pointer, for the stack's peak depth;
 *   - with --profile N, lists the N functions with the most cycles of their
 *     own inside the timed calls (libgcc's routines included).
 * Then it checks: the loop started (frames arrive, the loop counter rises);
 * the counter rises at --rate (from the frames' cycle stamps, within 0.5 %
 * or two loops); the telemetry reports that rate and arrives at its rate;
 * the worst iteration's cycles (the image's own Timer3 count) are below the
 * period F_CPU / rate and there were no overruns; fc_controller_step timed
 * from outside stays below the period and agrees with the image's own
 * figures; the image armed (--expect armed: motors on, ESC pulses in range)
 * or stayed disarmed (--expect disarmed: ESCs at 1000 us); the IMU was
 * configured and read once a loop, or its absence or loss was handled (error
 * bit, no arming, disarm within 0.1 s); the stack stays clear of the static
 * data.
 *
 * It prints the benchmark figure: cycles per fc_controller_step call, min,
 * max and mean, over the calls after arming (or all calls after the first
 * frame), and RAM use. Exit status 0 when every check passes.
 */
#include <fcntl.h>
#include <math.h>
#include <gelf.h>
#include <libelf.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "avr_twi.h"
#include "avr_uart.h"
#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_io.h"
#include "sim_irq.h"

#include "telemetry.h"
#include "sim_support.h"

#define MAX_FRAMES 4096
#define MAX_CALLS 50000
#define MAX_TIMED 16

typedef struct frame {
    uint64_t cycle; /* simulated cycle of the last byte */
    uint32_t loops;
    uint16_t loop_hz;
    uint16_t overruns;
    uint32_t loop_cycles_worst;
    uint32_t loop_cycles_window;
    uint32_t step_min, step_max;
    uint32_t init_cycles;
    uint16_t fc_status;
    uint8_t status;
    uint8_t rotor_count;
    int32_t thrust_mn;
    uint16_t esc_us[TM_ESC_CHANNELS];
    uint16_t imu_errors;
} frame;

typedef struct call {
    uint64_t start;
    uint32_t cycles;
} call;

/* A function timed from outside: entry when the PC reaches its address, exit
 * when the PC reaches the return address with the stack pointer back above it. */
typedef struct timed_fn {
    const char *name;
    sim_call_timer timer;
    call *calls;
    unsigned ncalls;
} timed_fn;

static timed_fn g_timed[MAX_TIMED];
static unsigned g_ntimed;

static void timed_track(avr_t *avr, uint16_t sp)
{
    for (unsigned k = 0; k < g_ntimed; k++) {
        timed_fn *t = &g_timed[k];
        const int64_t cycles = sim_call_timer_at(&t->timer, avr, avr->pc, sp, true);
        if (cycles >= 0 && t->ncalls < MAX_CALLS) {
            t->calls[t->ncalls].start = t->timer.start;
            t->calls[t->ncalls].cycles = (uint32_t)cycles;
            t->ncalls++;
        }
    }
}

/* min, max and mean cycles of the calls of t that started in [from, to) */
static unsigned timed_stats(const timed_fn *t, uint64_t from, uint64_t to, uint32_t *min, uint32_t *max,
                            double *mean)
{
    unsigned n = 0;
    double sum = 0.0;
    *min = UINT32_MAX;
    *max = 0;
    for (unsigned i = 0; i < t->ncalls; i++) {
        if (t->calls[i].start >= from && t->calls[i].start < to) {
            const uint32_t c = t->calls[i].cycles;
            *min = c < *min ? c : *min;
            *max = c > *max ? c : *max;
            sum += c;
            n++;
        }
    }
    *mean = n > 0 ? sum / n : 0.0;
    return n;
}

static struct {
    avr_t *avr;
    /* telemetry parser */
    uint8_t buf[TM_FRAME_SIZE];
    unsigned have;
    unsigned bad_crc;
    unsigned text_bytes;
    frame frames[MAX_FRAMES];
    unsigned nframes;
} g;

static int failures;

static void check(bool ok, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    printf("%s: ", ok ? "ok  " : "FAIL");
    vprintf(fmt, ap);
    printf("\n");
    va_end(ap);
    if (!ok) {
        failures++;
    }
}

static uint16_t le16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)le16(p) | ((uint32_t)le16(p + 2) << 16);
}

static uint8_t crc8(const uint8_t *p, unsigned n)
{
    uint8_t crc = 0;
    for (unsigned i = 0; i < n; i++) {
        crc ^= p[i];
        for (int b = 0; b < 8; b++) {
            crc = (uint8_t)((crc & 0x80u) != 0u ? ((unsigned)crc << 1) ^ 0x07u : (unsigned)crc << 1);
        }
    }
    return crc;
}

static void frame_complete(void)
{
    const uint8_t *b = g.buf;
    if (crc8(b + TM_OFF_LENGTH, TM_OFF_CRC - TM_OFF_LENGTH) != b[TM_OFF_CRC]) {
        g.bad_crc++;
        return;
    }
    if (g.nframes >= MAX_FRAMES) {
        return;
    }
    frame *f = &g.frames[g.nframes++];
    f->cycle = g.avr->cycle;
    f->loops = le32(b + TM_OFF_LOOP_COUNT);
    f->loop_hz = le16(b + TM_OFF_LOOP_HZ);
    f->overruns = le16(b + TM_OFF_OVERRUNS);
    f->loop_cycles_worst = le32(b + TM_OFF_LOOP_CYCLES_WORST);
    f->loop_cycles_window = le32(b + TM_OFF_LOOP_CYCLES_WINDOW);
    f->step_min = le32(b + TM_OFF_STEP_CYCLES_MIN);
    f->step_max = le32(b + TM_OFF_STEP_CYCLES_MAX);
    f->init_cycles = le32(b + TM_OFF_INIT_CYCLES);
    f->fc_status = le16(b + TM_OFF_FC_STATUS);
    f->status = b[TM_OFF_STATUS];
    f->rotor_count = b[TM_OFF_ROTOR_COUNT];
    f->thrust_mn = (int32_t)le32(b + TM_OFF_THRUST_MN);
    for (int ch = 0; ch < TM_ESC_CHANNELS; ch++) {
        f->esc_us[ch] = le16(b + TM_OFF_ESC_US + 2 * ch);
    }
    f->imu_errors = le16(b + TM_OFF_IMU_ERRORS);
}

/* USART0 output, one byte per call: find sync, length and version, collect
 * the frame, check its CRC. Other bytes (the boot banner) are skipped. */
static void uart_out_hook(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    const uint8_t c = (uint8_t)value;
    if (g.have == 0) {
        if (c == TM_SYNC0) {
            g.buf[g.have++] = c;
        } else {
            g.text_bytes++;
        }
        return;
    }
    g.buf[g.have++] = c;
    if ((g.have == 2 && c != TM_SYNC1) || (g.have == 3 && c != TM_LENGTH) ||
        (g.have == 4 && c != TM_VERSION)) {
        g.have = (c == TM_SYNC0) ? 1 : 0;
        if (c == TM_SYNC0) {
            g.buf[0] = c;
        }
        return;
    }
    if (g.have == TM_FRAME_SIZE) {
        frame_complete();
        g.have = 0;
    }
}

/* ---- a virtual MPU-6050 on the TWI bus (--imu) ------------------------------
 * Registers with auto-increment, WHO_AM_I 0x68, and a sample that moves: a
 * slow roll-rate sine with the matching accelerometer tilt and a little
 * deterministic noise, so the controller computes on changing data. simavr
 * clocks TWI at 1 us per bit whatever TWBR says (2.5x faster than 400 kHz). */
#define MPU_ADDRESS 0x68u

static struct {
    bool attached;
    uint8_t regs[128];
    uint8_t selected; /* SLA+R/W while addressed, else 0 */
    uint8_t pointer;
    bool pointer_set;
    unsigned reads, writes;
    uint32_t noise;
    uint64_t off_cycle; /* --imu-off-at: from here on nothing answers */
    avr_irq_t *to_avr;
} g_mpu;

static int16_t mpu_noise(void)
{
    g_mpu.noise = g_mpu.noise * 1664525u + 1013904223u;
    return (int16_t)((int32_t)(g_mpu.noise >> 28) - 8); /* -8 .. 7 counts */
}

static void mpu_put16(uint8_t reg, int16_t v)
{
    g_mpu.regs[reg] = (uint8_t)((uint16_t)v >> 8);
    g_mpu.regs[reg + 1] = (uint8_t)v;
}

static void mpu_sample(double t)
{
    const double roll_rate = 0.2 * sin(2.0 * M_PI * 0.5 * t);                /* rad/s */
    const double roll = -0.2 / (M_PI) * cos(2.0 * M_PI * 0.5 * t);           /* its integral */
    const double g_counts = 4096.0;                                          /* +-8 g */
    mpu_put16(0x3B, (int16_t)(0 + mpu_noise()));                              /* accel x */
    mpu_put16(0x3D, (int16_t)(g_counts * sin(roll) + mpu_noise()));           /* accel y */
    mpu_put16(0x3F, (int16_t)(g_counts * cos(roll) + mpu_noise()));           /* accel z */
    mpu_put16(0x41, 0);                                                       /* temperature */
    mpu_put16(0x43, (int16_t)(roll_rate / 1.06422515e-3 + mpu_noise()));     /* gyro x */
    mpu_put16(0x45, (int16_t)(mpu_noise()));                                 /* gyro y */
    mpu_put16(0x47, (int16_t)(mpu_noise()));                                 /* gyro z */
}

static void mpu_hook(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    avr_t *avr = param;
    avr_twi_msg_irq_t m;
    m.u.v = value;
    if (g_mpu.off_cycle != 0 && avr->cycle >= g_mpu.off_cycle) {
        g_mpu.selected = 0; /* gone: no ACK, the master sees a NACK */
        return;
    }
    if (m.u.twi.msg & TWI_COND_STOP) {
        g_mpu.selected = 0;
    }
    if (m.u.twi.msg & TWI_COND_START) {
        g_mpu.selected = 0;
        if ((m.u.twi.addr >> 1) == MPU_ADDRESS) {
            g_mpu.selected = m.u.twi.addr;
            g_mpu.pointer_set = false;
            if (m.u.twi.addr & 1u) {
                mpu_sample((double)avr->cycle / avr->frequency);
                g_mpu.reads++;
            }
            avr_raise_irq(g_mpu.to_avr, avr_twi_irq_msg(TWI_COND_ACK, g_mpu.selected, 1));
        }
    }
    if (g_mpu.selected == 0) {
        return;
    }
    if (m.u.twi.msg & TWI_COND_WRITE) {
        avr_raise_irq(g_mpu.to_avr, avr_twi_irq_msg(TWI_COND_ACK, g_mpu.selected, 1));
        if (!g_mpu.pointer_set) {
            g_mpu.pointer = m.u.twi.data & 0x7Fu;
            g_mpu.pointer_set = true;
        } else {
            if (g_mpu.pointer != 0x75u) { /* WHO_AM_I is read-only */
                g_mpu.regs[g_mpu.pointer] = m.u.twi.data;
            }
            g_mpu.pointer = (uint8_t)((g_mpu.pointer + 1u) & 0x7Fu);
            g_mpu.writes++;
        }
    }
    if (m.u.twi.msg & TWI_COND_READ) {
        const uint8_t data = g_mpu.regs[g_mpu.pointer];
        g_mpu.pointer = (uint8_t)((g_mpu.pointer + 1u) & 0x7Fu);
        avr_raise_irq(g_mpu.to_avr, avr_twi_irq_msg(TWI_COND_READ, g_mpu.selected, data));
    }
}

/* simavr 1.6 (Debian's) keeps TWINT set when the firmware writes a one to it
 * (the TWI vector is "raise_sticky"), so a polled TWI master sees every
 * transfer finish at once and reads a stale status. On the chip, writing a
 * one clears TWINT: this second write hook on TWCR, run after simavr's own,
 * does that. Each new status arrives through a cycle timer after the write,
 * which sets TWINT again. */
#define MEGA2560_TWCR 0xBCu
#define TWCR_TWINT 0x80u

static void twcr_write_fix(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    (void)param;
    if (v & TWCR_TWINT) {
        avr->data[addr] &= (uint8_t)~TWCR_TWINT;
    }
}

static bool mpu_attach(avr_t *avr)
{
    avr_irq_t *from_avr = avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT);
    g_mpu.to_avr = avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT);
    if (from_avr == NULL || g_mpu.to_avr == NULL) {
        return false;
    }
    g_mpu.regs[0x75] = 0x68u; /* WHO_AM_I */
    g_mpu.regs[0x6B] = 0x40u; /* PWR_MGMT_1 after reset: asleep */
    g_mpu.noise = 12345u;
    avr_irq_register_notify(from_avr, mpu_hook, avr);
    avr_register_io_write(avr, MEGA2560_TWCR, twcr_write_fix, NULL);
    g_mpu.attached = true;
    return true;
}

/* ---- optional profile (--profile N): self cycles per function inside the
 * timed calls, from the ELF's function symbols ---------------------------- */
typedef struct func {
    uint32_t addr, size;
    const char *name;
    uint64_t self_cycles;
    uint32_t entries;
} func;

static func *g_funcs;
static size_t g_nfuncs;

static int func_cmp(const void *a, const void *b)
{
    const func *x = a, *y = b;
    return x->addr < y->addr ? -1 : x->addr > y->addr;
}

static void add_function(const char *name, uint32_t addr, uint32_t size, void *user)
{
    size_t *capacity = user;
    if (g_nfuncs == *capacity) {
        const size_t grown = *capacity ? 2 * *capacity : 256;
        func *more = realloc(g_funcs, grown * sizeof *g_funcs);
        if (more == NULL) {
            return;
        }
        g_funcs = more;
        *capacity = grown;
    }
    g_funcs[g_nfuncs] = (func){addr, size, strdup(name), 0, 0};
    g_nfuncs++;
}

/* The image's code symbols (sim_code_symbols), sorted by address. */
static void load_functions(const char *path)
{
    size_t capacity = 0;
    (void)sim_code_symbols(path, add_function, &capacity);
    qsort(g_funcs, g_nfuncs, sizeof *g_funcs, func_cmp);
}

static func *func_at(uint32_t pc)
{
    size_t lo = 0, hi = g_nfuncs;
    while (lo < hi) { /* last function starting at or below pc */
        const size_t mid = (lo + hi) / 2;
        if (g_funcs[mid].addr <= pc) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo > 0 ? &g_funcs[lo - 1] : NULL;
}

static int self_cmp(const void *a, const void *b)
{
    const func *x = a, *y = b;
    return x->self_cycles > y->self_cycles ? -1 : x->self_cycles < y->self_cycles;
}

static void usage(void)
{
    fprintf(stderr, "usage: avr_loop_test --elf FILE --rate HZ [--seconds S] [--mcu NAME] [--freq HZ]\n"
                    "                     [--arm] [--expect armed|disarmed] [--symbol NAME] [--time NAME]...\n"
                    "                     [--imu] [--imu-off-at S] [--profile N] [--verbose]\n");
    exit(2);
}

int main(int argc, char **argv)
{
    const char *elf_path = NULL;
    const char *mcu = "atmega2560";
    const char *symbol = "fc_controller_step";
    uint32_t freq = 16000000u;
    double seconds = 2.0;
    unsigned rate = 0;
    bool arm = false;
    int expect_armed = -1; /* -1: no expectation */
    unsigned profile = 0;
    bool verbose = false;
    bool imu = false;
    double imu_off_at = 0.0;
    const char *time_names[MAX_TIMED];
    unsigned ntime_names = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--arm")) {
            arm = true;
        } else if (!strcmp(a, "--imu")) {
            imu = true;
        } else if (!strcmp(a, "--verbose")) {
            verbose = true;
        } else if (v == NULL) {
            usage();
        } else if (!strcmp(a, "--elf")) {
            elf_path = v, i++;
        } else if (!strcmp(a, "--mcu")) {
            mcu = v, i++;
        } else if (!strcmp(a, "--freq")) {
            freq = (uint32_t)strtoul(v, NULL, 10), i++;
        } else if (!strcmp(a, "--seconds")) {
            seconds = strtod(v, NULL), i++;
        } else if (!strcmp(a, "--rate")) {
            rate = (unsigned)strtoul(v, NULL, 10), i++;
        } else if (!strcmp(a, "--profile")) {
            profile = (unsigned)strtoul(v, NULL, 10), i++;
        } else if (!strcmp(a, "--imu-off-at")) {
            imu_off_at = strtod(v, NULL), i++;
            imu = true;
        } else if (!strcmp(a, "--time")) {
            if (ntime_names + 1 < MAX_TIMED) {
                time_names[ntime_names++] = v;
            }
            i++;
        } else if (!strcmp(a, "--symbol")) {
            symbol = v, i++;
        } else if (!strcmp(a, "--expect")) {
            expect_armed = !strcmp(v, "armed") ? 1 : !strcmp(v, "disarmed") ? 0 : (usage(), -1);
            i++;
        } else {
            usage();
        }
    }
    if (elf_path == NULL || rate == 0 || seconds <= 0.0) {
        usage();
    }
    elf_version(EV_CURRENT);

    /* the firmware, and the MCU it names (.mmcu) or the one given */
    static elf_firmware_t fw; /* static: zeroed, and large */
    if (elf_read_firmware(elf_path, &fw) != 0) {
        fprintf(stderr, "cannot read %s\n", elf_path);
        return 2;
    }
    const bool has_mmcu = fw.mmcu[0] != '\0';
    if (!has_mmcu) {
        snprintf(fw.mmcu, sizeof fw.mmcu, "%s", mcu);
    }
    if (fw.frequency == 0) {
        fw.frequency = freq;
    }
    uint32_t heap_start = 0, data_start = 0;
    for (unsigned k = 0; k <= ntime_names; k++) {
        timed_fn *t = &g_timed[g_ntimed];
        t->name = k == 0 ? symbol : time_names[k - 1];
        if (!elf_symbol(elf_path, t->name, &t->timer.addr)) {
            fprintf(stderr, "no symbol %s in %s%s\n", t->name, elf_path, k == 0 ? "" : " (skipped)");
            if (k == 0) {
                return 2;
            }
            continue;
        }
        t->calls = calloc(MAX_CALLS, sizeof *t->calls);
        if (t->calls == NULL) {
            return 2;
        }
        g_ntimed++;
    }
    const timed_fn *step = &g_timed[0];
    if (!elf_symbol(elf_path, "_end", &heap_start)) { /* end of .bss/.noinit */
        elf_symbol(elf_path, "__bss_end", &heap_start);
    }
    elf_symbol(elf_path, "__data_start", &data_start);
    heap_start &= 0xFFFFu; /* data addresses carry the 0x800000 offset */
    data_start &= 0xFFFFu;

    if (profile > 0) {
        load_functions(elf_path);
    }

    avr_t *avr = sim_start(&fw);
    if (avr == NULL) {
        return 2;
    }
    g.avr = avr;
    printf("%s: %s at %u Hz (%s), %.2f s simulated, expected loop rate %u Hz\n", elf_path, fw.mmcu,
           (unsigned)avr->frequency, has_mmcu ? "from its .mmcu section" : "given", seconds, rate);

    /* USART0: quiet simavr's own line printer, listen to the output */
    uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~(uint32_t)(AVR_UART_FLAG_STDIO | AVR_UART_FLAG_POLL_SLEEP);
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    avr_irq_t *uart_out = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT);
    avr_irq_t *uart_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    if (uart_out == NULL || uart_in == NULL) {
        fprintf(stderr, "no USART0 in this core\n");
        return 2;
    }
    avr_irq_register_notify(uart_out, uart_out_hook, NULL);
    if (imu && !mpu_attach(avr)) {
        fprintf(stderr, "no TWI in this core\n");
        return 2;
    }
    g_mpu.off_cycle = (uint64_t)(imu_off_at * (double)avr->frequency);

    /* run */
    const uint64_t end = (uint64_t)(seconds * (double)avr->frequency);
    const uint32_t period = avr->frequency / rate;
    uint16_t min_sp = 0xFFFFu;      /* from reset */
    uint16_t min_sp_loop = 0xFFFFu; /* after the first frame: the loop and its interrupts */
    bool arm_sent = false;
    uint64_t arm_cycle = 0;
    int state = cpu_Running;
    while (avr->cycle < end) {
        const uint16_t sp = (uint16_t)(avr->data[R_SPL] | (avr->data[R_SPH] << 8));
        if (sp < min_sp) {
            min_sp = sp;
        }
        if (sp < min_sp_loop && g.nframes > 0) {
            min_sp_loop = sp;
        }
        timed_track(avr, sp);
        if (arm && !arm_sent && g.nframes > 0) {
            for (const char *c = TM_CMD_ARM; *c != '\0'; c++) {
                avr_raise_irq(uart_in, (uint8_t)*c);
            }
            arm_sent = true;
            arm_cycle = avr->cycle;
        }
        if (profile > 0 && step->timer.in_call && arm_sent) {
            const uint32_t pc = avr->pc;
            const uint64_t before = avr->cycle;
            state = avr_run(avr);
            func *f = func_at(pc);
            if (f != NULL) {
                f->self_cycles += avr->cycle - before;
                f->entries += pc == f->addr;
            }
        } else {
            state = avr_run(avr);
        }
        if (state == cpu_Done || state == cpu_Crashed) {
            break;
        }
    }

    /* ---- results ---- */
    const double us_per_cycle = 1e6 / (double)avr->frequency;
    printf("ran %.3f s simulated (%llu cycles), %u frames (%u with a bad CRC), %u calls of %s, %u banner bytes\n",
           (double)avr->cycle / avr->frequency, (unsigned long long)avr->cycle, g.nframes, g.bad_crc, step->ncalls,
           symbol, g.text_bytes);
    check(state != cpu_Done && state != cpu_Crashed, "the image kept running (simavr state %d)", state);
    check(g.nframes >= 3, "telemetry frames received: %u", g.nframes);
    if (g.nframes < 3) {
        printf("FAILED (%d)\n", failures);
        return 1;
    }
    for (unsigned i = 0; verbose && i < g.nframes; i++) {
        const frame *f = &g.frames[i];
        printf("frame %3u at %8.2f ms: loop %6u, status 0x%02x, fc 0x%04x, step %7u..%7u, work %7u (worst %7u), "
               "overruns %u, thrust %.3f N, esc %u %u %u %u %u %u, imu errors %u\n",
               i, f->cycle * 1e3 / avr->frequency, f->loops, f->status, f->fc_status, f->step_min, f->step_max,
               f->loop_cycles_window, f->loop_cycles_worst, f->overruns, f->thrust_mn / 1000.0, f->esc_us[0],
               f->esc_us[1], f->esc_us[2], f->esc_us[3], f->esc_us[4], f->esc_us[5], f->imu_errors);
    }
    const frame *first = &g.frames[0];
    const frame *last = &g.frames[g.nframes - 1];

    bool increasing = true;
    for (unsigned i = 1; i < g.nframes; i++) {
        increasing = increasing && g.frames[i].loops > g.frames[i - 1].loops;
    }
    check(first->loops > 0 && increasing, "the loop started and its counter rises (%u -> %u)", first->loops,
          last->loops);

    /* rate from the cycle stamps of the frames (each stamped at its last
     * byte, so the transmission time cancels out; when the frame was queued
     * in its iteration varies: a loop or two of slack) */
    const double loops = (double)(last->loops - first->loops);
    const double expected_loops = (double)(last->cycle - first->cycle) * rate / avr->frequency;
    const double measured_hz = loops * avr->frequency / (double)(last->cycle - first->cycle);
    const double slack = expected_loops * 0.005 > 2.0 ? expected_loops * 0.005 : 2.0; /* stamps jitter */
    check(fabs(loops - expected_loops) <= slack, "loop rate %.2f Hz (expected %u Hz): %.0f loops in %.3f s",
          measured_hz, rate, loops, (double)(last->cycle - first->cycle) / avr->frequency);
    check(last->loop_hz == rate, "telemetry reports %u Hz", last->loop_hz);

    const double expected_frames = seconds * rate / ((rate + 19) / 20);
    check(g.nframes + 2 >= (unsigned)(0.9 * expected_frames), "telemetry rate: %u frames of about %.0f expected",
          g.nframes, expected_frames);

    check(last->loop_cycles_worst < period, "worst iteration %u cycles (%.0f us) < period %u cycles (%.0f us): %.1f %%",
          last->loop_cycles_worst, last->loop_cycles_worst * us_per_cycle, period, period * us_per_cycle,
          100.0 * last->loop_cycles_worst / period);
    check(last->overruns == 0, "deadline overruns: %u", last->overruns);
    /* the setup: the build-time snapshot's copy (fc_controller_init without simavr) */
    check((last->status & TM_STATUS_INIT_FAILED) == 0, "controller set up (%u cycles, %.1f ms), no init failure",
          last->init_cycles, last->init_cycles * us_per_cycle / 1000.0);
    check((last->status & TM_STATUS_TX_DROPPED) == 0, "no telemetry frame dropped");

    /* which calls and frames count: after the first armed frame (its window
     * may hold disarmed steps), else after the first frame */
    unsigned first_frame = 0;
    /* --imu-off-at: the armed phase ends there */
    const uint64_t off = g_mpu.off_cycle != 0 ? g_mpu.off_cycle : UINT64_MAX;
    unsigned end_frame = 0; /* frames [first_frame, end_frame) are before off */
    while (end_frame < g.nframes && g.frames[end_frame].cycle < off) {
        end_frame++;
    }
    if (expect_armed == 1) {
        while (first_frame < g.nframes && !(g.frames[first_frame].status & TM_STATUS_ARMED)) {
            first_frame++;
        }
        check(first_frame < g.nframes, "armed after \"%s\" (sent at %.1f ms)", TM_CMD_ARM,
              arm_cycle * us_per_cycle / 1000.0);
        bool all_armed = true, escs_ok = true, thrust_ok = true;
        for (unsigned i = first_frame; i < end_frame; i++) {
            const frame *f = &g.frames[i];
            all_armed = all_armed && (f->status & TM_STATUS_ARMED) && (f->status & TM_STATUS_MOTORS_ON);
            for (int ch = 0; ch < TM_ESC_CHANNELS; ch++) {
                const bool rotor = ch < f->rotor_count;
                escs_ok = escs_ok && (rotor ? (f->esc_us[ch] >= 1000 && f->esc_us[ch] <= 2000) : f->esc_us[ch] == 1000);
            }
            thrust_ok = thrust_ok && f->thrust_mn >= 0 && f->thrust_mn < 1000000;
        }
        check(first_frame < g.nframes && all_armed, "stays armed with the motors on");
        check(escs_ok, "ESC pulses in [1000, 2000] us on %u rotors, 1000 us on the rest (last: %u %u %u %u %u %u)",
              last->rotor_count, last->esc_us[0], last->esc_us[1], last->esc_us[2], last->esc_us[3],
              last->esc_us[4], last->esc_us[5]);
        check(thrust_ok, "thrust demanded finite and in range (last %.3f N, fc status 0x%x)", last->thrust_mn / 1000.0,
              last->fc_status);
    } else if (expect_armed == 0) {
        bool none_armed = true, escs_off = true;
        for (unsigned i = 0; i < g.nframes; i++) {
            const frame *f = &g.frames[i];
            none_armed = none_armed && !(f->status & (TM_STATUS_ARMED | TM_STATUS_MOTORS_ON));
            for (int ch = 0; ch < TM_ESC_CHANNELS; ch++) {
                escs_off = escs_off && f->esc_us[ch] == 1000;
            }
        }
        check(none_armed, "stays disarmed%s", arm && !imu ? " (the arm command is refused without an IMU)" : "");
        check(escs_off, "every ESC at 1000 us");
    }
    if (imu) {
        check(g_mpu.regs[0x6B] == 0x01 && g_mpu.regs[0x19] == 0x00 && g_mpu.regs[0x1A] == 0x03 &&
                  g_mpu.regs[0x1B] == 0x18 && g_mpu.regs[0x1C] == 0x10,
              "the MPU-6050 configured: PWR_MGMT_1 %02x, SMPLRT_DIV %02x, CONFIG %02x, GYRO %02x, ACCEL %02x",
              g_mpu.regs[0x6B], g_mpu.regs[0x19], g_mpu.regs[0x1A], g_mpu.regs[0x1B], g_mpu.regs[0x1C]);
    }
    if (off != UINT64_MAX) {
        /* the IMU went away: within 0.1 s (+ two periods and a frame)
         * disarmed, motors off, the loop going on */
        const uint64_t settle = off + avr->frequency / 10 + 2 * period + avr->frequency / 50;
        bool lost_ok = true, seen = false;
        for (unsigned i = end_frame; i < g.nframes; i++) {
            const frame *f = &g.frames[i];
            if (f->cycle < settle) {
                continue;
            }
            seen = true;
            lost_ok = lost_ok && (f->status & TM_STATUS_IMU_ERROR) && !(f->status & TM_STATUS_ARMED) &&
                      !(f->status & TM_STATUS_MOTORS_ON);
            for (int ch = 0; ch < TM_ESC_CHANNELS; ch++) {
                lost_ok = lost_ok && f->esc_us[ch] == 1000;
            }
        }
        check(seen && lost_ok, "IMU lost at %.2f s: error bit, disarmed, every ESC at 1000 us (%u failed reads)",
              imu_off_at, last->imu_errors);
        const frame *before = end_frame > 0 ? &g.frames[end_frame - 1] : NULL;
        check(before != NULL && before->imu_errors == 0, "no failed read before it");
    } else if (imu) {
        check(last->imu_errors == 0 && !(last->status & TM_STATUS_IMU_ERROR),
              "the virtual MPU-6050: no failed read, one burst per loop (%u reads, %u loops)", g_mpu.reads,
              last->loops);
        check(g_mpu.reads + 2 >= last->loops, "one burst read per loop (%u reads, %u loops)", g_mpu.reads,
              last->loops);
    } else {
        check((last->status & TM_STATUS_IMU_ERROR) && last->imu_errors > 0,
              "no IMU on the bus: error bit set, %u failed reads, the loop runs on", last->imu_errors);
    }
    if (first_frame >= end_frame) {
        printf("FAILED (%d)\n", failures);
        return 1;
    }

    /* the benchmark: fc_controller_step timed from outside */
    const uint64_t from = g.frames[first_frame].cycle;
    uint32_t host_min, host_max;
    double host_mean;
    const unsigned counted = timed_stats(step, from, off, &host_min, &host_max, &host_mean);
    /* and as the image measured it (Timer3), in the windows after that frame */
    uint32_t img_min = UINT32_MAX, img_max = 0, loop_max = 0;
    for (unsigned i = first_frame + 1; i < end_frame; i++) {
        const frame *f = &g.frames[i];
        img_min = f->step_min < img_min ? f->step_min : img_min;
        img_max = f->step_max > img_max ? f->step_max : img_max;
        loop_max = f->loop_cycles_window > loop_max ? f->loop_cycles_window : loop_max;
    }
    check(counted > 0, "%u calls of %s timed", counted, symbol);
    if (counted == 0 || img_max == 0) {
        printf("FAILED (%d)\n", failures);
        return 1;
    }
    printf("BENCHMARK %s %s: %u cycles min, %u cycles max, %.0f mean per call (%.0f .. %.0f us) over %u calls; "
           "loop %u Hz, period %u cycles, worst iteration %u cycles (%.1f %%)\n",
           symbol, (last->status & TM_STATUS_FIXED) ? "fixed" : "float", host_min, host_max, host_mean,
           host_min * us_per_cycle, host_max * us_per_cycle, counted, rate, period, loop_max,
           100.0 * loop_max / period);
    for (unsigned k = 1; k < g_ntimed; k++) {
        uint32_t mn, mx;
        double mean;
        const unsigned n = timed_stats(&g_timed[k], from, off, &mn, &mx, &mean);
        if (n > 0) {
            printf("  %-32s %8u min %8u max %10.0f mean cycles over %u calls\n", g_timed[k].name, mn, mx, mean, n);
        }
    }
    check(host_max < period, "%s max %u cycles < period %u cycles", symbol, host_max, period);
    /* the image's figures carry the call and two Timer3 reads (tens of cycles) */
    const double tol = 0.02 * host_max + 100.0;
    check(img_min + tol >= host_min && img_min <= host_min + tol && img_max + tol >= host_max &&
              img_max <= host_max + tol,
          "the image's own Timer3 figures agree: %u .. %u cycles", img_min, img_max);

    if (profile > 0 && g_nfuncs > 0) {
        uint64_t total = 0;
        for (size_t i = 0; i < g_nfuncs; i++) {
            total += g_funcs[i].self_cycles;
        }
        qsort(g_funcs, g_nfuncs, sizeof *g_funcs, self_cmp);
        printf("profile of %s after arming: self cycles per function (entries), %llu cycles in all\n", symbol,
               (unsigned long long)total);
        for (size_t i = 0; i < g_nfuncs && i < profile && g_funcs[i].self_cycles > 0; i++) {
            printf("  %5.1f %%  %12llu  %8u  %s\n", 100.0 * g_funcs[i].self_cycles / (double)total,
                   (unsigned long long)g_funcs[i].self_cycles, g_funcs[i].entries, g_funcs[i].name);
        }
    }

    /* RAM: static data + stack peak against 8 KiB */
    const unsigned ramend = avr->ramend;
    const unsigned static_ram = heap_start > data_start ? heap_start - data_start : 0;
    const unsigned stack_peak = ramend - min_sp;
    const unsigned ram_total = ramend + 1 - data_start;
    printf("RAM: static %u bytes (.data + .bss + .noinit), stack peak %u bytes (%u in the loop), %u of %u bytes used, "
           "%d free\n",
           static_ram, stack_peak, ramend - min_sp_loop, static_ram + stack_peak, ram_total,
           (int)ram_total - (int)(static_ram + stack_peak));
    check(heap_start != 0 && min_sp > heap_start, "the stack (down to 0x%04x) stays above the static data (0x%04x)",
          min_sp, heap_start);

    printf(failures == 0 ? "PASSED\n" : "FAILED (%d)\n", failures);
    return failures == 0 ? 0 : 1;
}

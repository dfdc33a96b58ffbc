/*
 * snapshot_host.c - avr_snapshot: the ATmega flight image's controller made
 * at build time (platform/atmega/controller_snapshot.h).
 *
 *   avr_snapshot --elf SNAPSHOT.elf --out FILE.c
 *       runs the snapshot image (platform/atmega/snapshot/snapshot_avr.c) in
 *       simavr (atmega2560, 16 MHz) until it sleeps with interrupts off,
 *       takes its fc_controller from RAM (address and size from the ELF's
 *       symbols) and writes FILE.c: those bytes as the PROGMEM array
 *       fc_atmega_controller_snapshot in the records of
 *       controller_snapshot.h (most of the controller is zero), with a
 *       static assertion that they fill the flight image's
 *       sizeof(fc_controller). If fc_controller_init
 *       did not return FC_INIT_OK, or the image did not finish, it says so
 *       and exits 1 without writing FILE.c: the build stops there.
 *   avr_snapshot --elf SNAPSHOT.elf --boot IMAGE.elf
 *       the same run, then IMAGE.elf (a flight image) until its first call
 *       of fc_controller_step: exit 0 when its g_ctl holds, byte for byte,
 *       the controller the snapshot image's init produced (the copy at boot
 *       works, the snapshot is this build's, nothing in it depends on where
 *       it lives).
 * Exit status 2: usage, or an ELF without the symbols.
 */
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "avr_uart.h"
#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_support.h"

/* fc_init_result's names (firmware/include/fc/status.h), for the message */
static const char *const init_names[] = {
    "FC_INIT_OK",
    "FC_INIT_BAD_PARAM",
    "FC_INIT_RANK_DEFICIENT",
    "FC_INIT_GRAVITY_MISMATCH",
    "FC_INIT_MASS_MISMATCH",
    "FC_INIT_THRUST_TOO_LOW",
    "FC_INIT_THRUST_ABOVE_ROTORS",
    "FC_INIT_AUTHORITY_MISMATCH",
};

#define SNAPSHOT_MAX_S 10u /* simulated seconds for the init */
#define BOOT_MAX_S 5u      /* simulated seconds to the flight image's first step */

static uint32_t data_addr(uint32_t elf_addr)
{
    return elf_addr & 0xFFFFu; /* data addresses carry the 0x800000 offset */
}

static bool symbol_or_say(const char *path, const char *name, uint32_t *addr, uint32_t *size)
{
    if (!elf_symbol_sized(path, name, addr, size)) {
        fprintf(stderr, "avr_snapshot: no symbol %s in %s\n", name, path);
        return false;
    }
    return true;
}

/* Runs the snapshot image; its controller's bytes (malloc'd) in *bytes, their
 * count in *size. 0, or the exit status. */
static int take_snapshot(const char *path, uint8_t **bytes, uint32_t *size)
{
    uint32_t ctl = 0, result = 0, done = 0, unused = 0;
    if (!symbol_or_say(path, "fc_snapshot_controller", &ctl, size) ||
        !symbol_or_say(path, "fc_snapshot_result", &result, &unused) ||
        !symbol_or_say(path, "fc_snapshot_done", &done, &unused)) {
        return 2;
    }
    static elf_firmware_t fw;
    avr_t *avr = sim_load_atmega2560(path, &fw);
    if (avr == NULL) {
        return 2;
    }
    int state = cpu_Running;
    const uint64_t limit = (uint64_t)fw.frequency * SNAPSHOT_MAX_S;
    while (avr->cycle < limit && state != cpu_Done && state != cpu_Crashed) {
        state = avr_run(avr);
    }
    if (avr->data[data_addr(done)] != 1u) {
        fprintf(stderr, "avr_snapshot: %s did not finish fc_controller_init (%s after %.1f s simulated)\n", path,
                state == cpu_Crashed ? "crashed" : "still running", (double)avr->cycle / (double)fw.frequency);
        return 1;
    }
    const unsigned r = avr->data[data_addr(result)];
    if (r != 0u) {
        fprintf(stderr,
                "avr_snapshot: fc_controller_init returned %s (%u) for this build's parameters "
                "(platform/atmega/controller_setup.c, FC_ATMEGA_* options): no flight image is built "
                "with a controller that did not initialise\n",
                r < sizeof init_names / sizeof init_names[0] ? init_names[r] : "an unknown result", r);
        return 1;
    }
    *bytes = malloc(*size);
    if (*bytes == NULL || *size == 0u) {
        return 2;
    }
    memcpy(*bytes, &avr->data[data_addr(ctl)], *size);
    printf("avr_snapshot: fc_controller_init FC_INIT_OK in %.1f ms simulated, fc_controller %u bytes\n",
           (double)avr->cycle * 1000.0 / (double)fw.frequency, (unsigned)*size);
    return 0;
}

/* A record ends at a run of zeros longer than this: a record's two bytes
 * cost more than the zeros they skip. */
#define RECORD_GAP_MAX 2u

/* The records of controller_snapshot.h for bytes[0, size) into rec (room
 * for 2 size + 2 bytes); returns their length. */
static uint32_t encode(const uint8_t *bytes, uint32_t size, uint8_t *rec)
{
    uint32_t n = 0, at = 0;
    while (at < size) {
        uint32_t skip = 0;
        while (at + skip < size && bytes[at + skip] == 0u && skip < 255u) {
            skip++;
        }
        at += skip;
        uint32_t len = 0, zeros = 0;
        while (at + len + zeros < size && len + zeros < 255u) {
            if (bytes[at + len + zeros] != 0u) {
                len += zeros + 1u;
                zeros = 0;
            } else if (++zeros > RECORD_GAP_MAX) {
                break;
            }
        }
        rec[n++] = (uint8_t)skip;
        rec[n++] = (uint8_t)len;
        memcpy(&rec[n], &bytes[at], len);
        n += len;
        at += len;
    }
    return n;
}

/* main.c's decoding of rec into out[size]; true when it gives bytes back. */
static bool decodes_to(const uint8_t *rec, uint32_t n, const uint8_t *bytes, uint32_t size)
{
    uint8_t *out = calloc(size, 1);
    uint32_t at = 0, i = 0;
    while (out != NULL && at < size && i + 2u <= n) {
        at += rec[i];
        const uint32_t len = rec[i + 1u];
        i += 2u;
        if (len > size - at || i + len > n) {
            break;
        }
        memcpy(&out[at], &rec[i], len);
        at += len;
        i += len;
    }
    const bool same = out != NULL && at == size && i == n && memcmp(out, bytes, size) == 0;
    free(out);
    return same;
}

static int write_source(const char *out, const char *elf_path, const uint8_t *bytes, uint32_t size)
{
    uint8_t *rec = malloc(2u * size + 2u);
    if (rec == NULL) {
        return 2;
    }
    const uint32_t n = encode(bytes, size, rec);
    if (!decodes_to(rec, n, bytes, size)) {
        fprintf(stderr, "avr_snapshot: the records do not decode to the controller\n");
        free(rec);
        return 2;
    }
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp", out);
    FILE *f = fopen(tmp, "w");
    if (f == NULL) {
        fprintf(stderr, "avr_snapshot: cannot write %s\n", tmp);
        free(rec);
        return 2;
    }
    const char *base = strrchr(elf_path, '/');
    fprintf(f,
            "/* Generated at build time by avr_snapshot (tools/simavr/snapshot_host.c)\n"
            " * from %s: the fc_controller that fc_controller_init\n"
            " * left, with FC_INIT_OK, for this build's parameters\n"
            " * (platform/atmega/controller_snapshot.h). Not to be edited. */\n"
            "#include \"controller_snapshot.h\"\n"
            "#include \"fc/controller.h\"\n\n"
            "/* the records fill this many bytes: the snapshot image's fc_controller */\n"
            "#define SNAPSHOT_CONTROLLER_BYTES %uu\n"
            "_Static_assert(SNAPSHOT_CONTROLLER_BYTES == sizeof(fc_controller),\n"
            "               \"the snapshot's fc_controller is not this build's\");\n\n"
            "const uint8_t fc_atmega_controller_snapshot[%u] PROGMEM = {",
            base != NULL ? base + 1 : elf_path, (unsigned)size, (unsigned)n);
    for (uint32_t i = 0; i < n; i++) {
        fprintf(f, "%s0x%02x,", i % 12u == 0u ? "\n    " : " ", rec[i]);
    }
    fprintf(f, "\n};\n");
    free(rec);
    if (fclose(f) != 0 || rename(tmp, out) != 0) {
        fprintf(stderr, "avr_snapshot: cannot write %s\n", out);
        return 2;
    }
    return 0;
}

/* Runs the flight image to its first fc_controller_step; 0 when its g_ctl is
 * the snapshot. */
static int check_boot(const char *path, const uint8_t *bytes, uint32_t size)
{
    uint32_t ctl = 0, ctl_size = 0, step = 0, step_size = 0;
    if (!symbol_or_say(path, "g_ctl", &ctl, &ctl_size) ||
        !symbol_or_say(path, "fc_controller_step", &step, &step_size)) {
        return 2;
    }
    if (ctl_size != size) {
        fprintf(stderr, "FAIL: g_ctl of %s is %u bytes, the snapshot image's controller %u\n", path,
                (unsigned)ctl_size, (unsigned)size);
        return 1;
    }
    static elf_firmware_t fw;
    avr_t *avr = sim_load_atmega2560(path, &fw);
    if (avr == NULL) {
        return 2;
    }
    /* the banner and telemetry on USART0: not to stdout */
    uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~(uint32_t)AVR_UART_FLAG_STDIO;
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    int state = cpu_Running;
    const uint64_t limit = (uint64_t)fw.frequency * BOOT_MAX_S;
    while (avr->pc != step && avr->cycle < limit && state != cpu_Done && state != cpu_Crashed) {
        state = avr_run(avr);
    }
    if (avr->pc != step) {
        fprintf(stderr, "FAIL: %s did not reach fc_controller_step in %u s simulated\n", path, BOOT_MAX_S);
        return 1;
    }
    const uint8_t *booted = &avr->data[data_addr(ctl)];
    uint32_t differ = 0, first = 0;
    for (uint32_t i = 0; i < size; i++) {
        if (booted[i] != bytes[i]) {
            first = differ == 0u ? i : first;
            differ++;
        }
    }
    if (differ != 0u) {
        printf("FAIL: at its first fc_controller_step (%.1f ms), %s's g_ctl differs from the snapshot image's "
               "initialised controller in %u of %u bytes, the first at offset %u (%02x, expected %02x)\n",
               (double)avr->cycle * 1000.0 / (double)fw.frequency, path, (unsigned)differ, (unsigned)size,
               (unsigned)first, booted[first], bytes[first]);
        return 1;
    }
    printf("ok: at its first fc_controller_step (%.1f ms simulated), %s's g_ctl is the initialised controller "
           "(%u bytes)\n",
           (double)avr->cycle * 1000.0 / (double)fw.frequency, path, (unsigned)size);
    return 0;
}

int main(int argc, char **argv)
{
    const char *elf_path = NULL, *out = NULL, *boot = NULL;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--elf")) {
            elf_path = argv[i + 1];
        } else if (!strcmp(argv[i], "--out")) {
            out = argv[i + 1];
        } else if (!strcmp(argv[i], "--boot")) {
            boot = argv[i + 1];
        }
    }
    if (elf_path == NULL || (out == NULL) == (boot == NULL)) {
        fprintf(stderr, "usage: avr_snapshot --elf SNAPSHOT.elf (--out FILE.c | --boot IMAGE.elf)\n");
        return 2;
    }
    elf_version(EV_CURRENT);
    uint8_t *bytes = NULL;
    uint32_t size = 0;
    int status = take_snapshot(elf_path, &bytes, &size);
    if (status == 0) {
        status = out != NULL ? write_source(out, elf_path, bytes, size) : check_boot(boot, bytes, size);
    }
    free(bytes);
    return status;
}

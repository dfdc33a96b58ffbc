/*
 * bench_host.c - avr_bench: runs the ATmega2560 benchmark image
 * (bench_avr.c) in simavr (atmega2560, 16 MHz) until it sleeps with
 * interrupts off, and times each --time NAME from outside, as
 * avr_loop_test does: a call starts when the PC reaches the symbol's address
 * and ends when the PC reaches the return address the CALL pushed, with the
 * stack pointer back. Only calls that start between the image's markers
 * bench_timed_begin and bench_timed_end count. Cycles are simavr's exact
 * instruction cycle counts of the ATmega2560.
 *
 * Output, one line per name: "CYCLES name min max mean calls", then
 * "STACK peak_bytes" (lowest SP from reset, against RAMEND) and
 * "RESULT 0x...." (the image's bench_result). Exit status 0 when the image
 * finished, its init succeeded and every name was timed at least once (no
 * timing limits: this is a measurement).
 */
#include <fcntl.h>
#include <gelf.h>
#include <libelf.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sim_avr.h"
#include "sim_elf.h"
#include "../sim/sim_support.h"

#define MAX_TIMED 16

typedef struct timed_fn {
    const char *name;
    uint32_t addr;
    bool in_call;
    uint64_t start;
    uint32_t ret;
    uint16_t sp;
    uint32_t min, max;
    uint64_t sum;
    unsigned n;
} timed_fn;

static timed_fn g_timed[MAX_TIMED];
static unsigned g_ntimed;

int main(int argc, char **argv)
{
    const char *elf_path = NULL;
    double max_seconds = 600.0;
    const char *names[MAX_TIMED];
    unsigned nnames = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--elf")) {
            elf_path = argv[i + 1];
        } else if (!strcmp(argv[i], "--time") && nnames < MAX_TIMED) {
            names[nnames++] = argv[i + 1];
        } else if (!strcmp(argv[i], "--max-seconds")) {
            max_seconds = strtod(argv[i + 1], NULL);
        } else {
            break;
        }
    }
    if (elf_path == NULL || nnames == 0 || (argc - 1) % 2 != 0) {
        fprintf(stderr, "usage: avr_bench --elf FILE --time NAME... [--max-seconds S]\n");
        return 2;
    }
    elf_version(EV_CURRENT);
    uint32_t begin_addr = 0, end_addr = 0, result_addr = 0;
    if (!elf_symbol(elf_path, "bench_timed_begin", &begin_addr) ||
        !elf_symbol(elf_path, "bench_timed_end", &end_addr) || !elf_symbol(elf_path, "bench_result", &result_addr)) {
        fprintf(stderr, "%s: no bench_timed_begin/bench_timed_end/bench_result symbol\n", elf_path);
        return 2;
    }
    for (unsigned k = 0; k < nnames; k++) {
        timed_fn *t = &g_timed[g_ntimed];
        t->name = names[k];
        t->min = UINT32_MAX;
        if (!elf_symbol(elf_path, t->name, &t->addr)) {
            fprintf(stderr, "no symbol %s in %s\n", t->name, elf_path);
            return 2;
        }
        g_ntimed++;
    }

    static elf_firmware_t fw;
    if (!sim_read_atmega2560(elf_path, &fw)) {
        return 2;
    }
    avr_t *avr = sim_start(&fw);
    if (avr == NULL) {
        return 2;
    }

    const uint64_t limit = (uint64_t)(max_seconds * (double)avr->frequency);
    uint16_t min_sp = 0xFFFFu;
    int phase = 0; /* 0 before the begin marker, 1 timed, 2 after the end marker */
    int state = cpu_Running;
    while (avr->cycle < limit) {
        const uint16_t sp = (uint16_t)(avr->data[R_SPL] | (avr->data[R_SPH] << 8));
        min_sp = sp < min_sp ? sp : min_sp;
        const uint32_t pc = avr->pc;
        if (pc == begin_addr) {
            phase = 1;
        } else if (pc == end_addr) {
            phase = 2;
        }
        for (unsigned k = 0; k < g_ntimed; k++) {
            timed_fn *t = &g_timed[k];
            if (!t->in_call && pc == t->addr && phase == 1) {
                uint32_t ret = 0;
                for (int i = 1; i <= avr->address_size; i++) {
                    ret = (ret << 8) | avr->data[sp + i];
                }
                t->in_call = true;
                t->start = avr->cycle;
                t->ret = ret * 2u;
                t->sp = sp;
            } else if (t->in_call && pc == t->ret && sp == t->sp + avr->address_size) {
                const uint32_t c = (uint32_t)(avr->cycle - t->start);
                t->in_call = false;
                t->min = c < t->min ? c : t->min;
                t->max = c > t->max ? c : t->max;
                t->sum += c;
                t->n++;
            }
        }
        state = avr_run(avr);
        if (state == cpu_Done || state == cpu_Crashed) {
            break;
        }
    }
    const uint16_t result = (uint16_t)(avr->data[(result_addr & 0xFFFFu)] | (avr->data[(result_addr & 0xFFFFu) + 1] << 8));
    for (unsigned k = 0; k < g_ntimed; k++) {
        const timed_fn *t = &g_timed[k];
        printf("CYCLES %s %u %u %.0f %u\n", t->name, t->n ? t->min : 0u, t->max, t->n ? (double)t->sum / t->n : 0.0,
               t->n);
    }
    printf("STACK %u\n", (unsigned)(avr->ramend - min_sp));
    printf("RESULT 0x%04x after %llu cycles (%s)\n", result, (unsigned long long)avr->cycle,
           state == cpu_Done ? "done" : state == cpu_Crashed ? "crashed" : "cycle limit");
    bool ok = state == cpu_Done && (result & 0x8000u) && phase == 2;
    for (unsigned k = 0; k < g_ntimed; k++) {
        ok = ok && g_timed[k].n > 0; /* every function timed at least once */
    }
    return ok ? 0 : 1;
}

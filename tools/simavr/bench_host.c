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
 * With --profile NAME (one of the --time names), a flat profile of NAME's
 * timed calls: every cycle spent while a call of NAME is under way is
 * charged to the function whose code holds the PC (exclusive cycles, from
 * the ELF's FUNC symbols and their sizes, libgcc's untyped labels up to the
 * next symbol); a call of a function is counted
 * when the PC enters its first instruction from outside it.
 *
 * Output, one line per name: "CYCLES name min max mean calls", then one
 * "PERCALL name c1 c2 ..." per name (the first 64 calls' cycles, in order),
 * then (--profile) "PROFILE name exclusive_cycles_per_call calls_per_call
 * percent", most cycles first, then
 * (--profile) "CLASS kind cycles_per_call percent": the same cycles by the
 * kind of instruction that spent them (multiplies, loads and stores, moves,
 * add/subtract, compares, control flow, other ALU), then
 * (--pc-cycles FILE, with --profile) the same cycles per instruction address
 * written to FILE, "0xADDRESS cycles_per_call" a line, for a line profile
 * (avr-addr2line on an image built with -g), then
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
#include "sim_support.h"

#define MAX_TIMED 16
#define MAX_CALLS_LISTED 64
#define MAX_FUNCS 4096

/* a function of the image: [addr, addr + size) in bytes of flash */
typedef struct prof_fn {
    const char *name;
    uint32_t addr, size;
    uint64_t cycles;
    uint64_t calls;
} prof_fn;

static prof_fn g_funcs[MAX_FUNCS];
static unsigned g_nfuncs;

static int prof_cmp_addr(const void *a, const void *b)
{
    const prof_fn *x = a, *y = b;
    return x->addr < y->addr ? -1 : x->addr > y->addr;
}

static int prof_cmp_cycles(const void *a, const void *b)
{
    const prof_fn *x = a, *y = b;
    return x->cycles > y->cycles ? -1 : x->cycles < y->cycles;
}

static void prof_add(const char *name, uint32_t addr, uint32_t size, void *user)
{
    (void)user;
    if (g_nfuncs < MAX_FUNCS) {
        prof_fn *f = &g_funcs[g_nfuncs++];
        f->name = strdup(name);
        f->addr = addr;
        f->size = size;
    }
}

/* Every code symbol of the ELF (sim_code_symbols), sorted by address; an
 * assembly label without a size extends to the next symbol. */
static bool prof_load(const char *path)
{
    if (!sim_code_symbols(path, prof_add, NULL)) {
        return false;
    }
    qsort(g_funcs, g_nfuncs, sizeof g_funcs[0], prof_cmp_addr);
    for (unsigned i = 0; i < g_nfuncs; i++) {
        if (g_funcs[i].size == 0u) {
            g_funcs[i].size = i + 1 < g_nfuncs ? g_funcs[i + 1].addr - g_funcs[i].addr : 2u;
        }
    }
    return g_nfuncs > 0;
}

/* The function holding byte address pc, or NULL. */
static prof_fn *prof_find(uint32_t pc)
{
    unsigned lo = 0, hi = g_nfuncs;
    while (lo < hi) {
        const unsigned mid = (lo + hi) / 2;
        if (g_funcs[mid].addr <= pc) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    if (lo == 0) {
        return NULL;
    }
    prof_fn *f = &g_funcs[lo - 1];
    return pc < f->addr + f->size ? f : NULL;
}

typedef struct timed_fn {
    const char *name;
    sim_call_timer timer;
    uint32_t min, max;
    uint64_t sum;
    unsigned n;
    uint32_t each[MAX_CALLS_LISTED]; /* the first calls' cycles, in order */
} timed_fn;

static timed_fn g_timed[MAX_TIMED];
static unsigned g_ntimed;

/* The kinds of AVR instruction the profile splits the cycles by. */
enum insn_class {
    CLASS_MUL,        /* MUL, MULS, MULSU, FMUL* */
    CLASS_MEMORY,     /* LD, LDD, LDS, ST, STD, STS, PUSH, POP, LPM, ELPM */
    CLASS_MOVE,       /* MOV, MOVW */
    CLASS_LDI,        /* LDI */
    CLASS_ADD_SUB,    /* ADD, ADC, SUB, SBC, SUBI, SBCI */
    CLASS_COMPARE,    /* CP, CPC, CPI */
    CLASS_FLOW,       /* branches, jumps, calls, returns, skips (CPSE, SBRC, SBRS, SBIC, SBIS) */
    CLASS_OTHER,      /* the rest of the ALU: shifts, logic, ADIW/SBIW, bit moves */
    CLASS_COUNT
};
static const char *const class_names[CLASS_COUNT] = {
    "mul", "load/store/push/pop", "mov/movw", "ldi", "add/adc/sub/sbc", "cp/cpc/cpi", "branch/jump/call/ret/skip",
    "other ALU"};
static uint64_t g_class_cycles[CLASS_COUNT];

/* calls counted by (callee, caller) during the profiled calls (CALLER lines) */
#define MAX_CALL_EDGES 1024
typedef struct call_edge {
    const char *callee, *caller; /* names: g_funcs is sorted again before the output */
    uint64_t calls;
} call_edge;
static call_edge g_edges[MAX_CALL_EDGES];
static unsigned g_nedges;

static void edge_count(const prof_fn *callee_fn, const prof_fn *caller_fn)
{
    const char *callee = callee_fn->name;
    const char *caller = caller_fn != NULL ? caller_fn->name : "?";
    for (unsigned i = 0; i < g_nedges; i++) {
        if (g_edges[i].callee == callee && g_edges[i].caller == caller) {
            g_edges[i].calls++;
            return;
        }
    }
    if (g_nedges < MAX_CALL_EDGES) {
        g_edges[g_nedges++] = (call_edge){callee, caller, 1u};
    }
}

static int edge_cmp_calls(const void *a, const void *b)
{
    const call_edge *x = a, *y = b;
    return x->calls > y->calls ? -1 : x->calls < y->calls;
}

/* cycles of the profiled calls per instruction word of the flash (--pc-cycles) */
#define FLASH_WORDS (256u * 1024u / 2u)
static uint64_t g_pc_cycles[FLASH_WORDS];

/* The class of the instruction word OP (AVR instruction set manual encodings). */
static enum insn_class insn_class_of(uint16_t op)
{
    if ((op & 0xFC00u) == 0x9C00u || (op & 0xFE00u) == 0x0200u) {
        return CLASS_MUL; /* MUL 1001 11rd; MULS 0000 0010, MULSU/FMUL* 0000 0011 */
    }
    if ((op & 0xD000u) == 0x8000u || (op & 0xFC00u) == 0x9000u) {
        return CLASS_MEMORY; /* LDD/STD 10q0; LD/ST/LDS/STS/PUSH/POP/LPM 1001 00xx */
    }
    if ((op & 0xFC00u) == 0x2C00u || (op & 0xFF00u) == 0x0100u) {
        return CLASS_MOVE;
    }
    if ((op & 0xF000u) == 0xE000u) {
        return CLASS_LDI;
    }
    if ((op & 0xEC00u) == 0x0C00u || (op & 0xEC00u) == 0x0800u || (op & 0xE000u) == 0x4000u) {
        return CLASS_ADD_SUB; /* ADD 0000 11, ADC 0001 11, SBC 0000 10, SUB 0001 10, SBCI 0100, SUBI 0101 */
    }
    if ((op & 0xEC00u) == 0x0400u || (op & 0xF000u) == 0x3000u) {
        return CLASS_COMPARE; /* CPC 0000 01, CP 0001 01, CPI 0011 */
    }
    if ((op & 0xF800u) == 0xF000u || (op & 0xE000u) == 0xC000u || (op & 0xFE0Cu) == 0x940Cu || op == 0x9508u ||
        op == 0x9518u || (op & 0xFEEFu) == 0x9409u || (op & 0xFC00u) == 0x1000u || (op & 0xFC08u) == 0xFC00u ||
        (op & 0xFD00u) == 0x9900u) {
        /* BRBS/BRBC 1111 0x; RJMP/RCALL 110x; JMP/CALL 1001 010k kkkk 11xk; RET, RETI;
         * IJMP/ICALL/EIJMP/EICALL; CPSE 0001 00; SBRC/SBRS 1111 11x; SBIC/SBIS 1001 10x1 */
        return CLASS_FLOW;
    }
    return CLASS_OTHER;
}

/* CALL, RCALL, ICALL, EICALL */
static bool is_call(uint16_t op)
{
    return (op & 0xFE0Eu) == 0x940Eu || (op & 0xF000u) == 0xD000u || op == 0x9509u || op == 0x9519u;
}

int main(int argc, char **argv)
{
    const char *elf_path = NULL;
    double max_seconds = 600.0;
    const char *names[MAX_TIMED];
    unsigned nnames = 0;
    const char *profile_name = NULL;
    const char *pc_cycles_path = NULL;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--elf")) {
            elf_path = argv[i + 1];
        } else if (!strcmp(argv[i], "--time") && nnames < MAX_TIMED) {
            names[nnames++] = argv[i + 1];
        } else if (!strcmp(argv[i], "--profile")) {
            profile_name = argv[i + 1];
        } else if (!strcmp(argv[i], "--pc-cycles")) {
            pc_cycles_path = argv[i + 1];
        } else if (!strcmp(argv[i], "--max-seconds")) {
            max_seconds = strtod(argv[i + 1], NULL);
        } else {
            break;
        }
    }
    if (elf_path == NULL || nnames == 0 || (argc - 1) % 2 != 0) {
        fprintf(stderr, "usage: avr_bench --elf FILE --time NAME... [--profile NAME [--pc-cycles FILE]] [--max-seconds S]\n");
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
        if (!elf_symbol(elf_path, t->name, &t->timer.addr)) {
            fprintf(stderr, "no symbol %s in %s\n", t->name, elf_path);
            return 2;
        }
        g_ntimed++;
    }
    const timed_fn *profiled = NULL;
    if (profile_name != NULL) {
        for (unsigned k = 0; k < g_ntimed; k++) {
            if (!strcmp(g_timed[k].name, profile_name)) {
                profiled = &g_timed[k];
            }
        }
        if (profiled == NULL || !prof_load(elf_path)) {
            fprintf(stderr, "--profile %s: not a --time name, or no function symbols\n", profile_name);
            return 2;
        }
    }
    prof_fn *prev_fn = NULL;
    uint16_t prev_opcode = 0u;

    static elf_firmware_t fw;
    avr_t *avr = sim_load_atmega2560(elf_path, &fw);
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
            const int64_t cycles = sim_call_timer_at(&t->timer, avr, pc, sp, phase == 1);
            if (cycles >= 0) {
                const uint32_t c = (uint32_t)cycles;
                t->min = c < t->min ? c : t->min;
                t->max = c > t->max ? c : t->max;
                t->sum += c;
                if (t->n < MAX_CALLS_LISTED) {
                    t->each[t->n] = c;
                }
                t->n++;
            }
        }
        const uint64_t before = avr->cycle;
        const bool profiling = profiled != NULL && profiled->timer.in_call;
        /* the instruction about to run (read before avr_run moves the PC), for the profile only */
        const uint16_t opcode = profiling ? (uint16_t)(avr->flash[pc] | (avr->flash[pc + 1] << 8)) : 0u;
        state = avr_run(avr);
        if (profiling) {
            g_class_cycles[insn_class_of(opcode)] += avr->cycle - before;
            g_pc_cycles[(pc / 2u) % FLASH_WORDS] += avr->cycle - before;
            prof_fn *f = prof_find(pc);
            if (f != NULL) {
                f->cycles += avr->cycle - before;
                if (f != prev_fn && pc == f->addr) {
                    f->calls++;
                    /* entered by a call (not a jump): its return address is on top */
                    if (is_call(prev_opcode)) {
                        uint32_t ret = 0;
                        for (int i = 1; i <= avr->address_size; i++) {
                            ret = (ret << 8) | avr->data[sp + i];
                        }
                        edge_count(f, prof_find(ret * 2u));
                    }
                }
            }
            prev_fn = f;
            prev_opcode = opcode;
        }
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
    for (unsigned k = 0; k < g_ntimed; k++) {
        const timed_fn *t = &g_timed[k];
        printf("PERCALL %s", t->name);
        for (unsigned i = 0; i < t->n && i < MAX_CALLS_LISTED; i++) {
            printf(" %u", t->each[i]);
        }
        printf("\n");
    }
    if (profiled != NULL && profiled->n > 0) {
        uint64_t total = 0;
        for (unsigned i = 0; i < g_nfuncs; i++) {
            total += g_funcs[i].cycles;
        }
        qsort(g_funcs, g_nfuncs, sizeof g_funcs[0], prof_cmp_cycles);
        for (unsigned i = 0; i < g_nfuncs && g_funcs[i].cycles > 0; i++) {
            printf("PROFILE %s %.0f %.2f %.1f\n", g_funcs[i].name, (double)g_funcs[i].cycles / profiled->n,
                   (double)g_funcs[i].calls / profiled->n, 100.0 * (double)g_funcs[i].cycles / (double)total);
        }
    }
    if (profiled != NULL && profiled->n > 0) {
        uint64_t total = 0;
        for (int c = 0; c < CLASS_COUNT; c++) {
            total += g_class_cycles[c];
        }
        for (int c = 0; c < CLASS_COUNT; c++) {
            printf("CLASS %s %.0f %.1f\n", class_names[c], (double)g_class_cycles[c] / profiled->n,
                   total > 0 ? 100.0 * (double)g_class_cycles[c] / (double)total : 0.0);
        }
    }
    if (profiled != NULL && profiled->n > 0) {
        qsort(g_edges, g_nedges, sizeof g_edges[0], edge_cmp_calls);
        for (unsigned i = 0; i < g_nedges; i++) {
            printf("CALLER %s %s %.2f\n", g_edges[i].callee, g_edges[i].caller,
                   (double)g_edges[i].calls / profiled->n);
        }
    }
    if (profiled != NULL && profiled->n > 0 && pc_cycles_path != NULL) {
        FILE *out = fopen(pc_cycles_path, "w");
        if (out == NULL) {
            perror(pc_cycles_path);
            return 2;
        }
        for (uint32_t w = 0; w < FLASH_WORDS; w++) {
            if (g_pc_cycles[w] > 0u) {
                fprintf(out, "0x%05lx %.2f\n", (unsigned long)(w * 2u), (double)g_pc_cycles[w] / profiled->n);
            }
        }
        fclose(out);
    }
    printf("STACK %u\n", (unsigned)(avr->ramend - min_sp));
    uint32_t digest_addr = 0;
    if (elf_symbol(elf_path, "bench_digest_out", &digest_addr)) {
        const uint8_t *d = &avr->data[digest_addr & 0xFFFFu];
        printf("DIGEST 0x%08lx (rotor speeds, thrust, moments of the timed steps)\n",
               (unsigned long)((uint32_t)d[0] | (uint32_t)d[1] << 8 | (uint32_t)d[2] << 16 | (uint32_t)d[3] << 24));
    }
    printf("RESULT 0x%04x after %llu cycles (%s)\n", result, (unsigned long long)avr->cycle,
           state == cpu_Done ? "done" : state == cpu_Crashed ? "crashed" : "cycle limit");
    bool ok = state == cpu_Done && (result & 0x8000u) && phase == 2;
    for (unsigned k = 0; k < g_ntimed; k++) {
        ok = ok && g_timed[k].n > 0; /* every function timed at least once */
    }
    return ok ? 0 : 1;
}

/*
 * insn_count.c - a QEMU TCG plugin (Debian bookworm's qemu-system-arm 7.2,
 * plugin API version 1, declared by hand below: Debian ships no
 * qemu-plugin.h) that counts the guest instructions executed per call of
 * named functions, the way avr_bench times them on the AVR: a call starts
 * when the PC reaches the function's address (the instruction before it, the
 * BL, gives the return address: its address + its size) and ends when the PC
 * reaches that return address. Only calls starting between the PCs `begin`
 * and `end` (the image's bench_timed_begin/bench_timed_end) count.
 *
 * Arguments (-plugin insn_count.so,arg=...,arg=...):
 *   begin=ADDR end=ADDR        the markers (hex, Thumb bit ignored)
 *   fn=NAME@ADDR               a function to count (repeatable)
 *   out=PATH                   where the results go (default: stderr)
 *   profile=NAME               also a flat profile of NAME's counted calls
 *                              (one of the fn= names): per instruction
 *                              address, instructions and estimated cycles
 *                              executed while a call of NAME is under way;
 *                              lines "PCPROF addr insns cycles" (hex addr),
 *                              mapped onto functions by tools/bench.sh,
 *                              and "PERCALL NAME c1 c2 ...": the estimated
 *                              cycles of each of its counted calls, in order
 *   profile_call=N             the PCPROF lines of the N-th counted call only
 *                              (1 = the first; to see what a worst step does)
 * Output lines: "INSNS name min max mean calls", "INSNS_TOTAL n", and
 * "CYCEST name min max mean calls": a cycle estimate from the Cortex-M4
 * instruction timings (ARM DDI 0439B, table 3-1), each instruction costed
 * from its disassembly (m4_cost below), with P = 2 cycles of pipeline refill
 * for a taken branch (the manual gives 1 to 3), and the load/store
 * pipelining of its section 3.3.2 (lsu_cost below): a STR with an immediate
 * offset takes 1 cycle, an LDR 2, or 1 straight after a single LDR whose
 * destination is not in its address. It leaves out: flash wait states and
 * the ART accelerator's misses (the STM32F405 at 168 MHz has 5), the
 * pipelining of FPU loads/stores (VLDR, VSTR counted 2), the IT
 * instruction's folding (counted 1), data-dependent divides (UDIV/SDIV
 * counted 12, their worst case), store-buffer stalls and bus contention.
 * Real cycles: bench-dwt.elf on the chip (DWT->CYCCNT).
 * "CYCEST2 name min max mean calls" is the same estimate with every LDR/STR
 * at 2 cycles (no pipelining), an upper side of the load/store timing.
 * A function reached by a tail call (B, not BL) never sees its return
 * address and reports 0 calls.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the v1 plugin API, the part used here (qemu/qemu-plugin.h of 7.2) ---- */
typedef uint64_t qemu_plugin_id_t;
struct qemu_info_t; /* not looked into */
struct qemu_plugin_tb;
struct qemu_plugin_insn;
enum qemu_plugin_cb_flags { QEMU_PLUGIN_CB_NO_REGS, QEMU_PLUGIN_CB_R_REGS, QEMU_PLUGIN_CB_RW_REGS };
typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id, struct qemu_plugin_tb *tb);
typedef void (*qemu_plugin_vcpu_udata_cb_t)(unsigned int vcpu_index, void *userdata);
typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void *userdata);
void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id, qemu_plugin_vcpu_tb_trans_cb_t cb);
void qemu_plugin_register_vcpu_insn_exec_cb(struct qemu_plugin_insn *insn, qemu_plugin_vcpu_udata_cb_t cb,
                                            enum qemu_plugin_cb_flags flags, void *userdata);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, qemu_plugin_udata_cb_t cb, void *userdata);
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb *tb);
struct qemu_plugin_insn *qemu_plugin_tb_get_insn(const struct qemu_plugin_tb *tb, size_t idx);
uint64_t qemu_plugin_insn_vaddr(const struct qemu_plugin_insn *insn);
size_t qemu_plugin_insn_size(const struct qemu_plugin_insn *insn);
char *qemu_plugin_insn_disas(const struct qemu_plugin_insn *insn); /* malloc'd, capstone syntax */
#define QEMU_PLUGIN_EXPORT __attribute__((visibility("default")))
QEMU_PLUGIN_EXPORT extern int qemu_plugin_version;
QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const struct qemu_info_t *info, int argc,
                                           char **argv);
/* ------------------------------------------------------------------------- */

QEMU_PLUGIN_EXPORT int qemu_plugin_version = 1;

#define MAX_FN 16

typedef struct counted_fn {
    char name[64];
    uint64_t addr;
    bool in_call;
    uint64_t start, ret, cstart;
    uint64_t min, max, sum;
    uint64_t cmin, cmax, csum; /* cycle estimate */
    uint64_t fstart, fmin, fmax, fsum; /* the estimate with LDR/STR at 2 cycles */
    unsigned n;
} counted_fn;

static counted_fn fns[MAX_FN];
static unsigned nfns;
static uint64_t begin_addr = UINT64_MAX, end_addr = UINT64_MAX;
static int phase; /* 0 before begin, 1 timed, 2 after end */
static uint64_t count, prev_next, cycles;
static bool prev_branch;
static uint64_t cycles_flat;    /* the estimate with every LDR/STR at 2 cycles */
static int prev_load_dest = -1; /* register loaded by the previous instruction, a single LDR; -1: none */
#define REFILL 2u /* P: pipeline refill after a taken branch */
static char out_path[512];
static char profile_name[64];
static counted_fn *profiled;
static uint64_t profile_call; /* profile only this call of it (1 = the first counted), 0: all */
/* the estimated cycles of each counted call of the profiled function */
#define PERCALL_MAX 256u
static uint64_t percall[PERCALL_MAX];
static unsigned percall_n;
/* the flat profile: per executed address, open addressing (the image is small) */
#define PCPROF_SLOTS 65536u
typedef struct pc_slot {
    uint64_t pc, insns, cycles;
} pc_slot;
static pc_slot *pcprof;

/* one per translated instruction: its address and the address after it */
typedef struct insn_info {
    uint64_t pc, next;
    uint32_t cost;  /* cycles when it does not branch (an LDR: when not pipelined) */
    uint32_t cost_flat; /* the same with a single LDR/STR at 2 cycles */
    bool branch;    /* may change the flow: a taken one costs REFILL more */
    uint32_t cost_lsu; /* a single LDR/STR's cost by lsu_cost (0: not one) */
    bool load;      /* a single LDR (B/H/SB/SH), not LDRD/LDM, not into pc */
    int8_t dest;    /* a load's destination register */
    int8_t base, index; /* a load's or store's address registers (-1: none) */
} insn_info;

static bool is_cond(const char *c)
{
    static const char *const conds[] = {"eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs",
                                        "vc", "hi", "ls", "ge", "lt", "gt", "le", "al"};
    for (size_t i = 0; i < sizeof conds / sizeof conds[0]; i++) {
        if (!strcmp(c, conds[i])) {
            return true;
        }
    }
    return false;
}

/* registers in the {...} list of the operands (a d register is two words) */
static unsigned reg_list(const char *ops, bool *has_pc)
{
    const char *c = strchr(ops, '{');
    unsigned n = 0;
    *has_pc = false;
    if (c == NULL) {
        return 1;
    }
    for (c++; *c != '\0' && *c != '}'; c++) {
        while (*c == ' ') {
            c++;
        }
        n += *c == 'd' ? 2u : 1u;
        *has_pc = *has_pc || (c[0] == 'p' && c[1] == 'c');
        while (*c != '\0' && *c != ',' && *c != '}') {
            c++;
        }
        if (*c != ',') {
            break;
        }
    }
    return n > 0 ? n : 1;
}

/* r0..r15 of a register name (capstone's: r0..r12, sb, sl, fp, ip, sp, lr, pc); -1 if not one */
static int reg_id(const char *c)
{
    static const char *const alias[] = {"sb", "sl", "fp", "ip", "sp", "lr", "pc"};
    if (c[0] == 'r' && c[1] >= '0' && c[1] <= '9') {
        return c[2] >= '0' && c[2] <= '9' ? 10 * (c[1] - '0') + (c[2] - '0') : c[1] - '0';
    }
    for (int k = 0; k < 7; k++) {
        if (c[0] == alias[k][0] && c[1] == alias[k][1]) {
            return 9 + k;
        }
    }
    return -1;
}

/* The load/store pipelining of ARM DDI 0439B 3.3.2 for the single LDR/STR
 * forms (mnemonic m without its suffix, operands ops): whether it is a load,
 * its destination and address registers, and its cost when not pipelined
 * after a load: a STR with an immediate offset (or none) 1 cycle, with a
 * register offset 2; an LDR 2. Returns 0 for anything else. */
static uint32_t lsu_cost(const char *m, const char *ops, insn_info *ii)
{
    const bool load = !strcmp(m, "ldr") || !strcmp(m, "ldrb") || !strcmp(m, "ldrh") || !strcmp(m, "ldrsb") ||
                      !strcmp(m, "ldrsh");
    const bool store = !strcmp(m, "str") || !strcmp(m, "strb") || !strcmp(m, "strh");
    if (!load && !store) {
        return 0;
    }
    while (*ops == ' ') {
        ops++;
    }
    const int dest = reg_id(ops);
    const char *bracket = strchr(ops, '[');
    if (dest < 0 || dest == 15 || bracket == NULL) {
        return 0; /* a load into pc, or a form not understood: the flat cost */
    }
    const int base = reg_id(bracket + 1);
    const char *comma = strchr(bracket, ',');
    const char *close = strchr(bracket, ']');
    int index = -1;
    if (comma != NULL && close != NULL && comma < close) {
        const char *o = comma + 1;
        while (*o == ' ') {
            o++;
        }
        index = reg_id(o);
    }
    ii->load = load;
    ii->dest = (int8_t)dest;
    ii->base = (int8_t)base;
    ii->index = (int8_t)index;
    return load || index >= 0 ? 2u : 1u;
}

/* Cortex-M4 cycles of one instruction from its disassembly ("mnemonic ops") */
static uint32_t m4_cost(const char *dis, bool *branch, insn_info *ii)
{
    char m[32];
    size_t k = 0;
    while (dis[k] != '\0' && dis[k] != ' ' && k + 1 < sizeof m) {
        m[k] = dis[k];
        k++;
    }
    m[k] = '\0';
    const char *ops = dis + k;
    char *dot = strchr(m, '.'); /* .w, .n, .f32 */
    if (dot != NULL) {
        *dot = '\0';
    }
    const bool pc_dest = strncmp(ops, " pc,", 4) == 0;
    *branch = pc_dest;
    if (!strcmp(m, "b") || !strcmp(m, "bl") || !strcmp(m, "blx") || !strcmp(m, "bx") || !strcmp(m, "cbz") ||
        !strcmp(m, "cbnz") || (m[0] == 'b' && strlen(m) == 3 && is_cond(m + 1))) {
        *branch = true;
        return 1;
    }
    if (!strcmp(m, "tbb") || !strcmp(m, "tbh")) {
        *branch = true;
        return 2;
    }
    bool has_pc = false;
    if (!strcmp(m, "push") || !strcmp(m, "pop") || !strncmp(m, "ldm", 3) || !strncmp(m, "stm", 3) ||
        !strcmp(m, "vpush") || !strcmp(m, "vpop") || !strncmp(m, "vldm", 4) || !strncmp(m, "vstm", 4)) {
        const unsigned n = reg_list(ops, &has_pc);
        *branch = *branch || has_pc;
        return 1u + n;
    }
    if (!strcmp(m, "ldrd") || !strcmp(m, "strd")) {
        return 3;
    }
    if (!*branch) {
        ii->cost_lsu = lsu_cost(m, ops, ii);
    }
    if (!strncmp(m, "ldr", 3) || !strncmp(m, "str", 3) || !strcmp(m, "vldr") || !strcmp(m, "vstr")) {
        return 2;
    }
    if (!strcmp(m, "mla") || !strcmp(m, "mls")) {
        return 2;
    }
    if (!strcmp(m, "sdiv") || !strcmp(m, "udiv")) {
        return 12;
    }
    if (!strcmp(m, "vdiv") || !strcmp(m, "vsqrt")) {
        return 14;
    }
    if (!strcmp(m, "vmla") || !strcmp(m, "vmls") || !strcmp(m, "vnmla") || !strcmp(m, "vnmls") ||
        !strcmp(m, "vfma") || !strcmp(m, "vfms") || !strcmp(m, "vfnma") || !strcmp(m, "vfnms")) {
        return 3;
    }
    if (!strcmp(m, "vmov")) { /* two core registers <-> d or two s: 2 */
        unsigned commas = 0;
        for (const char *c = ops; *c != '\0'; c++) {
            commas += *c == ',';
        }
        return commas >= 2 ? 2 : 1;
    }
    return 1; /* data processing, MUL, (S|U)MULL/MLAL, VADD/VMUL/VCMP/VCVT, IT, ... */
}

static void on_insn(unsigned int vcpu, void *udata)
{
    (void)vcpu;
    const insn_info *ii = udata;
    const uint64_t pc = ii->pc;
    if (prev_branch && pc != prev_next) {
        cycles += REFILL;
    }
    /* an LDR right after a single LDR whose result it does not address with: pipelined, 1 cycle */
    uint32_t cost = ii->cost;
    if (ii->load && prev_load_dest >= 0 && ii->base != prev_load_dest && ii->index != prev_load_dest) {
        cost = 1u;
    }
    if (prev_branch && pc != prev_next) {
        cycles_flat += REFILL;
    }
    if (pc == begin_addr) {
        phase = 1;
    } else if (pc == end_addr) {
        phase = 2;
    }
    for (unsigned k = 0; k < nfns; k++) {
        counted_fn *f = &fns[k];
        if (!f->in_call && pc == f->addr && phase == 1) {
            f->in_call = true;
            f->start = count;
            f->cstart = cycles;
            f->fstart = cycles_flat;
            f->ret = prev_next;
        } else if (f->in_call && pc == f->ret) {
            const uint64_t c = count - f->start;
            f->in_call = false;
            f->min = c < f->min ? c : f->min;
            f->max = c > f->max ? c : f->max;
            f->sum += c;
            const uint64_t cc = cycles - f->cstart;
            f->cmin = cc < f->cmin ? cc : f->cmin;
            f->cmax = cc > f->cmax ? cc : f->cmax;
            f->csum += cc;
            const uint64_t fc = cycles_flat - f->fstart;
            f->fmin = fc < f->fmin ? fc : f->fmin;
            f->fmax = fc > f->fmax ? fc : f->fmax;
            f->fsum += fc;
            f->n++;
            if (f == profiled && percall_n < PERCALL_MAX) {
                percall[percall_n++] = cc;
            }
        }
    }
    if (profiled != NULL && profiled->in_call && (profile_call == 0u || profiled->n + 1u == profile_call)) {
        uint32_t h = (uint32_t)(pc >> 1) & (PCPROF_SLOTS - 1u);
        while (pcprof[h].pc != 0u && pcprof[h].pc != pc + 1u) {
            h = (h + 1u) & (PCPROF_SLOTS - 1u);
        }
        pcprof[h].pc = pc + 1u; /* 0 marks a free slot */
        pcprof[h].insns++;
        /* the refill of a taken branch into pc was charged above, to cycles */
        pcprof[h].cycles += cost + (prev_branch && pc != prev_next ? REFILL : 0u);
    }
    count++;
    cycles += cost;
    cycles_flat += ii->cost_flat;
    prev_next = ii->next;
    prev_branch = ii->branch;
    prev_load_dest = ii->load ? ii->dest : -1;
}

static void on_tb_trans(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    (void)id;
    const size_t n = qemu_plugin_tb_n_insns(tb);
    for (size_t i = 0; i < n; i++) {
        struct qemu_plugin_insn *insn = qemu_plugin_tb_get_insn(tb, i);
        insn_info *ii = malloc(sizeof *ii); /* lives as long as the translation; never freed (a short run) */
        if (ii == NULL) {
            abort();
        }
        ii->pc = qemu_plugin_insn_vaddr(insn);
        ii->next = ii->pc + qemu_plugin_insn_size(insn);
        ii->load = false;
        ii->dest = ii->base = ii->index = -1;
        ii->cost_lsu = 0u;
        char *dis = qemu_plugin_insn_disas(insn);
        ii->cost_flat = m4_cost(dis != NULL ? dis : "", &ii->branch, ii);
        ii->cost = ii->cost_lsu != 0u ? ii->cost_lsu : ii->cost_flat;
        free(dis);
        qemu_plugin_register_vcpu_insn_exec_cb(insn, on_insn, QEMU_PLUGIN_CB_NO_REGS, ii);
    }
}

static void plugin_exit(qemu_plugin_id_t id, void *udata)
{
    (void)id;
    (void)udata;
    FILE *f = out_path[0] != '\0' ? fopen(out_path, "w") : stderr;
    if (f == NULL) {
        f = stderr;
    }
    for (unsigned k = 0; k < nfns; k++) {
        const counted_fn *c = &fns[k];
        fprintf(f, "INSNS %s %llu %llu %.0f %u\n", c->name, (unsigned long long)(c->n ? c->min : 0),
                (unsigned long long)c->max, c->n ? (double)c->sum / c->n : 0.0, c->n);
    }
    for (unsigned k = 0; k < nfns; k++) {
        const counted_fn *c = &fns[k];
        fprintf(f, "CYCEST %s %llu %llu %.0f %u\n", c->name, (unsigned long long)(c->n ? c->cmin : 0),
                (unsigned long long)c->cmax, c->n ? (double)c->csum / c->n : 0.0, c->n);
    }
    for (unsigned k = 0; k < nfns; k++) {
        const counted_fn *c = &fns[k];
        fprintf(f, "CYCEST2 %s %llu %llu %.0f %u\n", c->name, (unsigned long long)(c->n ? c->fmin : 0),
                (unsigned long long)c->fmax, c->n ? (double)c->fsum / c->n : 0.0, c->n);
    }
    fprintf(f, "INSNS_TOTAL %llu\n", (unsigned long long)count);
    if (profiled != NULL) {
        fprintf(f, "PERCALL %s", profiled->name);
        for (unsigned i = 0; i < percall_n; i++) {
            fprintf(f, " %llu", (unsigned long long)percall[i]);
        }
        fprintf(f, "\n");
    }
    for (uint32_t h = 0; pcprof != NULL && h < PCPROF_SLOTS; h++) {
        if (pcprof[h].pc != 0u) {
            fprintf(f, "PCPROF %llx %llu %llu\n", (unsigned long long)(pcprof[h].pc - 1u),
                    (unsigned long long)pcprof[h].insns, (unsigned long long)pcprof[h].cycles);
        }
    }
    if (f != stderr) {
        fclose(f);
    }
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const struct qemu_info_t *info, int argc,
                                           char **argv)
{
    (void)info;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if (!strncmp(a, "begin=", 6)) {
            begin_addr = strtoull(a + 6, NULL, 0) & ~1ull;
        } else if (!strncmp(a, "end=", 4)) {
            end_addr = strtoull(a + 4, NULL, 0) & ~1ull;
        } else if (!strncmp(a, "out=", 4)) {
            snprintf(out_path, sizeof out_path, "%s", a + 4);
        } else if (!strncmp(a, "profile=", 8)) {
            snprintf(profile_name, sizeof profile_name, "%s", a + 8);
        } else if (!strncmp(a, "profile_call=", 13)) {
            profile_call = strtoull(a + 13, NULL, 0);
        } else if (!strncmp(a, "fn=", 3) && nfns < MAX_FN) {
            const char *at = strchr(a + 3, '@');
            if (at == NULL) {
                fprintf(stderr, "insn_count: fn=NAME@ADDR, not %s\n", a);
                return -1;
            }
            counted_fn *f = &fns[nfns++];
            snprintf(f->name, sizeof f->name, "%.*s", (int)(at - (a + 3)), a + 3);
            f->addr = strtoull(at + 1, NULL, 0) & ~1ull;
            f->min = UINT64_MAX;
            f->cmin = UINT64_MAX;
            f->fmin = UINT64_MAX;
        } else {
            fprintf(stderr, "insn_count: unknown argument %s\n", a);
            return -1;
        }
    }
    for (unsigned k = 0; profile_name[0] != '\0' && k < nfns; k++) {
        if (!strcmp(fns[k].name, profile_name)) {
            profiled = &fns[k];
        }
    }
    if (profile_name[0] != '\0') {
        pcprof = profiled != NULL ? calloc(PCPROF_SLOTS, sizeof *pcprof) : NULL;
        if (pcprof == NULL) {
            fprintf(stderr, "insn_count: profile=%s is not a fn= name\n", profile_name);
            return -1;
        }
    }
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_tb_trans);
    qemu_plugin_register_atexit_cb(id, plugin_exit, NULL);
    return 0;
}

/* pil_avr.c - the ATmega2560 image of a PIL run in simavr (pil_avr.h). */
#include "pil_avr.h"

#include <stdio.h>
#include <stdlib.h>

#include "sim_support.h" /* tools/simavr: ELF symbols, the core */

/* AVR data symbols carry this offset in the ELF (the RAM's address space). */
#define AVR_DATA_OFFSET 0x800000u
/* a step that has not reached the next stop after a simulated second is a hang */
#define STEP_CYCLE_LIMIT 16000000u

typedef struct mailbox {
    uint32_t addr;  /* in avr->data */
    unsigned words;
} mailbox;

struct pil_avr {
    elf_firmware_t fw;
    avr_t *avr;
    uint32_t exchange_pc, step_pc; /* byte addresses of pil_exchange, fc_controller_step */
    mailbox params, inputs, out;
    /* the call of fc_controller_step under way: its return address and SP */
    bool in_step;
    uint32_t step_return_pc;
    uint16_t step_sp;
    uint64_t step_start;
    pil_avr_cycles cycles;
    double cycles_sum;
    uint16_t min_sp;
};

static bool find_mailbox(const char *path, const char *name, unsigned words, mailbox *m, char *err, size_t err_len)
{
    uint32_t value = 0, size = 0;
    if (!elf_symbol_sized(path, name, &value, &size) || value < AVR_DATA_OFFSET) {
        snprintf(err, err_len, "%s: no data symbol %s (not a PIL image?)", path, name);
        return false;
    }
    if (size != 4u * words) {
        snprintf(err, err_len, "%s: %s holds %u bytes, the host expects %u words: rebuild both", path, name,
                 (unsigned)size, words);
        return false;
    }
    m->addr = value - AVR_DATA_OFFSET;
    m->words = words;
    return true;
}

/* Little-endian words to and from the image's RAM. */
static void write_words(avr_t *avr, const mailbox *m, const uint32_t *words)
{
    for (unsigned i = 0; i < m->words; i++) {
        for (unsigned b = 0; b < 4u; b++) {
            avr->data[m->addr + 4u * i + b] = (uint8_t)(words[i] >> (8u * b));
        }
    }
}

static void read_words(const avr_t *avr, const mailbox *m, uint32_t *words)
{
    for (unsigned i = 0; i < m->words; i++) {
        uint32_t w = 0;
        for (unsigned b = 0; b < 4u; b++) {
            w |= (uint32_t)avr->data[m->addr + 4u * i + b] << (8u * b);
        }
        words[i] = w;
    }
}

static uint16_t stack_pointer(const avr_t *avr)
{
    return (uint16_t)(avr->data[R_SPL] | (avr->data[R_SPH] << 8));
}

/* Notes the entry into and the return from fc_controller_step at this PC. */
static void time_step(pil_avr *t, uint32_t pc, uint16_t sp)
{
    avr_t *avr = t->avr;
    if (!t->in_step && pc == t->step_pc) {
        uint32_t ret = 0;
        for (int i = 1; i <= avr->address_size; i++) {
            ret = (ret << 8) | avr->data[sp + i];
        }
        t->in_step = true;
        t->step_return_pc = 2u * ret; /* a word address on the stack */
        t->step_sp = sp;
        t->step_start = avr->cycle;
    } else if (t->in_step && pc == t->step_return_pc && sp == t->step_sp + avr->address_size) {
        const uint32_t c = (uint32_t)(avr->cycle - t->step_start);
        pil_avr_cycles *s = &t->cycles;
        t->in_step = false;
        s->min = s->calls == 0 || c < s->min ? c : s->min;
        s->max = c > s->max ? c : s->max;
        s->calls++;
        t->cycles_sum += c;
    }
}

/* Runs the core from where it stands to the next first instruction of pil_exchange. */
static bool run_to_exchange(pil_avr *t, char *err, size_t err_len)
{
    avr_t *avr = t->avr;
    const uint64_t limit = avr->cycle + STEP_CYCLE_LIMIT;
    bool left = avr->pc != t->exchange_pc; /* standing on the stop: step off it first */
    while (avr->cycle < limit) {
        const uint32_t pc = avr->pc;
        const uint16_t sp = stack_pointer(avr);
        if (pc == t->exchange_pc && left) {
            return true;
        }
        left = true;
        t->min_sp = sp < t->min_sp ? sp : t->min_sp;
        time_step(t, pc, sp);
        const int state = avr_run(avr);
        if (state == cpu_Done || state == cpu_Crashed) {
            snprintf(err, err_len, "the ATmega image stopped (%s) at PC 0x%05x",
                     state == cpu_Crashed ? "crashed" : "done", (unsigned)avr->pc);
            return false;
        }
    }
    snprintf(err, err_len, "the ATmega image did not come back within %u cycles", STEP_CYCLE_LIMIT);
    return false;
}

pil_avr *pil_avr_open(const char *elf_path, const uint32_t *params, unsigned param_words, unsigned input_words,
                      uint32_t *out, unsigned output_words, char *err, size_t err_len)
{
    pil_avr *t = calloc(1, sizeof *t);
    if (t == NULL) {
        snprintf(err, err_len, "out of memory");
        return NULL;
    }
    elf_version(EV_CURRENT);
    if (access(elf_path, R_OK) != 0) {
        snprintf(err, err_len, "cannot read the PIL image %s", elf_path);
        free(t);
        return NULL;
    }
    if (!elf_symbol(elf_path, "pil_exchange", &t->exchange_pc) ||
        !elf_symbol(elf_path, "fc_controller_step", &t->step_pc)) {
        snprintf(err, err_len, "%s: no pil_exchange or fc_controller_step (not a PIL image?)", elf_path);
        free(t);
        return NULL;
    }
    if (!find_mailbox(elf_path, "pil_params", param_words, &t->params, err, err_len) ||
        !find_mailbox(elf_path, "pil_inputs", input_words, &t->inputs, err, err_len) ||
        !find_mailbox(elf_path, "pil_out", output_words, &t->out, err, err_len) ||
        !sim_read_atmega2560(elf_path, &t->fw)) {
        if (err[0] == '\0') {
            snprintf(err, err_len, "cannot read %s", elf_path);
        }
        free(t);
        return NULL;
    }
    t->avr = sim_start(&t->fw);
    t->min_sp = 0xFFFFu;
    if (t->avr == NULL) {
        snprintf(err, err_len, "simavr has no atmega2560 core");
        free(t);
        return NULL;
    }
    if (!run_to_exchange(t, err, err_len)) {
        pil_avr_close(t);
        return NULL;
    }
    write_words(t->avr, &t->params, params);
    if (!run_to_exchange(t, err, err_len)) {
        pil_avr_close(t);
        return NULL;
    }
    read_words(t->avr, &t->out, out);
    return t;
}

bool pil_avr_step(pil_avr *t, const uint32_t *inputs, uint32_t *out, char *err, size_t err_len)
{
    write_words(t->avr, &t->inputs, inputs);
    if (!run_to_exchange(t, err, err_len)) {
        return false;
    }
    read_words(t->avr, &t->out, out);
    return true;
}

pil_avr_cycles pil_avr_step_cycles(const pil_avr *t)
{
    pil_avr_cycles c = t->cycles;
    c.mean = c.calls > 0 ? t->cycles_sum / (double)c.calls : 0.0;
    c.stack_peak_bytes = (uint16_t)(t->avr->ramend - t->min_sp);
    return c;
}

void pil_avr_close(pil_avr *t)
{
    if (t != NULL) {
        if (t->avr != NULL) {
            avr_terminate(t->avr);
            free(t->avr);
        }
        free(t);
    }
}

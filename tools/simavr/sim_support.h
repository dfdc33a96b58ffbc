/*
 * sim_support.h - helpers shared by the simavr host programs (avr_loop_test,
 * avr_bench, avr_scalar_test): symbol lookup in the ELF, reading an image,
 * starting a core on it, and the sleep hook that keeps simavr from sleeping
 * in real time. Header-only: each program is one file.
 */
#ifndef FC_ATMEGA_SIM_SUPPORT_H
#define FC_ATMEGA_SIM_SUPPORT_H

#include <fcntl.h>
#include <gelf.h>
#include <libelf.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "sim_avr.h"
#include "sim_elf.h"

/* visit(elf, sym, name, user) for every symbol of the ELF at path, until it
 * returns true (then true: found); false also when the file cannot be read. */
typedef bool (*sim_symbol_fn)(Elf *elf, const GElf_Sym *sym, const char *name, void *user);

static inline bool sim_each_symbol(const char *path, sim_symbol_fn visit, void *user)
{
    bool stopped = false;
    const int fd = open(path, O_RDONLY);
    if (fd < 0) {
        return false;
    }
    Elf *elf = elf_begin(fd, ELF_C_READ, NULL);
    Elf_Scn *scn = NULL;
    while (elf != NULL && !stopped && (scn = elf_nextscn(elf, scn)) != NULL) {
        GElf_Shdr sh;
        if (gelf_getshdr(scn, &sh) == NULL || sh.sh_type != SHT_SYMTAB) {
            continue;
        }
        Elf_Data *data = elf_getdata(scn, NULL);
        const size_t n = sh.sh_entsize ? sh.sh_size / sh.sh_entsize : 0;
        for (size_t i = 0; data != NULL && !stopped && i < n; i++) {
            GElf_Sym sym;
            const char *name = gelf_getsym(data, (int)i, &sym) != NULL ? elf_strptr(elf, sh.sh_link, sym.st_name)
                                                                         : NULL;
            stopped = name != NULL && visit(elf, &sym, name, user);
        }
    }
    if (elf != NULL) {
        elf_end(elf);
    }
    close(fd);
    return stopped;
}

typedef struct sim_symbol_query {
    const char *name;
    uint32_t value, size;
} sim_symbol_query;

static inline bool sim_symbol_named(Elf *elf, const GElf_Sym *sym, const char *name, void *user)
{
    (void)elf;
    sim_symbol_query *q = user;
    if (strcmp(name, q->name) != 0) {
        return false;
    }
    q->value = (uint32_t)sym->st_value;
    q->size = (uint32_t)sym->st_size;
    return true;
}

/* The value and size of symbol name in the ELF at path. */
static inline bool elf_symbol_sized(const char *path, const char *name, uint32_t *value, uint32_t *size)
{
    sim_symbol_query q = {name, 0u, 0u};
    if (!sim_each_symbol(path, sim_symbol_named, &q)) {
        return false;
    }
    *value = q.value;
    *size = q.size;
    return true;
}

/* The value of symbol name in the ELF at path. */
static inline bool elf_symbol(const char *path, const char *name, uint32_t *value)
{
    uint32_t size = 0;
    return elf_symbol_sized(path, name, value, &size);
}

/* visit(name, address, size, user) for every code symbol of the ELF at path:
 * C functions, and the untyped global labels of libgcc's assembly routines
 * (__mulsidi3, __udivmod64, ...: no type and size 0, in an executable
 * section). For the profilers of avr_loop_test and avr_bench. */
typedef void (*sim_code_symbol_fn)(const char *name, uint32_t addr, uint32_t size, void *user);

typedef struct sim_code_visit {
    sim_code_symbol_fn visit;
    void *user;
} sim_code_visit;

static inline bool sim_code_symbol(Elf *elf, const GElf_Sym *sym, const char *name, void *user)
{
    const sim_code_visit *v = user;
    if (sym->st_shndx == SHN_UNDEF || sym->st_shndx >= SHN_LORESERVE || name[0] == '\0') {
        return false;
    }
    const int type = GELF_ST_TYPE(sym->st_info);
    bool code = type == STT_FUNC;
    if (!code && type == STT_NOTYPE && GELF_ST_BIND(sym->st_info) != STB_LOCAL) {
        Elf_Scn *in = elf_getscn(elf, sym->st_shndx);
        GElf_Shdr ish;
        code = in != NULL && gelf_getshdr(in, &ish) != NULL && (ish.sh_flags & SHF_EXECINSTR) != 0;
    }
    if (code) {
        v->visit(name, (uint32_t)sym->st_value, (uint32_t)sym->st_size, v->user);
    }
    return false; /* every symbol */
}

static inline bool sim_code_symbols(const char *path, sim_code_symbol_fn visit, void *user)
{
    if (access(path, R_OK) != 0) {
        return false;
    }
    sim_code_visit v = {visit, user};
    (void)sim_each_symbol(path, sim_code_symbol, &v);
    return true;
}

/* simavr's raw mode sleeps in real time while the AVR sleeps: not here */
static void no_sleep(avr_t *avr, avr_cycle_count_t how_long)
{
    (void)avr;
    (void)how_long;
}

/* The ELF at path as an ATmega2560 image at 16 MHz (the bench and test images
 * carry no .mmcu section). False, said on stderr, if it cannot be read. */
static inline bool sim_read_atmega2560(const char *path, elf_firmware_t *fw)
{
    if (elf_read_firmware(path, fw) != 0) {
        fprintf(stderr, "cannot read %s\n", path);
        return false;
    }
    snprintf(fw->mmcu, sizeof fw->mmcu, "%s", "atmega2560");
    fw->frequency = 16000000u;
    return true;
}

/* A core of fw's MCU with fw loaded, at its frequency, errors only logged and
 * no real-time sleep; NULL, said on stderr, if simavr has no such core. */
static inline avr_t *sim_start(elf_firmware_t *fw)
{
    avr_t *avr = avr_make_mcu_by_name(fw->mmcu);
    if (avr == NULL) {
        fprintf(stderr, "simavr has no core %s\n", fw->mmcu);
        return NULL;
    }
    avr_init(avr);
    avr->log = LOG_ERROR;
    avr_load_firmware(avr, fw);
    avr->frequency = fw->frequency;
    avr->sleep = no_sleep;
    return avr;
}

/* The ATmega2560 image at path read into *fw (which must outlive the core)
 * and started (sim_read_atmega2560, sim_start); NULL, said on stderr, if
 * either fails. */
static inline avr_t *sim_load_atmega2560(const char *path, elf_firmware_t *fw)
{
    return sim_read_atmega2560(path, fw) ? sim_start(fw) : NULL;
}

/* A function timed from outside by its addresses: a call runs from the PC
 * reaching its entry to the PC reaching the return address the CALL pushed,
 * with the stack pointer back to where it was at the entry (so a recursive
 * or nested return elsewhere does not end it). */
typedef struct sim_call_timer {
    uint32_t addr;  /* the entry, byte address */
    bool in_call;
    uint64_t start; /* the cycle of the entry */
    uint32_t ret;   /* the return address, byte address */
    uint16_t sp;    /* the stack pointer at the entry */
} sim_call_timer;

/* t at the instruction at pc (stack pointer sp) about to run: a call starts
 * (if may_start) or ends there. Returns the cycles of a call that ends at
 * this instruction, or -1. */
static inline int64_t sim_call_timer_at(sim_call_timer *t, const avr_t *avr, uint32_t pc, uint16_t sp,
                                        bool may_start)
{
    if (!t->in_call && pc == t->addr && may_start) {
        /* the CALL pushed the return address (words), high byte lowest */
        uint32_t ret = 0;
        for (int i = 1; i <= avr->address_size; i++) {
            ret = (ret << 8) | avr->data[sp + i];
        }
        t->in_call = true;
        t->start = avr->cycle;
        t->ret = ret * 2u;
        t->sp = sp;
    } else if (t->in_call && pc == t->ret && sp == t->sp + avr->address_size) {
        t->in_call = false;
        return (int64_t)(avr->cycle - t->start);
    }
    return -1;
}

#endif /* FC_ATMEGA_SIM_SUPPORT_H */

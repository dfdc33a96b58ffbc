/*
 * scalar_test_host.c - avr_scalar_test: runs the image of scalar_test_avr.c
 * in simavr (atmega2560, 16 MHz) until it sleeps with interrupts off and
 * reads its counts from RAM. Exit status 0 when the image finished, ran at
 * least --min-cases comparisons and none failed.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_support.h"

static uint32_t read_u32(const avr_t *avr, uint32_t addr)
{
    const uint32_t a = addr & 0xFFFFu;
    return (uint32_t)avr->data[a] | ((uint32_t)avr->data[a + 1] << 8) | ((uint32_t)avr->data[a + 2] << 16) |
           ((uint32_t)avr->data[a + 3] << 24);
}

int main(int argc, char **argv)
{
    const char *elf_path = NULL;
    unsigned long min_cases = 1;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--elf")) {
            elf_path = argv[i + 1];
        } else if (!strcmp(argv[i], "--min-cases")) {
            min_cases = strtoul(argv[i + 1], NULL, 10);
        }
    }
    if (elf_path == NULL) {
        fprintf(stderr, "usage: avr_scalar_test --elf FILE [--min-cases N]\n");
        return 2;
    }
    elf_version(EV_CURRENT);
    uint32_t cases_addr = 0, failures_addr = 0, done_addr = 0, first_addr = 0;
    if (!elf_symbol(elf_path, "scalar_test_cases", &cases_addr) ||
        !elf_symbol(elf_path, "scalar_test_failures", &failures_addr) ||
        !elf_symbol(elf_path, "scalar_test_done", &done_addr) ||
        !elf_symbol(elf_path, "scalar_test_first", &first_addr)) {
        fprintf(stderr, "%s: not a scalar test image\n", elf_path);
        return 2;
    }
    static elf_firmware_t fw;
    avr_t *avr = sim_load_atmega2560(elf_path, &fw);
    if (avr == NULL) {
        return 2;
    }
    int state = cpu_Running;
    const uint64_t limit = 16000000ull * 3600u; /* an hour of simulated time */
    while (avr->cycle < limit) {
        state = avr_run(avr);
        if (state == cpu_Done || state == cpu_Crashed) {
            break;
        }
    }
    const uint32_t cases = read_u32(avr, cases_addr);
    const uint32_t failures = read_u32(avr, failures_addr);
    const bool done = avr->data[done_addr & 0xFFFFu] == 1u;
    printf("SCALAR cases %lu failures %lu (%s, %.1f s simulated)\n", (unsigned long)cases, (unsigned long)failures,
           done ? "done" : state == cpu_Crashed ? "crashed" : "did not finish",
           (double)avr->cycle / (double)avr->frequency);
    if (failures != 0u) {
        printf("first failure: op %ld shift %ld got %ld expected %ld\n", (long)(int32_t)read_u32(avr, first_addr),
               (long)(int32_t)read_u32(avr, first_addr + 4), (long)(int32_t)read_u32(avr, first_addr + 8),
               (long)(int32_t)read_u32(avr, first_addr + 12));
    }
    return done && failures == 0u && cases >= min_cases ? 0 : 1;
}

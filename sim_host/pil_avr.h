/*
 * pil_avr.h - the ATmega2560 side of a processor-in-the-loop run: an image
 * built from platform/atmega/pil/pil_main.c, run in simavr (libsimavr), and
 * stopped at each call of its pil_exchange() to swap the mailboxes'
 * words (tools/pil/pil_wire.h says what the words are). Knows
 * nothing of the firmware's types: words in, words out, and the cycles the
 * image spent in each call of fc_controller_step.
 */
#ifndef SIM_PIL_AVR_H
#define SIM_PIL_AVR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct pil_avr pil_avr;

/* The cycles of the calls of fc_controller_step so far. */
typedef struct pil_avr_cycles {
    unsigned long calls;
    uint32_t min, max;
    double mean;
    uint16_t stack_peak_bytes; /* RAMEND - the lowest SP seen */
} pil_avr_cycles;

/* Loads the image at elf_path, checks that its mailboxes pil_params,
 * pil_inputs and pil_out hold the given numbers of words, runs it to its
 * first stop, writes params, runs it to the second and reads out (the init
 * result). NULL, with err set, if any of that fails. */
pil_avr *pil_avr_open(const char *elf_path, const uint32_t *params, unsigned param_words, unsigned input_words,
                      uint32_t *out, unsigned output_words, char *err, size_t err_len);

/* One step: writes inputs, runs the image to its next stop, reads out.
 * false (err set) if the core crashed or did not stop within a second of
 * simulated time. */
bool pil_avr_step(pil_avr *t, const uint32_t *inputs, uint32_t *out, char *err, size_t err_len);

pil_avr_cycles pil_avr_step_cycles(const pil_avr *t);

void pil_avr_close(pil_avr *t);

#endif /* SIM_PIL_AVR_H */

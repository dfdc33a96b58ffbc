/*
 * pil_main.c - the ATmega2560 image of a processor-in-the-loop (PIL) run:
 * the library as built for the ATmega (the preset's libfc.a), stepped by the
 * SIL plant on the host through three mailboxes in RAM (pil_wire.h).
 *
 * The host (fc-sil --numeric pil, sim_host/pil_avr.c) runs this image in
 * simavr and stops it whenever the PC reaches pil_exchange():
 *   1st stop: the host has nothing to read; it writes pil_params;
 *   2nd stop: it reads the init result from pil_out[0];
 *   then every step: it writes pil_inputs, lets the image run one step to
 *   the next stop, and reads pil_out (status, outputs, loop internals).
 * Everything between two stops is the image's own code on the simulated
 * core: the controller runs with the ATmega's arithmetic, cycle by cycle.
 * The flight image (main.c) gets its inputs from its HALs instead; the
 * controller calls are the same three of fc/controller.h.
 */
#include <stdint.h>

#include "fc/controller.h"
#include "pil_wire.h"

/* the mailboxes: found by the host through their symbols (and sizes) */
uint32_t pil_params[PIL_PARAM_WORDS];
uint32_t pil_inputs[PIL_INPUT_WORDS];
uint32_t pil_out[PIL_OUTPUT_WORDS];

static fc_controller s_ctl;
static fc_controller_params s_params;
static fc_controller_inputs s_in;
static fc_controller_outputs s_out;

/* The host stops the core at this function's first instruction and reads or
 * writes the mailboxes; the memory clobber makes the compiler reload them. */
void pil_exchange(void) __attribute__((noinline));
void pil_exchange(void)
{
    __asm__ volatile("" ::: "memory");
}

int main(void)
{
    pil_exchange(); /* the host writes pil_params */
    uint32_t airframe = 0u, variant = 0u;
    pil_wire wire = {pil_params, PIL_PARAM_WORDS, 0u, false};
    const bool params_ok = pil_wire_params(&wire, &airframe, &variant, &s_params) &&
                           airframe < (uint32_t)FC_AIRFRAME_COUNT && variant < (uint32_t)FC_ALT_VARIANT_COUNT;
    pil_out[0] = params_ok ? (uint32_t)fc_controller_init(&s_ctl, &s_params) : UINT32_MAX;
    for (;;) {
        pil_exchange(); /* the host reads pil_out, writes pil_inputs */
        wire = (pil_wire){pil_inputs, PIL_INPUT_WORDS, 0u, false};
        (void)pil_wire_inputs(&wire, &s_in);
        uint32_t status = fc_controller_step(&s_ctl, &s_in, &s_out);
        pil_internals internals = pil_internals_of(&s_ctl);
        wire = (pil_wire){pil_out, PIL_OUTPUT_WORDS, 0u, true};
        (void)pil_wire_outputs(&wire, &status, &s_out, &internals);
    }
}

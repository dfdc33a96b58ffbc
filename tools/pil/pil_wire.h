/*
 * pil_wire.h - what crosses between the SIL plant on the host and the ATmega
 * image in simavr in a processor-in-the-loop (PIL) run: the controller's
 * parameters once, then every step its inputs one way and its outputs the
 * other, as arrays of 32-bit words in three mailboxes of the image's RAM.
 *
 * Why words and not the structs: the two sides lay the same struct out
 * differently (on the ATmega int and enums are 16 bits, bool and uint8_t pack
 * without padding), so each field is carried as one word, in the order of the
 * one listing per struct in pil_wire.c, which both sides compile. An fc_real
 * travels as its 32 bits, so the fixed backend's values arrive unchanged
 * (both targets are little-endian, and simavr's RAM is read byte by byte).
 *
 * The parameters: the image calls fc_controller_default_params itself and
 * then takes the fields the SIL may override (fsw_adapter.c) from the wire,
 * so a field overridden there must be listed in pil_wire.c too.
 */
#ifndef PIL_WIRE_H
#define PIL_WIRE_H

#include <stdbool.h>
#include <stdint.h>

#include "fc/controller.h"

#define PIL_PARAM_WORDS 37u
#define PIL_INPUT_WORDS 29u
#define PIL_OUTPUT_WORDS (FC_MAX_ROTORS + 69u)

/* A mailbox being written (to the wire) or read (from it), one word at a time. */
typedef struct pil_wire {
    uint32_t *word;
    unsigned size;    /* words */
    unsigned at;      /* the next word */
    bool writing;     /* true: values -> words; false: words -> values */
} pil_wire;

/* The controller state the SIL's trace shows beside the outputs. */
typedef struct pil_internals {
    fc_vec3 attitude_error_rad;      /* ANGLE */
    fc_vec3 attitude_integral_rad_s; /* ANGLE */
    fc_vec3 position_integral_mps2;  /* ACCEL */
    fc_vec3 accel_feedback_mps2;     /* ACCEL: I_a of the position loop (2.11) */
} pil_internals;

/* One listing per message, used in both directions: with w->writing the
 * fields are copied to the words, else from them. Each returns false if the
 * mailbox does not hold exactly the listing's words (the two builds disagree). */
bool pil_wire_params(pil_wire *w, uint32_t *airframe, uint32_t *variant, fc_controller_params *p);
bool pil_wire_inputs(pil_wire *w, fc_controller_inputs *in);
bool pil_wire_outputs(pil_wire *w, uint32_t *status, fc_controller_outputs *out, pil_internals *internals);

/* The internals of a running controller. */
pil_internals pil_internals_of(const fc_controller *ctl);

#endif /* PIL_WIRE_H */

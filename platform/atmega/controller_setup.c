/*
 * controller_setup.c - the ATmega image's controller parameters
 * (controller_setup.h).
 */
#include "controller_setup.h"

#ifndef FC_ATMEGA_AIRFRAME
#define FC_ATMEGA_AIRFRAME FC_AIRFRAME_F450 /* the hexa: FC_AIRFRAME_HEXA_4KG */
#endif
#ifndef FC_ATMEGA_ALTITUDE_VARIANT
#define FC_ATMEGA_ALTITUDE_VARIANT FC_ALT_VARIANT_SSC_ADAPTIVE
#endif

/* The outer group's major frame in loops (fc_controller_set_outer_divider):
 * each of its parts (position loop, pad model, the pad model's work ahead)
 * in its own minor frame, so that no loop carries two of them. */
#ifndef FC_ATMEGA_OUTER_DIVIDER
#define FC_ATMEGA_OUTER_DIVIDER 2
#endif
#if FC_ATMEGA_OUTER_DIVIDER < 1 || FC_ATMEGA_OUTER_DIVIDER > 10
#error "FC_ATMEGA_OUTER_DIVIDER must be in [1, FC_OUTER_DIVIDER_MAX]"
#endif

void fc_atmega_params(fc_controller_params *p)
{
    fc_controller_default_params(p, FC_ATMEGA_AIRFRAME, FC_ATMEGA_ALTITUDE_VARIANT,
                                 FC_C(1.0f / (float)FC_ATMEGA_LOOP_HZ, DT));
    fc_controller_set_outer_divider(p, FC_ATMEGA_OUTER_DIVIDER);
}

/*
 * controller_setup.h - the ATmega image's controller parameters: the build's
 * airframe, altitude law, loop rate and outer frame (CMakeLists.txt sets
 * them), in one place for the two images that run fc_controller_init on
 * them: the snapshot image (snapshot/snapshot_avr.c), whose initialised
 * controller the flight images copy from flash at boot, and the flight
 * image itself in a build without simavr (main.c).
 */
#ifndef FC_ATMEGA_CONTROLLER_SETUP_H
#define FC_ATMEGA_CONTROLLER_SETUP_H

#include "fc/controller.h"

/* Loop rate: what the worst iteration measured in simavr allows. */
#ifndef FC_ATMEGA_LOOP_HZ
#define FC_ATMEGA_LOOP_HZ 100
#endif

/* p: the parameters fc_controller_init takes for this build. */
void fc_atmega_params(fc_controller_params *p);

#endif /* FC_ATMEGA_CONTROLLER_SETUP_H */

/*
 * controller_snapshot.h - the ATmega flight image's controller as
 * fc_controller_init leaves it for this build's parameters
 * (controller_setup.h), computed at build time: avr_snapshot
 * (tools/simavr/snapshot_host.c) runs the snapshot image
 * (snapshot/snapshot_avr.c) in simavr and writes its fc_controller's bytes
 * as this array in flash (controller_snapshot.c in the build directory). An
 * init that fails stops the build there, so the flight image never holds a
 * controller that did not initialise. fc_controller holds no pointers: the
 * bytes are valid at any address.
 */
#ifndef FC_ATMEGA_CONTROLLER_SNAPSHOT_H
#define FC_ATMEGA_CONTROLLER_SNAPSHOT_H

#include <avr/pgmspace.h>
#include <stdint.h>

/* Records, one after the other until they fill sizeof(fc_controller) bytes
 * (the generated source asserts it): a count of zero bytes to skip, a count
 * n, then the next n bytes of the controller. Most of an initialised
 * controller is zero (states, integrators, histories), so the records are
 * much shorter than the controller. */
extern const uint8_t fc_atmega_controller_snapshot[] PROGMEM;

#endif /* FC_ATMEGA_CONTROLLER_SNAPSHOT_H */

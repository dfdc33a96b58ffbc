/*
 * snapshot_avr.c - fc-atmega-snapshot.elf: runs fc_controller_init on the
 * flight image's parameters (controller_setup.h: the same airframe, altitude
 * law, loop rate and outer frame, the same library build) and stops (cli;
 * sleep) with the controller and the init's result in RAM. avr_snapshot
 * (tools/simavr/snapshot_host.c) runs it in simavr and writes the
 * controller's bytes into the flight images (controller_snapshot.h).
 *
 * FC_SNAPSHOT_SPOILED=1 (fc-atmega-snapshot-spoiled.elf, a test image only)
 * empties the altitude law's thrust range, a parameter fc_controller_init
 * refuses, so that atmega.snapshot_refused sees avr_snapshot refuse an init
 * that failed.
 */
#include <avr/interrupt.h>
#include <avr/sleep.h>
#include <stdint.h>

#include "controller_setup.h"

#ifndef FC_SNAPSHOT_SPOILED
#define FC_SNAPSHOT_SPOILED 0
#endif

/* read by avr_snapshot through the ELF's symbols */
fc_controller fc_snapshot_controller;
volatile uint8_t fc_snapshot_result;
volatile uint8_t fc_snapshot_done;

int main(void)
{
    fc_controller_params p;
    fc_atmega_params(&p);
#if FC_SNAPSHOT_SPOILED
    p.altitude.thrust_max_n = p.altitude.thrust_min_n;
#endif
    fc_snapshot_result = (uint8_t)fc_controller_init(&fc_snapshot_controller, &p);
    fc_snapshot_done = 1u;
    cli();
    sleep_enable();
    for (;;) {
        sleep_cpu();
    }
}

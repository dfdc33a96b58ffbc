/*
 * bench_avr.c - the ATmega2560 benchmark image: bench_run.h's workload
 * (fc_controller_init, warm-up, fixed input vectors between the markers),
 * then sleep with interrupts off, which ends the simavr run. Timed from
 * outside by avr_bench (bench_host.c). No I/O: the result is in
 * bench_result (read by the host from RAM).
 */
#include <avr/interrupt.h>
#include <avr/sleep.h>
#include <stdint.h>

#include "bench_run.h"

volatile uint16_t bench_result; /* 0x8000 | status bits when done; 0x4000 on init failure */
volatile uint32_t bench_digest_out; /* bench_run.h's digest of the outputs, read by the host too */

int main(void)
{
    uint16_t status = 0;
    const uint16_t result = bench_run(&status) == 0 ? (uint16_t)(0x8000u | status) : 0x4000u;
    bench_digest_out = bench_digest;
    bench_result = result;
    cli();
    set_sleep_mode(SLEEP_MODE_PWR_DOWN);
    sleep_enable();
    for (;;) {
        sleep_cpu();
    }
}

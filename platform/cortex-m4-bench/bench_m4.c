/*
 * bench_m4.c - the Cortex-M4F benchmark image (STM32F405: Crazyflie 2.x, or
 * QEMU's netduinoplus2): bench_run.h's workload (the same fixed input vectors
 * as the ATmega bench), then the result over semihosting (newlib's rdimon)
 * and exit. Counted from outside by the QEMU plugin insn_count.c, by symbol,
 * between the markers bench_timed_begin and bench_timed_end.
 *
 * BENCH_DWT=1: the image also times each fc_controller_step with DWT->CYCCNT
 * and prints min/max cycles: real cycles on the chip (a Crazyflie with a
 * debugger attached for semihosting). Under QEMU CYCCNT reads 0.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#ifndef BENCH_DWT
#define BENCH_DWT 0
#endif

#if BENCH_DWT
#define DEMCR (*(volatile uint32_t *)0xE000EDFCu)
#define DWT_CTRL (*(volatile uint32_t *)0xE0001000u)
#define DWT_CYCCNT (*(volatile uint32_t *)0xE0001004u)
static uint32_t bench_dwt_t0, bench_dwt_min = UINT32_MAX, bench_dwt_max;
#define BENCH_STEP_BEFORE() (bench_dwt_t0 = DWT_CYCCNT)
#define BENCH_STEP_AFTER()                                                                                        \
    do {                                                                                                          \
        const uint32_t c_ = DWT_CYCCNT - bench_dwt_t0;                                                            \
        bench_dwt_min = c_ < bench_dwt_min ? c_ : bench_dwt_min;                                                  \
        bench_dwt_max = c_ > bench_dwt_max ? c_ : bench_dwt_max;                                                  \
    } while (0)
#endif

#include "bench_run.h"

extern void initialise_monitor_handles(void);
int main(void);
void reset_handler(void);
void default_handler(void);
void _init(void);
void _fini(void);

/* -nostartfiles: newlib's exit() calls _fini (no destructors here) */
void _init(void)
{
}
void _fini(void)
{
}

extern uint32_t _data_load, _data_start, _data_end, _bss_start, _bss_end, _stack_top, end;

/* Stack peak: the free RAM between the static data and the stack is painted
 * at reset; after the benchmark, the lowest word no longer painted gives the
 * deepest the stack went (init and steps; before any heap use by printf). */
#define STACK_PAINT 0xA5C3E1F7u
static uint32_t stack_peak_bytes(void)
{
    const uint32_t *w = &end;
    while (w < &_stack_top && *w == STACK_PAINT) {
        w++;
    }
    return (uint32_t)((uintptr_t)&_stack_top - (uintptr_t)w);
}

void default_handler(void)
{
    exit(3);
}

void reset_handler(void)
{
    /* FPU: CP10 and CP11 full access (the float build uses it) */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    for (uint32_t *s = &_data_load, *d = &_data_start; d < &_data_end;) {
        *d++ = *s++;
    }
    for (uint32_t *d = &_bss_start; d < &_bss_end;) {
        *d++ = 0;
    }
    uint32_t *sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    for (uint32_t *d = &end; d < sp - 16;) { /* clear of this frame */
        *d++ = STACK_PAINT;
    }
    exit(main());
}

/* initial SP, reset, then NMI .. SysTick */
__attribute__((section(".isr_vector"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&_stack_top, reset_handler, default_handler, default_handler,
    default_handler, default_handler, default_handler, 0, 0, 0, 0, default_handler, default_handler, 0,
    default_handler, default_handler,
};

int main(void)
{
    initialise_monitor_handles();
#if BENCH_DWT
    DEMCR |= 1u << 24; /* TRCENA */
    DWT_CYCCNT = 0;
    DWT_CTRL |= 1u;    /* CYCCNTENA */
#endif
    uint16_t status = 0;
    const int rc = bench_run(&status);
    const uint32_t peak = stack_peak_bytes();
    printf("bench_m4 (%s): %s, step status bits 0x%04x\n", FC_NUMERIC_FIXED ? "fixed" : "float",
           rc == 0 ? "done" : "fc_controller_init failed", (unsigned)status);
    printf("STACK %lu\n", (unsigned long)peak);
    printf("DIGEST 0x%08lx (rotor speeds, thrust, moments of the timed steps)\n", (unsigned long)bench_digest);
#if BENCH_DWT
    printf("DWT fc_controller_step %lu %lu cycles min max\n", (unsigned long)bench_dwt_min,
           (unsigned long)bench_dwt_max);
#endif
    return rc;
}

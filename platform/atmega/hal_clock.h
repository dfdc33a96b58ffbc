/*
 * hal_clock.h - a 32-bit cycle counter: Timer3 free-running at prescaler 1
 * (one count per CPU cycle, 62.5 ns at 16 MHz) with an overflow interrupt that
 * extends it to 32 bits (wraps after 268 s; differences of unsigned values
 * are right across the wrap). Used to time the loop, the controller step and
 * the TWI timeouts.
 */
#ifndef FC_ATMEGA_HAL_CLOCK_H
#define FC_ATMEGA_HAL_CLOCK_H

#include <avr/io.h>
#include <stdint.h>

/* high 16 bits, counted by TIMER3_OVF_vect */
extern volatile uint16_t hal_clock_high;

void hal_clock_init(void);

/* Cycles since hal_clock_init. Safe with interrupts on or off (an overflow
 * that is pending but not yet counted is accounted for); about 25 cycles. */
static inline uint32_t hal_clock_cycles(void)
{
    const uint8_t sreg = SREG;
    __asm__ __volatile__("cli" ::: "memory");
    const uint16_t low = TCNT3;
    uint16_t high = hal_clock_high;
    if ((TIFR3 & _BV(TOV3)) != 0u && low < 0x8000u) {
        high++; /* wrapped after the ISR last ran, before this read */
    }
    SREG = sreg;
    return ((uint32_t)high << 16) | low;
}

#endif /* FC_ATMEGA_HAL_CLOCK_H */

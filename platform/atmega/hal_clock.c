/* hal_clock.c - Timer3 as a 32-bit cycle counter (hal_clock.h). */
#include "hal_clock.h"

#include <avr/interrupt.h>

volatile uint16_t hal_clock_high;

ISR(TIMER3_OVF_vect)
{
    hal_clock_high++;
}

void hal_clock_init(void)
{
    TCCR3A = 0u;               /* normal mode, outputs disconnected */
    TCCR3B = 0u;
    TCNT3 = 0u;
    hal_clock_high = 0u;
    TIFR3 = _BV(TOV3);         /* clear a stale overflow flag */
    TIMSK3 = _BV(TOIE3);
    TCCR3B = _BV(CS30);        /* clk/1 */
}

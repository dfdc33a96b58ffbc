/* hal_esc.c - ESC PWM on Timer4/Timer5 (hal_esc.h). */
#include "hal_esc.h"

#include <avr/io.h>

#define TICKS_PER_US 2u /* 16 MHz / 8 */
#define PWM_TOP ((uint16_t)(F_CPU / 8UL / HAL_ESC_RATE_HZ - 1UL)) /* 4999 */

/* Fast PWM, non-inverting: the output is high for OCR + 1 ticks. */
static uint16_t us_to_ocr(uint16_t us)
{
    if (us < HAL_ESC_US_OFF) {
        us = HAL_ESC_US_OFF;
    } else if (us > HAL_ESC_US_MAX) {
        us = HAL_ESC_US_MAX;
    }
    return (uint16_t)(us * TICKS_PER_US - 1u);
}

void hal_esc_write_us(uint8_t ch, uint16_t us)
{
    const uint16_t ocr = us_to_ocr(us);
    switch (ch) {
    case 0: OCR4A = ocr; break;
    case 1: OCR4B = ocr; break;
    case 2: OCR4C = ocr; break;
    case 3: OCR5A = ocr; break;
    case 4: OCR5B = ocr; break;
    case 5: OCR5C = ocr; break;
    default: break;
    }
}

void hal_esc_all_off(void)
{
    for (uint8_t ch = 0u; ch < HAL_ESC_CHANNELS; ch++) {
        hal_esc_write_us(ch, HAL_ESC_US_OFF);
    }
}

void hal_esc_init(void)
{
    /* stop, configure, preload "off", then enable the pins */
    TCCR4B = 0u;
    TCCR5B = 0u;
    ICR4 = PWM_TOP;
    ICR5 = PWM_TOP;
    TCNT4 = 0u;
    TCNT5 = 0u;
    hal_esc_all_off();
    /* WGM 14 (1110): WGMn1 in A, WGMn3:2 in B; COMnA/B/C1 = clear on match, set at BOTTOM */
    TCCR4A = _BV(COM4A1) | _BV(COM4B1) | _BV(COM4C1) | _BV(WGM41);
    TCCR5A = _BV(COM5A1) | _BV(COM5B1) | _BV(COM5C1) | _BV(WGM51);
    DDRH |= _BV(PH3) | _BV(PH4) | _BV(PH5);
    DDRL |= _BV(PL3) | _BV(PL4) | _BV(PL5);
    TCCR4B = _BV(WGM43) | _BV(WGM42) | _BV(CS41); /* clk/8 */
    TCCR5B = _BV(WGM53) | _BV(WGM52) | _BV(CS51);
}
